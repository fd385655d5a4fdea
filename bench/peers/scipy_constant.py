#!/usr/bin/env python3
"""The peer a user would write for the constant kernel K = 1 (the truncated equations of [Kalinov2022, eq. 4]
in their mass-conserving form, as solvers/model.hpp, `drop` truncation, monodisperse start): with K = 1 the
gain is a convolution, ½ (n * n)_k, computed by scipy.signal.fftconvolve (O(N log N)), the collision rate is
M0 and the monomer source from shattering λ n_1 (M1 - n_1) + λ (M1 - n_1)(M0 - n_1). Integrated by scipy's
solve_ivp (DOP853 by default; LSODA, BDF, RK45, Radau with their finite-difference Jacobians).

  /usr/bin/python3 bench/peers/scipy_constant.py [--size 32768] [--lam 0.1] [--rtol 1e-8] [--atol 1e-14] [--method DOP853]

prints one line per output time: t M0 M2 M3, then the wall time. Also imported by bench/scipy_vs_aggkit.py,
which also times the direct sum np.convolve(n, n) (what scipy_direct.py is for the ballistic kernel) per call.
"""
import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.signal import fftconvolve


def right_hand_side(size, lam, convolve=fftconvolve):
    def f(t, n):
        m0, m1 = np.sum(n), np.dot(np.arange(1, size + 1, dtype=float), n)
        dndt = np.empty(size)
        dndt[1:] = 0.5 * convolve(n, n)[: size - 1] - (1.0 + lam) * n[1:] * m0
        rest0, rest1 = m0 - n[0], m1 - n[0]
        dndt[0] = -n[0] * m0 + lam * n[0] * rest1 + lam * rest1 * rest0
        return dndt

    return f


def solve(size=32768, lam=0.1, times=(1.0, 10.0, 100.0), rtol=1e-8, atol=1e-14, method="DOP853"):
    """Moments M0, M2, M3 at `times` (rows), the wall time and the number of right-hand sides."""
    started = time.perf_counter()
    n0 = np.zeros(size)
    n0[0] = 1.0
    solution = solve_ivp(right_hand_side(size, lam), (0.0, times[-1]), n0, method=method, t_eval=list(times),
                         rtol=rtol, atol=atol)
    if not solution.success:
        raise RuntimeError(solution.message)
    k = np.arange(1, size + 1, dtype=float)
    moments = np.array([[np.sum(n), np.sum(k**2 * n), np.sum(k**3 * n)] for n in solution.y.T])
    return moments, time.perf_counter() - started, solution.nfev


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=32768)
    parser.add_argument("--lam", type=float, default=0.1)
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--atol", type=float, default=1e-14)
    parser.add_argument("--method", default="DOP853")
    args = parser.parse_args()
    times = (1.0, 10.0, 100.0)
    moments, seconds, evaluations = solve(args.size, args.lam, times, args.rtol, args.atol, args.method)
    for t, row in zip(times, moments):
        print(f"{t:g} {row[0]:.15e} {row[1]:.15e} {row[2]:.15e}")
    print(f"wall {seconds:.2f} s, {evaluations} right-hand sides")


if __name__ == "__main__":
    main()
