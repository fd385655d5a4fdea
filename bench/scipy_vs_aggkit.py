#!/usr/bin/env python3
"""Work-precision of aggkit against the peer a user would write (bench/peers/scipy_direct.py: scipy DOP853
with numpy direct sums), same problem, same run: ballistic kernel, λ = 0.01, N = 2000, cutoff, monodisperse,
M0, M2, M3 at t = 1, 10, 100. Errors are the largest relative error over those nine numbers against an
aggkit run at rtol 1e-12 (checked against the tightest scipy run, printed). Runs alternate between the two
codes so that machine load affects both alike.

  PYTHONPATH=build/python /usr/bin/python3 bench/scipy_vs_aggkit.py [--scipy-rtol 1e-8 ...] [--aggkit-rtol 1e-6 ...]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "peers"))
import scipy_direct  # noqa: E402
import aggkit  # noqa: E402

SIZE, LAM, TIMES = 2000, 0.01, (1.0, 10.0, 100.0)


def aggkit_run(rtol):
    started = time.perf_counter()
    model = aggkit.Model("ballistic", lam=LAM, size=SIZE, truncation="cutoff")
    solution = aggkit.integrate(model, np.array(TIMES), rtol=rtol)
    moments = np.array([solution.moment(0), solution.moment(2), solution.moment(3)]).T
    return moments, time.perf_counter() - started


def error(moments, reference):
    return float(np.max(np.abs(moments / reference - 1.0)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scipy-rtol", type=float, nargs="+", default=[1e-8])
    parser.add_argument("--aggkit-rtol", type=float, nargs="+", default=[1e-6, 1e-8, 1e-10])
    args = parser.parse_args()
    reference, reference_seconds = aggkit_run(1e-12)
    print(f"reference: aggkit rtol 1e-12, {reference_seconds:.2f} s", flush=True)
    rows = []
    for i in range(max(len(args.scipy_rtol), len(args.aggkit_rtol))):
        if i < len(args.aggkit_rtol):
            moments, seconds = aggkit_run(args.aggkit_rtol[i])
            rows.append(("aggkit bdf-gmres", args.aggkit_rtol[i], seconds, error(moments, reference)))
            print("%-18s rtol %-8g %9.2f s  max rel. error %.2e" % rows[-1], flush=True)
        if i < len(args.scipy_rtol):
            moments, seconds, evaluations = scipy_direct.solve(SIZE, LAM, TIMES, args.scipy_rtol[i], 1e-14)
            rows.append(("scipy DOP853", args.scipy_rtol[i], seconds, error(moments, reference)))
            print("%-18s rtol %-8g %9.2f s  max rel. error %.2e  (%d right-hand sides)" % (rows[-1] + (evaluations,)),
                  flush=True)
    print("\nratios (scipy time / aggkit time) where aggkit's error is at most scipy's:")
    for name, rtol, seconds, err in rows:
        if not name.startswith("scipy"):
            continue
        matches = [r for r in rows if r[0].startswith("aggkit") and r[3] <= err]
        if not matches:
            print(f"  scipy rtol {rtol:g} (error {err:.1e}): no aggkit run as accurate")
            continue
        best = min(matches, key=lambda r: r[2])
        print(f"  scipy rtol {rtol:g} (error {err:.1e}, {seconds:.1f} s) vs aggkit rtol {best[1]:g} (error {best[3]:.1e}, "
              f"{best[2]:.2f} s): {seconds / best[2]:.0f}x")


if __name__ == "__main__":
    main()
