"""The pressureless cold-collapse time of a uniform cloud at which a given share of its mass has reached the
centre, the reference of validation/scenes/dem-gravitational-collapse.toml and tests/validation/test_engine_dem.cpp.

A cold particle starting at distance r from the centre of a uniform cloud falls in under the mass M(<r)
initially inside its radius (no shell crossing, the spherical approximation) and reaches the centre at
t(r) = (pi/2) sqrt(r^3 / (2 G M(<r))) [the free fall of a cold sphere; for a uniform sphere every particle
arrives at (pi/2) sqrt(R^3/(2GM)) = 1.1107 t_ff]. The time at which the share q of the mass has arrived is the
q-quantile of t over the particles, here by Monte Carlo over 2 000 000 points uniform in a cube or a ball, in
units of t_ff = sqrt(R_c^3/(G M)), R_c the largest distance of a particle from the centre (as the dem engine
reports free_fall_time).

  /usr/bin/python3 bench/cold_collapse_reference.py
"""
import numpy as np

rng = np.random.default_rng(2026)
n = 2_000_000
for shape in ("cube", "ball"):
    points = rng.uniform(-1.0, 1.0, (n if shape == "cube" else 2 * n, 3))
    if shape == "ball":
        points = points[np.linalg.norm(points, axis=1) < 1.0][:n]
    r = np.linalg.norm(points, axis=1)
    enclosed = np.searchsorted(np.sort(r), r, side="right") / len(r)  # M(<r) / M
    t = (np.pi / 2) * np.sqrt(r**3 / (2 * enclosed))                  # G = M = 1
    t_ff = r.max() ** 1.5
    quantiles = {q: np.quantile(t, q) / t_ff for q in (0.5, 0.9, 0.95)}
    print(f"{shape}: share of the mass at the centre by t/t_ff: " +
          ", ".join(f"{int(100 * q)} % at {v:.4f}" for q, v in quantiles.items()))
