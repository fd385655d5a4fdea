#!/usr/bin/env python3
"""How loose the low-rank kernel factorisation may be for a given rtol: one lever on the kinetic solvers' speed.

The ballistic kernel K = (i^1/3 + j^1/3)^2 sqrt(1/i + 1/j) has no exact factorisation; the fast right-hand side
uses a low-rank cross approximation whose relative error is `lowrank_tolerance` (default: rtol clamped to
[1e-12, 1e-6]). Its rank, and with it each right-hand side's FFT work, falls as the tolerance loosens. This bench
runs the README case (λ = 0.01, N = 2000, cutoff, monodisperse start; M0, M2, M3 at t = 1, 10, 100 against
bdf-gmres at rtol 1e-12) with lowrank_tolerance = f · rtol for each factor f, each method and each rtol, the
factors interleaved and repeated so that load affects them alike, and prints per run the kernel rank, the
achieved kernel error, the median CPU seconds and the error, and the CPU ratio against f = 1.

  PYTHONPATH=build/python /usr/bin/python3 bench/lowrank_tolerance.py [--methods auto erk bdf-gmres]
      [--rtol 1e-6 1e-8 1e-10] [--factors 1 10 100] [--repeats 3]

An rtol is honoured where the error stays at or below 10 rtol (the tolerance tests' bound).
"""
import argparse
import statistics
import time

import numpy as np

import aggkit

TIMES = np.array([1.0, 10.0, 100.0])


def model():
    return aggkit.Model("ballistic", lam=0.01, size=2000, truncation="cutoff")


def moments(solution):
    return np.array([solution.moment(0), solution.moment(2), solution.moment(3)]).T


def run(method, rtol, lowrank):
    started = time.process_time()
    solution = aggkit.integrate(model(), TIMES, rtol=rtol, method=method, lowrank_tolerance=lowrank)
    return moments(solution), time.process_time() - started, solution.statistics


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--methods", nargs="+", default=["auto", "erk", "bdf-gmres"])
    parser.add_argument("--rtol", nargs="+", type=float, default=[1e-6, 1e-8, 1e-10])
    parser.add_argument("--factors", nargs="+", type=float, default=[1.0, 10.0, 100.0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    reference = moments(aggkit.integrate(model(), TIMES, rtol=1e-12, method="bdf-gmres"))
    print(f"{'method':>10} {'rtol':>7} {'factor':>6} {'rank':>4} {'kernel err':>10} {'cpu s':>7} {'error':>9} "
          f"{'err/rtol':>8} {'cpu/f=1':>7}", flush=True)
    for method in args.methods:
        for rtol in args.rtol:
            cpu = {f: [] for f in args.factors}
            last = {}
            for _ in range(args.repeats):
                for f in args.factors:
                    lowrank = min(f * rtol, 0.09)
                    m, seconds, stats = run(method, rtol, lowrank)
                    cpu[f].append(seconds)
                    last[f] = (m, stats)
            base = statistics.median(cpu[args.factors[0]])
            for f in args.factors:
                m, stats = last[f]
                err = float(np.max(np.abs(m / reference - 1.0)))
                median = statistics.median(cpu[f])
                print(f"{method:>10} {rtol:7.0e} {f:6g} {stats['kernel_rank']:4d} {stats['kernel_relative_error']:10.2e} "
                      f"{median:7.3f} {err:9.2e} {err / rtol:8.2f} {median / base:7.3f}", flush=True)


if __name__ == "__main__":
    main()
