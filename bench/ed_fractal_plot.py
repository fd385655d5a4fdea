#!/usr/bin/python3
# Plots the output of bench_ed_fractal (fractal dimension of the final aggregate against the volume
# fraction): /usr/bin/python3 bench/ed_fractal_plot.py bench/results/ed_fractal_n1e5.txt bench/results/ed_fractal.png
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

lines = open(sys.argv[1]).read().splitlines()
rows = [l.split() for l in lines if l.strip() and not l.startswith("#") and not l.split()[0] == "nu"]
count = next((l.split()[2].rstrip(",") for l in lines if l.startswith("# N ")), "?")
nu = [float(r[0]) for r in rows]
dm, em = [float(r[1]) for r in rows], [max(float(r[2]), float(r[3])) for r in rows]
db = [float(r[4]) for r in rows]
plt.figure(figsize=(6, 4))
plt.errorbar(nu, dm, yerr=em, marker="o", label="mass–radius")
eb = [float(r[5]) for r in rows]
fits = [(n, d, e) for n, d, e in zip(nu, db, eb) if d == d]
plt.errorbar([f[0] for f in fits], [f[1] for f in fits], yerr=[f[2] for f in fits], marker="s", linestyle="--",
             label="box counting")
plt.xscale("log")
plt.xlabel("volume fraction ν")
plt.ylabel("fractal dimension of the final aggregate")
plt.title(f"ED, 2-D, reflecting walls, N = {count}")
plt.grid(True, which="both", alpha=0.3)
plt.legend()
plt.tight_layout()
plt.savefig(sys.argv[2], dpi=100)
