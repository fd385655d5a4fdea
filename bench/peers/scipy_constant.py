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
import os
import sys
import time

import numpy as np
from scipy.signal import fftconvolve

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scipy_direct  # noqa: E402


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
    return scipy_direct.integrate(right_hand_side(size, lam), size, times, rtol, atol, method, time.perf_counter())


if __name__ == "__main__":
    scipy_direct.command_line(solve, __doc__, 32768, 0.1)
