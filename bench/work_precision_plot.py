#!/usr/bin/env python3
"""Work-precision diagrams from the runs bench/scipy_vs_aggkit.py recorded: for each case, wall time against the
largest relative error of M0, M2, M3 at t = 1, 10, 100, one line per method (aggkit's CVODE BDF, Adams, ARKODE's
explicit Runge–Kutta, auto; scipy's DOP853, LSODA, BDF), each point labelled with its rtol. Only the latest run
of the CSV (each case's last date) is drawn; scipy runs stopped by the time limit are drawn at the limit with an arrow.

  /usr/bin/python3 bench/work_precision_plot.py [--csv build/bench/scipy_vs_aggkit_runs.csv] [--out bench/work_precision]
      [--since DATE]

writes OUT_<case>.png.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {"aggkit": "-", "scipy": "--"}
TITLES = {
    "ballistic": "ballistic kernel, λ = 0.01, N = 2000, cutoff (scipy: numpy direct sums)",
    "constant": "constant kernel, λ = 0.1, N = 32768 (scipy: fftconvolve; 'direct': np.convolve, estimated)",
}


def latest_runs(path, since=None):
    """The rows of each case's latest run (the cases may come from separate invocations), or every row since
    `since` (concurrent invocations of one case)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if since:
        return [r for r in rows if r["date"] >= since]
    last = {}
    for r in rows:
        last[r["case"]] = max(last.get(r["case"], ""), r["date"])
    return [r for r in rows if r["date"] == last[r["case"]]]


def draw(case, rows, out):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for code, method in sorted({(r["code"], r["method"]) for r in rows}):
        runs = sorted((r for r in rows if (r["code"], r["method"]) == (code, method)), key=lambda r: float(r["rtol"]))
        done = [r for r in runs if not math.isnan(float(r["error"]))]
        if done:
            line, = ax.loglog([float(r["error"]) for r in done], [float(r["seconds"]) for r in done], STYLE[code],
                              marker="o", label=f"{code} {method}")
            for r in done:
                ax.annotate(f"{float(r['rtol']):.0e}", (float(r["error"]), float(r["seconds"])), fontsize=7,
                            xytext=(3, 3), textcoords="offset points", color=line.get_color())
        for r in runs:
            if math.isnan(float(r["error"])):
                ax.annotate(f"{code} {method} rtol {float(r['rtol']):.0e}: {r['note']}", (0.02, 0.02 + 0.04 * runs.index(r)),
                            xycoords="axes fraction", fontsize=7)
    ax.set_xlabel("largest relative error of M0, M2, M3 at t = 1, 10, 100")
    ax.set_ylabel("wall time [s]")
    ax.set_title(TITLES.get(case, case), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{out}_{case}.png", dpi=110)
    print(f"wrote {out}_{case}.png")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--csv", default=os.path.join(here, "build", "bench", "scipy_vs_aggkit_runs.csv"))
    parser.add_argument("--out", default=os.path.join(here, "bench", "work_precision"))
    parser.add_argument("--since", metavar="DATE", help="draw every run recorded since DATE (UTC), not only the latest")
    args = parser.parse_args()
    rows = latest_runs(args.csv, args.since)
    for case in sorted({r["case"] for r in rows}):
        draw(case, [r for r in rows if r["case"] == case], args.out)


if __name__ == "__main__":
    main()
