#!/usr/bin/python3
"""How far Newton–Krylov shooting gets on one cycle, and at what cost (aggkit.limit_cycle).

    PYTHONPATH=build/python /usr/bin/python3 bench/shooting_convergence.py A LAMBDA SETTLE [NEWTON] [RTOL]

Brownian-type kernel a = A, λ = LAMBDA, N = 2^40 on the graded grid K = 32, r = 1.1 (287 classes); the start is
the state at the last upward M0 crossing of a run from the monodisperse state to t = SETTLE. Shooting to a scaled
residual of 1e-6 in at most NEWTON (12) steps of at most 40 GMRES iterations, CVODE at RTOL (1e-10) inside.
Prints: converged, period, final scaled residual, Newton steps, GMRES iterations, period maps, the three largest
nontrivial Floquet |μ|, CPU seconds and the solver's note."""
import sys
import time

import numpy as np

import aggkit

a, lam, settle = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
newton = int(sys.argv[4]) if len(sys.argv) > 4 else 12
rtol = float(sys.argv[5]) if len(sys.argv) > 5 else 1e-10
model = aggkit.Model("brownian", lam=lam, size=2**40, truncation="drop", grid={"resolved": 32, "ratio": 1.1}, a=a)
started = time.process_time()
r = aggkit.limit_cycle(model, settle=settle, rtol=rtol, tolerance=1e-6, max_newton_iterations=newton,
                       max_krylov_iterations=40, floquet_count=4)
floquet = np.abs(r["floquet"])[:3] if len(r["floquet"]) else []
print(f"a = {a}, lambda = {lam}: converged {r['converged']}, period {r['period']:.6f}, residual {r['residual']:.3g}, "
      f"Newton {r['newton_iterations']}, GMRES {r['krylov_iterations']}, period maps {r['period_maps']}, "
      f"Floquet |mu| {', '.join(f'{m:.4g}' for m in floquet)}, CPU {time.process_time() - started:.1f} s; {r['note']}")
