#!/usr/bin/env python3
"""The peer a user would write: the truncated aggregation-shattering equations (the mass-conserving form
of [Kalinov2022, eq. 4], with the 1/2 on the monomer double sum, as solvers/rates_direct.cpp) integrated
by scipy's solve_ivp (DOP853 by default; LSODA, BDF, RK45, Radau with their finite-difference Jacobians) with
the right-hand side as numpy direct O(N^2) sums. Ballistic kernel
K_ij = (i^{1/3}+j^{1/3})^2 sqrt(1/i+1/j), cutoff truncation (K_ij = 0 for i + j > N), monodisperse start.

  /usr/bin/python3 bench/peers/scipy_direct.py [--size 2000] [--lam 0.01] [--rtol 1e-8] [--atol 1e-14] [--method DOP853]

prints one line per output time: t M0 M2 M3, then the wall time. Also imported by bench/scipy_vs_aggkit.py.
"""
import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp


def ballistic_cutoff(size):
    k = np.arange(1, size + 1, dtype=float)
    i, j = np.meshgrid(k, k, indexing="ij")
    K = (np.cbrt(i) + np.cbrt(j)) ** 2 * np.sqrt(1.0 / i + 1.0 / j)
    K[i + j > size] = 0.0  # cutoff: no collision that would exceed N
    return K


def right_hand_side(K, lam):
    size = K.shape[0]
    k = np.arange(1, size + 1, dtype=float)
    index = np.add.outer(np.arange(size), np.arange(size)) + 1  # 0-based index of size i + j
    index = index.ravel()
    loss_factor = np.full(size, 1.0 + lam)
    loss_factor[0] = 1.0  # a monomer colliding is not "shattered" into monomers again
    K_aggregates = K.copy()
    K_aggregates[0, :] = 0.0
    K_aggregates[:, 0] = 0.0

    def f(t, n):
        rate = K @ n
        gain = 0.5 * np.bincount(index, weights=(K * np.outer(n, n)).ravel(), minlength=2 * size)[:size]
        dndt = gain - loss_factor * n * rate
        # Shattering returns the colliding mass as monomers: λ n_1 Σ_{j≥2} j K_1j n_j + (λ/2) Σ_{i,j≥2} (i+j) K_ij n_i n_j.
        dndt[0] += lam * n[0] * np.dot(k[1:] * K[0, 1:], n[1:]) + lam * np.dot(k * n, K_aggregates @ n)
        return dndt

    return f


def integrate(f, size, times, rtol, atol, method, started):
    """solve_ivp of dn/dt = f from the monodisperse start: moments M0, M2, M3 at `times` (rows), the wall time
    since `started` and the number of right-hand sides. Shared with scipy_constant.py."""
    n0 = np.zeros(size)
    n0[0] = 1.0
    solution = solve_ivp(f, (0.0, times[-1]), n0, method=method, t_eval=list(times), rtol=rtol, atol=atol)
    if not solution.success:
        raise RuntimeError(solution.message)
    k = np.arange(1, size + 1, dtype=float)
    moments = np.array([[np.sum(n), np.sum(k**2 * n), np.sum(k**3 * n)] for n in solution.y.T])
    return moments, time.perf_counter() - started, solution.nfev


def solve(size=2000, lam=0.01, times=(1.0, 10.0, 100.0), rtol=1e-8, atol=1e-14, method="DOP853"):
    """Moments M0, M2, M3 at `times` (rows), the wall time (kernel set-up included), the right-hand sides."""
    started = time.perf_counter()
    return integrate(right_hand_side(ballistic_cutoff(size), lam), size, times, rtol, atol, method, started)


def command_line(solve, doc, size, lam):
    """The peers' command line: one line t M0 M2 M3 per output time, then the wall time."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=size)
    parser.add_argument("--lam", type=float, default=lam)
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
    command_line(solve, __doc__, 2000, 0.01)
