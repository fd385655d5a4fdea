#!/usr/bin/env python3
"""Phase diagram of an aggkit scan: the regime of every (a, lambda) point (scan.csv) and the lambda_crit(a)
curve with its error bars (lambda_crit.csv: bracket plus the N -> 2N change). Called by `aggkit scan`; runs with Debian's python3-matplotlib."""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "sustained": dict(color="tab:red", marker="o", label="sustained"),
    "damped": dict(color="tab:blue", marker="s", label="damped"),
    "steady": dict(color="tab:green", marker="^", label="steady"),
    "irregular": dict(color="tab:gray", marker="x", label="irregular"),
    # Relaxing in the run, but its grid or run length does not resolve it (linear stability says unstable,
    # or the decay did not converge): neither damped nor sustained.
    "unresolved": dict(color="tab:orange", marker="D", label="unresolved"),
    # Verdicts from the steady state's spectrum (the `verdict` column): an unstable steady state whose cycle the
    # run did not show, and points below where the continuation's roots stay positive.
    "unstable": dict(color="tab:purple", marker="v", label="unstable steady state (no attracting cycle found)"),
    "no-positive-steady-state": dict(color="black", marker="x", label="no positive steady state on the grid"),
    # Below the curve where the cycle continued down the column outgrows the grid's largest size N.
    "not-representable": dict(color="tab:brown", marker="*", label="cycle outgrows the grid (needs a larger N)"),
    # A stable steady state and, at the same point, the cycle continued down its column settled too.
    "bistable": dict(color="tab:olive", marker="P", label="bistable: stable steady state and an attracting cycle"),
}


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--scan", required=True)
    parser.add_argument("--lambda-crit", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--bifurcation", help="also draw the bifurcation diagram per a to this PNG")
    parser.add_argument("--title", default="scan")
    parser.add_argument("--log-lambda", action="store_true")
    args = parser.parse_args()

    with open(args.scan, newline="") as f:
        points = list(csv.DictReader(f))
    with open(args.lambda_crit, newline="") as f:
        crit = list(csv.DictReader(f))

    fig, ax = plt.subplots(figsize=(9, 7))
    # The verdict from the spectrum where the scan has one (marker filled where the time series confirms it,
    # hollow where it does not or says nothing); else the time series' regime (hollow: not converged).
    by_verdict = bool(points) and "verdict" in points[0]
    key = "verdict" if by_verdict else "regime"
    def period(p):  # the computed cycle's period where there is one, else the run's
        value = number(p.get("cycle_period", "") or "nan")
        return value if value > 0 else number(p["period"])

    periods = [period(p) for p in points if p[key] == "sustained" and period(p) > 0]
    norm = matplotlib.colors.LogNorm(min(periods), max(periods)) if len(periods) >= 2 and min(periods) < max(periods) else None
    for regime, style in STYLE.items():
        for confirmed in (True, False):
            chosen = [p for p in points if p[key] == regime and
                      ((p["agree"] == "yes") if by_verdict else (p["converged"] == "yes")) == confirmed]
            if not chosen:
                continue
            label = style["label"] + ("" if confirmed else " (not confirmed by the run)" if by_verdict else " (not converged)")
            x = [number(p["a"]) for p in chosen]
            y = [number(p["lambda"]) for p in chosen]
            if regime == "sustained" and norm is not None:
                # Sustained points coloured by their period (log scale).
                colours = [plt.cm.viridis(norm(period(p))) if period(p) > 0 else "tab:red" for p in chosen]
                ax.scatter(x, y, s=34, marker=style["marker"], label=label, edgecolors="tab:red", linewidths=1.2,
                           facecolors=colours if confirmed else "none")
            elif style["marker"] == "x":  # an unfilled marker: drawn in its line colour
                ax.scatter(x, y, s=28, marker="x", label=label, color=style["color"], linewidths=1.0)
            else:
                ax.scatter(x, y, s=28, marker=style["marker"], label=label, edgecolors=style["color"],
                           facecolors=style["color"] if confirmed else "none")
    if norm is not None:
        bar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, pad=0.01, fraction=0.04)
        bar.set_label("period of sustained points")
    rows = [r for r in crit if not math.isnan(number(r["lambda_crit"]))]
    if rows:
        a = [number(r["a"]) for r in rows]
        lc = [number(r["lambda_crit"]) for r in rows]
        # Error bar: the bracket of the estimate plus, where lambda_crit was also found at 2N, the change
        # N -> 2N (the truncation error; change_2N is relative).
        err = []
        for r, value in zip(rows, lc):
            bracket, change = number(r["lambda_crit_error"]), number(r.get("change_2N", ""))
            err.append((0.0 if math.isnan(bracket) else bracket) + (0.0 if math.isnan(change) else change * value))
            for key in ("change_2K", "change_half_ratio"):  # the graded grid's refinements, where present
                extra = number(r.get(key, "") or "nan")
                if not math.isnan(extra):
                    err[-1] += extra * value
        method = rows[0]["method"]
        ax.errorbar(a, lc, yerr=err, color="black", lw=1.5, capsize=3,
                    label="lambda_crit(a) (%s)" % method)
    if args.log_lambda:
        ax.set_yscale("log")
    ax.set_xlabel("a  (kernel (i/j)^a + (j/i)^a)")
    ax.set_ylabel("lambda (shattering rate)")
    ax.set_title(args.title)
    # Below the axes: the colour bar of the periods takes the right-hand side.
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, borderaxespad=0.0)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120, format="png")
    if args.bifurcation:
        bifurcation_diagram(points, crit, args)


