#!/usr/bin/env python3
"""Independent check of the graded grid's Hopf point at a = 0.7 on the uniform grid.

λ_crit(0.7) = 4.3910e-4 comes from the graded grid (K = 64, r = 1.02; validation/scenes/scan-brownian.toml).
Here, at λ = 0.8 λ_crit and 1.25 λ_crit:
  1. the graded grid's steady state and rightmost eigenvalue pair μ (r = 1.02);
  2. the uniform grid's own steady state (every size 1..N, N = 65536: λN ≥ 23, so that the leak of the drop
     truncation moves nothing over 10^4 time units — at N = 32768 M0 drifted 15 % in that time and the
     envelope with it, on both grids alike; Newton from the graded one carried
     over: density per unit size interpolated log-linearly between pivots, which is off by ~3e-3), started
     from 1e-3 of the way back towards the carried state (a perturbation of ~3e-6 in every mode), integrated
     by CVODE on the uniform grid (rtol 1e-8) for about 10 periods;
  3. the envelope of M0 - M0_steady fitted over its turning points (log |peak| against t: least squares) and
     the period from the spacing of the peaks.
Below λ_crit the uniform run must grow at Re μ > 0, above it decay at Re μ < 0, with the period 2π/Im μ.
  PYTHONPATH=build/python /usr/bin/python3 bench/either_side_a07.py [--size 65536] [--periods 10]
"""
import argparse
import sys
import time

import numpy as np

import aggkit

LAMBDA_CRIT = 4.391029736419316e-4  # bench/results/log/scan-brownian/lambda_crit.csv, a = 0.7


def uniform_start(steady, size):
    x = np.asarray(steady.sizes, dtype=float)
    n = np.asarray(steady.n, dtype=float)
    # The width a pivot stands for, (x_{i+1} - x_{i-1}) / 2 with x_0 = 0 and x_{M+1} = 2 x_M - x_{M-1}
    # (solvers/size_grid.hpp): 1 on the integers of the resolved block.
    padded = np.concatenate(([0.0], x, [2 * x[-1] - x[-2]]))
    density = n / (0.5 * (padded[2:] - padded[:-2]))
    keep = density > 0
    k = np.arange(1, size + 1, dtype=float)
    return np.exp(np.interp(np.log(k), np.log(x[keep]), np.log(density[keep])))


def envelope(t, y):
    """Turning points of y (maxima of |y|, one per half cycle), the least-squares growth rate of ln|y| there and
    the mean spacing of the maxima."""
    i = np.where((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]))[0] + 1  # maxima
    j = np.where((y[1:-1] < y[:-2]) & (y[1:-1] <= y[2:]))[0] + 1  # minima
    turns = np.sort(np.concatenate((i, j)))
    slope, intercept = np.polyfit(t[turns], np.log(np.abs(y[turns])), 1)
    residual = np.log(np.abs(y[turns])) - (slope * t[turns] + intercept)
    period = np.mean(np.diff(t[i]))
    return slope, period, len(i), np.max(np.abs(residual))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=65536)
    parser.add_argument("--periods", type=float, default=10)
    parser.add_argument("--save", default="either_side", help="M0(t) goes to SAVE_<lambda/lambda_crit>.csv")
    args = parser.parse_args()
    print(f"a = 0.7, lambda_crit (graded, K = 64, r = 1.02) = {LAMBDA_CRIT:.6g}; uniform N = {args.size}")
    print("lambda/lambda_crit, Re mu (graded), period 2pi/Im mu, growth (uniform), period (uniform), "
          "cycles, fit residual, CPU s")
    failed = False
    for factor in (0.8, 1.25):
        lam = factor * LAMBDA_CRIT
        if lam * args.size < 8:
            sys.exit(f"N = {args.size} is too short for lambda = {lam:.4g} (need lambda N >= 8)")
        graded = aggkit.Model("brownian", lam=lam, size=2**30, grid={"resolved": 64, "ratio": 1.02}, a=0.7)
        steady = aggkit.steady_state(graded)
        mu = [e for e in aggkit.rightmost_eigenvalues(graded, steady.n, 16) if e.imag != 0][0]
        period_linear = 2 * np.pi / abs(mu.imag)
        carried = uniform_start(steady, args.size)
        try:
            uniform = np.asarray(aggkit.steady_state(
                aggkit.Model("brownian", lam=lam, size=args.size, initial=carried, a=0.7), start_time=1e-3).n)
            start = uniform + 1e-3 * (carried - uniform)
        except RuntimeError as error:  # Newton on 2^15+ sizes may stall: start from the carried state itself
            print(f"  (uniform steady state not found: {str(error)[:80]}...; starting from the carried state)")
            uniform = start = carried
        model = aggkit.Model("brownian", lam=lam, size=args.size, initial=start, a=0.7)
        times = np.arange(0.0, args.periods * period_linear, period_linear / 60)[1:]
        began = time.process_time()
        run = aggkit.integrate(model, times, rtol=1e-8)
        cpu = time.process_time() - began
        m0 = np.asarray(run.moment(0))
        m0_steady = float(np.sum(uniform))
        np.savetxt(f"{args.save}_{factor:g}.csv", np.column_stack((times, m0)), delimiter=",", header="t,M0",
                   comments="")
        # The oscillation about a running mean over one period (drop truncation leaks: the state drifts slowly),
        # fitted after the first period (the fast modes of the perturbation relax).
        window = 60  # samples per linear period
        trend = np.convolve(m0, np.ones(window) / window, mode="same")
        keep = (times > period_linear) & (np.arange(len(times)) < len(times) - window // 2)
        growth, period, cycles, residual = envelope(times[keep], m0[keep] - trend[keep])
        print(f"{factor:g}, {mu.real:.4e}, {period_linear:.1f}, {growth:.4e}, {period:.1f}, {cycles}, "
              f"{residual:.2f}, {cpu:.0f}   (M0 steady {m0_steady:.5g})")
        same_sign = (growth > 0) == (mu.real > 0)
        failed = failed or not same_sign
    print("uniform runs grow below and decay above lambda_crit: " + ("no" if failed else "yes"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
