#!/usr/bin/python3
# Plots the output of bench_ed_fractal (fractal dimension of the final aggregate against the volume
# fraction): /usr/bin/python3 bench/ed_fractal_plot.py bench/ed_fractal_n1e4.txt bench/ed_fractal.png
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = [l.split() for l in open(sys.argv[1]) if l.strip() and not l.startswith("#") and not l.split()[0] == "nu"]
nu = [float(r[0]) for r in rows]
dm, em = [float(r[1]) for r in rows], [max(float(r[2]), float(r[3])) for r in rows]
db = [float(r[4]) for r in rows]
plt.figure(figsize=(6, 4))
plt.errorbar(nu, dm, yerr=em, marker="o", label="mass–radius")
plt.plot([n for n, d in zip(nu, db) if d == d], [d for d in db if d == d], "s--", label="box counting (where it fits)")
plt.xscale("log")
plt.xlabel("volume fraction ν")
plt.ylabel("fractal dimension of the final aggregate")
plt.title("ED, 2-D, reflecting walls, N = 10^4")
plt.grid(True, which="both", alpha=0.3)
plt.legend()
plt.tight_layout()
plt.savefig(sys.argv[2], dpi=100)
