#!/usr/bin/python3
"""The lambda_crit(a) curve printed by bench_lambda_crit_curve, drawn with the scan's phase-diagram plotter.

  bench/lambda_crit_plot.py OUTPUT.png LOG [LOG ...]

Reads the Markdown rows `| a | lambda_crit | N | lambda_crit(N/2) | change | bracket | omega | ...` of the
bench's output (one or more logs; rows marked NOT CONVERGED are left out), writes them as the scan's
lambda_crit.csv (validation/scan/scan_output.cpp: size = N/2, lambda_crit = its value, lambda_crit_2N = the
value at N, change_2N = the relative change, error = the Brent bracket) in a temporary folder, and calls
validation/scan/plot_scan.py with an empty scan.csv: the curve with error bars bracket + change, log lambda.
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COLUMNS = ["a", "lambda_crit", "lambda_crit_error", "method", "lambda_sustained", "lambda_relaxing", "period", "N",
           "lambda_crit_2N", "change_2N", "note"]


def rows_from(log):
    rows = []
    with open(log) as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) < 10 or not cells[0] or cells[0] in ("a",) or cells[0].startswith("-"):
                continue
            try:
                a, lam, n, lam_half, change, bracket, omega = (float(c) for c in cells[:7])
            except ValueError:
                continue
            if "NOT CONVERGED" in line or lam_half <= 0:
                continue
            rows.append({"a": a, "lambda_crit": lam_half, "lambda_crit_error": bracket, "method": "hopf, N doubled",
                         "lambda_sustained": "nan", "lambda_relaxing": "nan",
                         "period": 2 * math.pi / omega if omega > 0 else "nan", "N": int(n) // 2,
                         "lambda_crit_2N": lam, "change_2N": change, "note": ""})
    return rows


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    output = sys.argv[1]
    rows = sorted((r for log in sys.argv[2:] for r in rows_from(log)), key=lambda r: r["a"])
    if not rows:
        print("no converged rows in " + " ".join(sys.argv[2:]), file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as folder:
        crit = os.path.join(folder, "lambda_crit.csv")
        with open(crit, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=COLUMNS)
            w.writeheader()
            w.writerows(rows)
        scan = os.path.join(folder, "scan.csv")
        with open(scan, "w") as f:
            f.write("a,lambda,regime,converged\n")
        return subprocess.call(["/usr/bin/python3", os.path.join(ROOT, "validation", "scan", "plot_scan.py"), "--scan",
                                scan, "--lambda-crit", crit, "--output", os.path.abspath(output), "--log-lambda",
                                "--title", "lambda_crit(a), brownian kernel, converged in N (bench_lambda_crit_curve)"])

if __name__ == "__main__":
    sys.exit(main())
