#!/usr/bin/env python3
"""Plots the series of an `aggkit run` (one panel per observable, every engine overlaid) and, if any were
written, the size distributions n_k (log-log). Called by the harness (validation/harness/plot.cpp):

  plot_series.py --output FILE.png --title NAME [--reference LABEL]
                 --series LABEL series.csv [--series ...] [--distribution LABEL distribution.csv ...]
                 [--absolute-tolerance LABEL ATOL EXPONENT FLOOR ...]

A deterministic integrator resolves n_k only down to its absolute tolerance atol_k = max(ATOL k^-EXPONENT,
FLOOR): values below it (the far tail at early times, round-off of either sign) are not drawn, and the region
below atol_k is shaded as unresolved.

Values are drawn on a log axis where they are positive and span more than a factor 30; times too, unless
the output times are (nearly) evenly spaced, as from `every`, where a linear axis keeps oscillations legible.
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker as ticker  # noqa: E402

# Drawing cost. The plot runs after every `aggkit run`, so it is laid out by hand: fixed margins in inches
# instead of figure.tight_layout() (which measures every tick label of every panel, ~0.6 s for the README
# example), titles at a fixed height (an automatic title position measures the tick labels again) and
# decade labels on log axes in plain text with Unicode superscripts (10⁻⁵) instead of mathtext, whose
# parser cost ~0.2 s per figure. The content is unchanged: same panels, curves, masks and shading.
SUPERSCRIPTS = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def read_csv(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    if not rows:
        raise ValueError(f"{path} is empty")
    header, body = rows[0], rows[1:]
    columns = {name: [float(row[i]) for row in body] for i, name in enumerate(header)}
    return header, columns


def wide_positive(values):
    """True if all values are finite and positive and span more than a factor 30 (log scale helps)."""
    finite = [v for v in values if math.isfinite(v)]
    if not finite or min(finite) <= 0:
        return False
    return max(finite) / min(finite) > 30.0


def geometric(times):
    """True if the times are spaced roughly geometrically (median ratio of neighbours above 1.1)."""
    ratios = sorted(b / a for a, b in zip(times, times[1:]) if a > 0)
    return bool(ratios) and ratios[len(ratios) // 2] > 1.1


def style(label, reference, points):
    if label == reference:
        return dict(color="black", linewidth=2.5, alpha=0.5, label=f"{label} (reference)")
    markers = dict(marker=".", markersize=3) if points <= 200 else {}
    return dict(linewidth=1.2, label=label, **markers)


def decade_label(value, _position=None):
    """'10⁻⁵' at a power of ten, '' elsewhere (a log axis's major ticks sit on decades)."""
    exponent = math.log10(value) if value > 0 else 0.5
    return "10" + str(round(exponent)).translate(SUPERSCRIPTS) if abs(exponent - round(exponent)) < 1e-9 else ""


def label_log_axes(axes):
    """Decade labels on log axes; no minor ticks where more than 6 decades make them a solid comb (each
    tick is an object to build and draw: ~130 of them on a 16-decade distribution axis)."""
    for axis, limits in ((axes.xaxis, axes.get_xlim()), (axes.yaxis, axes.get_ylim())):
        if axis.get_scale() == "log":
            axis.set_major_formatter(ticker.FuncFormatter(decade_label))
            axis.set_minor_formatter(ticker.NullFormatter())
            low, high = sorted(limits)
            if low > 0 and math.log10(high / low) > 6:
                axis.set_minor_locator(ticker.NullLocator())


def plot_series(axes, observable, engines, reference):
    everything_t, everything_y = [], []
    for label, (_, columns) in engines.items():
        t, y = columns["t"], columns[observable]
        lines = axes.plot(t, y, **style(label, reference, len(t)))
        if observable + "_stderr" in columns:  # an ensemble engine: shade ±2 standard errors
            error = columns[observable + "_stderr"]
            axes.fill_between(t, [a - 2 * e for a, e in zip(y, error)], [a + 2 * e for a, e in zip(y, error)],
                              color=lines[0].get_color(), alpha=0.25, linewidth=0)
        everything_t += t
        everything_y += y
    times = sorted(set(everything_t))
    if wide_positive(times) and geometric(times):
        axes.set_xscale("log")
    if wide_positive(everything_y):
        axes.set_yscale("log")
    axes.set_title(observable, y=1.0)
    axes.set_xlabel("t")
    axes.grid(True, which="major", alpha=0.3)
    axes.legend(fontsize="small")


def absolute_tolerance(tolerance, k):
    """atol_k of an engine's tolerance (atol, exponent, floor), or 0 where none was given."""
    if tolerance is None:
        return 0.0
    atol, exponent, floor = tolerance
    return max(atol * k ** -exponent, floor)


def plot_distributions(axes, distributions, reference, tolerances):
    times = sorted({t for _, columns in distributions.values() for t in columns["t"]})
    colours = plt.cm.viridis([i / max(1, len(times) - 1) for i in range(len(times))])
    dashes = ["-", "--", ":", "-."]
    lowest, largest_k = math.inf, 1
    for e, (label, (_, columns)) in enumerate(distributions.items()):
        tolerance = tolerances.get(label)
        for colour, time in zip(colours, times):
            # Below atol_k the integrator does not resolve n_k: those values are left out (masked), not drawn
            # as a jagged tail of round-off.
            points = [(k, n) for t, k, n in zip(columns["t"], columns["k"], columns["n"])
                      if t == time and n > 0 and n >= absolute_tolerance(tolerance, k)]
            if not points:
                continue
            k, n = zip(*points)
            lowest, largest_k = min(lowest, min(n)), max(largest_k, max(columns["k"]))
            axes.plot(k, n, linestyle=dashes[e % len(dashes)], color=colour,
                      linewidth=2.0 if label == reference else 1.0, label=f"{label}, t = {time:g}")
    axes.set_xscale("log")
    axes.set_yscale("log")
    shaded = [(label, tolerances[label]) for label in distributions if label in tolerances]
    if shaded and math.isfinite(lowest):
        bottom = lowest / 10.0
        k = sorted(set([1.0] + [math.exp(math.log(largest_k) * i / 400.0) for i in range(401)]))
        for label, tolerance in shaded:
            atol_k = [max(absolute_tolerance(tolerance, x), bottom) for x in k]
            axes.fill_between(k, bottom, atol_k, color="grey", alpha=0.2, linewidth=0,
                              label=f"below atol_k ({label}): unresolved")
        axes.set_ylim(bottom=bottom)
    axes.set_title("size distribution", y=1.0)
    axes.set_xlabel("k")
    axes.set_ylabel("n_k")
    axes.grid(True, which="major", alpha=0.3)
    axes.legend(fontsize="x-small")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--output", required=True)
    parser.add_argument("--title", default="")
    parser.add_argument("--reference", default=None)
    parser.add_argument("--series", nargs=2, action="append", metavar=("LABEL", "CSV"), required=True)
    parser.add_argument("--distribution", nargs=2, action="append", metavar=("LABEL", "CSV"), default=[])
    parser.add_argument("--absolute-tolerance", nargs=4, action="append", default=[],
                        metavar=("LABEL", "ATOL", "EXPONENT", "FLOOR"))
    args = parser.parse_args()

    engines = {label: read_csv(path) for label, path in args.series}
    distributions = {label: read_csv(path) for label, path in args.distribution}
    tolerances = {label: (float(atol), float(exponent), float(floor))
                  for label, atol, exponent, floor in args.absolute_tolerance}
    observables = [name for name in next(iter(engines.values()))[0][1:] if not name.endswith("_stderr")]
    panels = len(observables) + (1 if distributions else 0)
    columns = min(3, panels)
    rows = math.ceil(panels / columns)
    figure, grid = plt.subplots(rows, columns, figsize=(5.0 * columns, 3.8 * rows), squeeze=False)
    cells = [cell for row in grid for cell in row]
    for axes, observable in zip(cells, observables):
        plot_series(axes, observable, engines, args.reference)
    if distributions:
        plot_distributions(cells[len(observables)], distributions, args.reference, tolerances)
    for axes in cells[panels:]:
        axes.set_visible(False)
    for axes in cells[:panels]:
        label_log_axes(axes)
    figure.suptitle(args.title)
    # Margins in inches (tick labels left and below, titles above; see "Drawing cost" above).
    width, height = figure.get_size_inches()
    figure.subplots_adjust(left=0.85 / width, right=1 - 0.2 / width, bottom=0.55 / height, top=1 - 0.75 / height,
                           wspace=0.9 * columns / width, hspace=0.95 * rows / height)
    figure.savefig(args.output, format="png", dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
