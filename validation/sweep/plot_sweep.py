#!/usr/bin/env python3
"""One column of an aggkit sweep drawn from sweep_mean.csv: a heat map of its mean over the first two swept
keys (a panel per value of any further keys), or its mean with standard-error bars against a single key.
Called by `aggkit sweep`; runs with Debian's python3-matplotlib."""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def ordered(values):
    """Distinct values (or tuples of values: the panels' keys) in numeric order when they are all numbers, else in
    order of appearance."""
    distinct = list(dict.fromkeys(values))

    def numbers(v):
        return tuple(number(x) for x in v) if isinstance(v, tuple) else (number(v),)

    if all(not any(math.isnan(x) for x in numbers(v)) for v in distinct):
        distinct.sort(key=numbers)
    return distinct


class KeyAction(argparse.Action):
    """--key K and --log-key K, in the order given (the sweep's key order); --log-key draws K on a log axis."""

    def __call__(self, parser, namespace, value, option_string=None):
        keys = getattr(namespace, "keys", None) or []
        keys.append((value, option_string == "--log-key"))
        setattr(namespace, "keys", keys)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mean", required=True)
    parser.add_argument("--column", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--title", default="sweep")
    parser.add_argument("--key", "--log-key", action=KeyAction, dest="keys", default=[])
    args = parser.parse_args()
    keys = [k for k, _ in args.keys]
    log = {k for k, is_log in args.keys if is_log}
    if not keys:
        raise SystemExit("at least one --key")

    with open(args.mean, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or args.column not in rows[0]:
        raise SystemExit("no column %s in %s" % (args.column, args.mean))
    err = args.column + "_stderr"

    if len(keys) == 1:
        key = keys[0]
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        xs = [number(r[key]) for r in rows]
        ys = [number(r[args.column]) for r in rows]
        es = [number(r[err]) for r in rows]
        es = [0.0 if math.isnan(e) else e for e in es]
        ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3)
        if key in log:
            ax.set_xscale("log")
        ax.set_xlabel(key)
        ax.set_ylabel(args.column + " (mean ± standard error)")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_title(args.title)
        fig.tight_layout()
        fig.savefig(args.output, dpi=120, format="png")
        return

    kx, ky = keys[0], keys[1]
    rest = keys[2:]
    xs, ys = ordered([r[kx] for r in rows]), ordered([r[ky] for r in rows])
    groups = ordered([tuple(r[k] for k in rest) for r in rows]) if rest else [()]
    groups = groups[:12]
    cols = min(len(groups), 3)
    lines = (len(groups) + cols - 1) // cols
    fig, axes = plt.subplots(lines, cols, figsize=(1.2 + 4.8 * cols, 0.8 + 4.0 * lines), squeeze=False)
    finite = [number(r[args.column]) for r in rows if not math.isnan(number(r[args.column]))]
    low, high = (min(finite), max(finite)) if finite else (0.0, 1.0)
    image = None
    for g, group in enumerate(groups):
        ax = axes[g // cols][g % cols]
        grid = [[math.nan] * len(xs) for _ in ys]
        for r in rows:
            if tuple(r[k] for k in rest) != group:
                continue
            grid[ys.index(r[ky])][xs.index(r[kx])] = number(r[args.column])
        image = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis", vmin=low, vmax=high)
        for j in range(len(ys)):
            for i in range(len(xs)):
                if not math.isnan(grid[j][i]):
                    ax.text(i, j, "%.3g" % grid[j][i], ha="center", va="center", fontsize=7, color="white")
        ax.set_xticks(range(len(xs)))
        ax.set_xticklabels(["%.3g" % number(x) if not math.isnan(number(x)) else x for x in xs], rotation=45, fontsize=8)
        ax.set_yticks(range(len(ys)))
        ax.set_yticklabels(["%.3g" % number(y) if not math.isnan(number(y)) else y for y in ys], fontsize=8)
        ax.set_xlabel(kx + (" (log spaced)" if kx in log else ""))
        ax.set_ylabel(ky + (" (log spaced)" if ky in log else ""))
        if rest:
            ax.set_title(", ".join("%s = %s" % (k, v) for k, v in zip(rest, group)), fontsize=9)
    for g in range(len(groups), lines * cols):
        axes[g // cols][g % cols].axis("off")
    fig.colorbar(image, ax=axes, label=args.column + " (mean)")
    fig.suptitle(args.title)
    fig.savefig(args.output, dpi=120, format="png", bbox_inches="tight")  # keep the axis labels whole


if __name__ == "__main__":
    main()