def bifurcation_diagram(points, crit, args):
    """Per a: the steady state's M0 against lambda (solid and filled where stable, hollow where unstable), the
    cycles' M0 range (min and max; filled where the cycle is stable, hollow where not) and the Hopf point."""
    by_a = {}
    for p in points:
        by_a.setdefault(number(p["a"]), []).append(p)
    hopf = {number(r["a"]): number(r["lambda_crit"]) for r in crit}
    values = sorted(by_a)
    columns = min(4, len(values))
    rows = (len(values) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(3.2 * columns, 2.6 * rows), squeeze=False)
    for ax, a in zip(axes.flat, values):
        chosen = sorted(by_a[a], key=lambda p: number(p["lambda"]))
        lam = [number(p["lambda"]) for p in chosen]
        steady = [number(p.get("mean_steady", "nan")) for p in chosen]
        stable = [p.get("regime_stability") in ("damped", "steady") for p in chosen]
        ax.plot(lam, steady, color="gray", lw=0.8)
        ax.scatter([x for x, s in zip(lam, stable) if s], [y for y, s in zip(steady, stable) if s], s=12,
                   color="tab:blue", label="steady state, stable")
        ax.scatter([x for x, s in zip(lam, stable) if not s], [y for y, s in zip(steady, stable) if not s], s=12,
                   facecolors="none", edgecolors="tab:blue", label="steady state, unstable")
        for key in ("cycle_m0_min", "cycle_m0_max"):
            for stable_cycle in (True, False):
                pts = [(number(p["lambda"]), number(p.get(key, "nan") or "nan")) for p in chosen
                       if (p.get("cycle_stable") == "yes") == stable_cycle and p.get("cycle_stable")]
                if pts:
                    ax.scatter(*zip(*pts), s=14, marker="^" if key.endswith("max") else "v", color="tab:red",
                               facecolors="tab:red" if stable_cycle else "none",
                               label=("cycle M0 range, stable" if stable_cycle else "cycle M0 range, unstable")
                               if key.endswith("max") else None)
        if a in hopf and hopf[a] > 0:
            ax.axvline(hopf[a], color="black", lw=0.8, ls="--", label="lambda_crit")
        if args.log_lambda:
            ax.set_xscale("log")
        if any(y > 0 for y in steady) or any(p.get("cycle_stable") for p in chosen):
            ax.set_yscale("log")
        ax.set_title("a = %g" % a, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(values):]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("lambda", fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel("M0", fontsize=8)
    fig.suptitle(args.title + ": bifurcation diagrams", fontsize=10)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(args.bifurcation, dpi=110, format="png")


if __name__ == "__main__":
    main()
