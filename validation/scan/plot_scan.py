#!/usr/bin/env python3
"""Phase diagram of an aggkit scan: the regime of every (a, lambda) point (scan.csv) and the lambda_crit(a)
curve with its error bars (lambda_crit.csv: bracket plus the N -> 2N change). Called by `aggkit scan`; runs with Debian's python3-matplotlib."""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "sustained": dict(color="tab:red", marker="o", label="sustained"),
    "damped": dict(color="tab:blue", marker="s", label="damped"),
    "steady": dict(color="tab:green", marker="^", label="steady"),
    "irregular": dict(color="tab:gray", marker="x", label="irregular"),
    # Relaxing in the run, but its grid or run length does not resolve it (linear stability says unstable,
    # or the decay did not converge): neither damped nor sustained.
    "unresolved": dict(color="tab:orange", marker="D", label="unresolved (run or grid too short)"),
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
    parser.add_argument("--title", default="scan")
    parser.add_argument("--log-lambda", action="store_true")
    args = parser.parse_args()

    with open(args.scan, newline="") as f:
        points = list(csv.DictReader(f))
    with open(args.lambda_crit, newline="") as f:
        crit = list(csv.DictReader(f))

    fig, ax = plt.subplots(figsize=(9, 5))
    for regime, style in STYLE.items():
        for converged in (True, False):
            # Tentative verdicts (the classifier's convergence check failed) are drawn hollow.
            chosen = [p for p in points if p["regime"] == regime and (p["converged"] == "yes") == converged]
            if not chosen:
                continue
            label = style["label"] if converged else style["label"] + " (not converged)"
            ax.scatter([number(p["a"]) for p in chosen], [number(p["lambda"]) for p in chosen], s=28,
                       marker=style["marker"], label=label, edgecolors=style["color"],
                       facecolors=style["color"] if converged else "none")
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
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120, format="png")


if __name__ == "__main__":
    main()
