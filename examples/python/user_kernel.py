"""A kernel no scene can express: K(i, j) = (i j)^(1/4) + 0.1 (i + j)^(1/2), given as a Python function.
The core samples it to build a low-rank factorisation, then integrates with CVODE as for the built-in ones.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/user_kernel.py
"""
import aggkit


def kernel(i, j):
    return (i * j) ** 0.25 + 0.1 * (i + j) ** 0.5


solution = aggkit.integrate(aggkit.Model(kernel, lam=0.05, size=1024), [1.0, 10.0, 100.0])
for t, m0, m2 in zip(solution.t, solution.moment(0), solution.moment(2)):
    print(f"t = {t:6.1f}   M0 = {m0:.6f}   M2 = {m2:.4f}")
print("kernel rank:", solution.statistics["kernel_rank"], " error:", solution.statistics["kernel_relative_error"])
