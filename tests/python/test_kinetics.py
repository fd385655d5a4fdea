"""The kinetic solvers from Python against exact solutions, closed forms and the built-in kernels."""
import numpy as np
import pytest

import aggkit


def test_constant_kernel_against_the_exact_solution():
    # K = 1, λ = 0, unit monodisperse start: M0 = 2/(t+2), M2 = 1 + t, n_1 = 4/(t+2)^2.
    t = np.array([0.5, 1.0, 5.0, 20.0])
    s = aggkit.integrate(aggkit.Model("constant", size=4096), t, rtol=1e-9)
    assert np.allclose(s.t, t)
    assert np.allclose(s.moment(0), 2 / (t + 2), rtol=1e-7)
    assert np.allclose(s.moment(2), 1 + t, rtol=1e-6)
    assert np.allclose(s.moment(3), 1 + 3 * t + 1.5 * t * t, rtol=1e-6)
    assert np.allclose(s.n[:, 0], 4 / (t + 2) ** 2, rtol=1e-7)
    assert s.statistics["steps"] > 0


def test_sum_and_product_kernels_against_the_exact_solutions():
    t = np.array([0.2, 0.5, 0.9])
    product = aggkit.integrate(aggkit.Model("product", size=4096), t, rtol=1e-9)
    assert np.allclose(product.moment(2), 1 / (1 - t), rtol=1e-5)  # M2 = 1/(1-t) before gelation
    s = aggkit.integrate(aggkit.Model("sum", size=4096), [1.0], rtol=1e-9)
    tau = 1 - np.exp(-1.0)
    assert s.moment(0)[0] == pytest.approx(1 - tau, rel=1e-6)  # M0 = e^{-t}


def test_steady_state_of_K2_against_its_closed_form():
    # K = 2 (brownian, a = 0): the total density relaxes to N* = 2λ/(1+2λ).
    lam = 0.25
    ss = aggkit.steady_state(aggkit.Model("brownian", a=0.0, lam=lam, size=512, truncation="cutoff"))
    assert ss.residual <= 1e-10
    assert ss.moment(0) == pytest.approx(2 * lam / (1 + 2 * lam), rel=1e-6)
    assert ss.moment(1) == pytest.approx(1.0, rel=1e-12)  # mass conserved under cutoff


def test_a_python_kernel_equal_to_a_built_in_one_gives_the_same_solution():
    t = [1.0, 4.0]
    built_in = aggkit.integrate(aggkit.Model("brownian", a=0.5, lam=0.1, size=256), t, rtol=1e-9)
    user = aggkit.integrate(aggkit.Model(lambda i, j: (i / j) ** 0.5 + (j / i) ** 0.5, lam=0.1, size=256), t, rtol=1e-9)
    assert np.allclose(user.moment(0), built_in.moment(0), rtol=1e-7)
    assert np.allclose(user.moment(2), built_in.moment(2), rtol=1e-6)


def test_a_python_shattering_rate_equal_to_a_built_in_law_gives_the_same_solution():
    # λ(t) = 0.01 (1 - t/400) [Kalinov2022, Sec. 5.2]: the built-in linear law against a callable.
    t = [50.0, 200.0]
    built_in = aggkit.integrate(aggkit.Model("brownian", a=0.9, lam={"initial": 0.01, "slope": -0.01 / 400}, size=512),
                                t, rtol=1e-9)
    user = aggkit.integrate(aggkit.Model("brownian", a=0.9, lam=lambda s: 0.01 * (1 - s / 400), size=512), t, rtol=1e-9)
    assert np.allclose(user.moment(0), built_in.moment(0), rtol=1e-8)
    with pytest.raises(ValueError, match="constant shattering rate"):
        aggkit.steady_state(aggkit.Model("brownian", a=0.9, lam=lambda s: 0.01, size=64, truncation="cutoff"))


def test_dsmc_means_and_standard_errors_bracket_the_exact_solution():
    # Constant kernel: every trial is accepted and advances the clock by a fixed step, so M0 is the same in
    # every run (its standard error is 0); M2 = 1 + t fluctuates.
    t = np.array([1.0, 2.0])
    e = aggkit.dsmc(aggkit.Model("constant", size=1000), particles=20000, times=t, runs=8, seed=3, observables=["M0", "M2"])
    assert e.stderr["M2"].shape == (2,)
    assert np.all(e.stderr["M2"] > 0)
    assert np.all(np.abs(e.series["M2"] - (1 + t)) <= 5 * e.stderr["M2"])
    # M0 is bracketed like M2. (With every trial accepted, as for K = 1 under a majorant without empty slots, M0
    # was off only by the clock's granularity, 1e-4; the majorant's empty slots (particle/dsmc/slot_majorant.hpp)
    # reject a trial now and then, so the number of events by t is random, as it is in the exact process.)
    assert np.all(e.stderr["M0"] > 0)
    assert np.all(np.abs(e.series["M0"] - 2 / (t + 2)) <= 5 * e.stderr["M0"])


def test_arrays_are_views_of_the_core_buffer_that_outlive_the_solution():
    s = aggkit.integrate(aggkit.Model("constant", size=1024), [1.0, 2.0])
    n = s.n
    assert not n.flags["OWNDATA"] and n.base is not None  # a view: no copy on the way out
    first = n[0, 0]
    del s
    import gc
    gc.collect()
    assert n[0, 0] == first and n[0, 0] == pytest.approx(4 / 9, rel=1e-5)


def test_the_gil_is_released_while_a_solver_runs():
    import threading
    counter = [0]
    done = threading.Event()

    def spin():
        while not done.is_set():
            counter[0] += 1

    spinner = threading.Thread(target=spin)
    spinner.start()
    try:
        before = counter[0]
        aggkit.integrate(aggkit.Model("ballistic", lam=0.01, size=8192), [10.0, 100.0])
        during = counter[0] - before
    finally:
        done.set()
        spinner.join()
    # With the GIL held for the whole run the other thread would hardly run (a few switch intervals).
    assert during > 10000


def test_stability_at_the_published_regimes():
    # a = 0.95, λ = 0.01 oscillates forever (unstable steady state); a = 0.5 relaxes [Brilliantov2018].
    unstable = aggkit.Model("brownian", a=0.95, lam=0.01, size=1024)
    eigenvalues = aggkit.rightmost_eigenvalues(unstable, aggkit.steady_state(unstable), count=4)
    assert eigenvalues.dtype == complex and eigenvalues[0].real > 0 and abs(eigenvalues[0].imag) > 0
    stable = aggkit.Model("brownian", a=0.5, lam=0.1, size=256, truncation="cutoff")
    assert aggkit.rightmost_eigenvalues(stable, aggkit.steady_state(stable), count=4)[0].real < 0
    with pytest.raises(ValueError, match="state"):
        aggkit.rightmost_eigenvalues(stable, np.ones(3))


def test_spectrum_and_limit_cycle_at_a_sustained_point():
    # a = 0.95, λ = 0.01 on a graded grid (K = 32, r = 1.1, N = 2^20): an unstable focus, and the attracting
    # cycle around it found by shooting from a run to t = 3000, its period 33.694 to 1e-3 (the limit in r: four-
    # and three-moment shares both give 33.694 at r = 1.025; four-moment 33.707 at r = 1.1, three-moment
    # 33.83; the C++ tests check the period against a long time series to 1e-3), one period of M0..M3 that
    # closes on itself.
    model = aggkit.Model("brownian", a=0.95, lam=0.01, size=2**20, grid={"resolved": 32, "ratio": 1.1})
    s = aggkit.spectrum(model, aggkit.steady_state(model))
    assert s["kind"] == "unstable focus" and not s["stable"]
    cycle = aggkit.limit_cycle(model, settle=3000.0)
    assert cycle["converged"], cycle["note"]
    assert cycle["period"] == pytest.approx(33.694, rel=1e-3)
    assert cycle["stable"] and abs(cycle["floquet"][0]) < 1
    assert cycle["orbit"].shape == (201, 5)
    assert cycle["orbit"][-1, 1] == pytest.approx(cycle["orbit"][0, 1], rel=1e-6)
    assert cycle["m0_min"] < cycle["m0_max"]
    with pytest.raises(ValueError, match="orbit_samples"):
        aggkit.limit_cycle(model, settle=3000.0, orbit_samples=1)
    with pytest.raises(ValueError, match="newton"):
        aggkit.limit_cycle(model, settle=3000.0, newton=3)
    with pytest.raises(ValueError, match="start"):
        aggkit.limit_cycle(model, start=np.ones(3), period=30.0)


def test_hopf_normal_form_predicts_the_cycle_near_the_curve():
    # a = 0.95 at λ = 0.012, 5 % below λ_crit = 0.01268 on this grid: supercritical (l1 = -31.6), and the
    # normal form's M0 half-range (0.0400) within 3 % of the cycle shot from a run (0.0397; C++:
    # tests/solvers/test_hopf_normal_form.cpp), its angular frequency within 2e-3 of 2 pi / period.
    model = aggkit.Model("brownian", a=0.95, lam=0.012, size=2**20, grid={"resolved": 32, "ratio": 1.1})
    form = aggkit.hopf_normal_form(model, aggkit.steady_state(model))
    assert form["mu"].real > 0 and form["supercritical"] and form["lyapunov"] < 0
    assert form["q"].ndim == 1 and len(form["q"]) > 32  # one entry per size class of the graded grid
    cycle = aggkit.limit_cycle(model, settle=3000.0, floquet_count=0)
    assert cycle["converged"], cycle["note"]
    assert form["m0_half_range"] == pytest.approx(0.5 * (cycle["m0_max"] - cycle["m0_min"]), rel=0.03)
    assert 2 * np.pi / form["frequency"] == pytest.approx(cycle["period"], rel=2e-3)
    with pytest.raises(ValueError, match="state"):
        aggkit.hopf_normal_form(model, np.ones(3))


def test_locate_hopf_finds_where_the_rightmost_pair_crosses():
    model = aggkit.Model("brownian", a=0.95, lam=0.01, size=512, truncation="cutoff")
    h = aggkit.locate_hopf(model, a=0.95, lambda_lo=0.005, lambda_hi=0.5)
    assert h["found"] and 0.005 < h["lambda_crit"] < 0.5
    assert h["period"] == pytest.approx(2 * np.pi / h["omega"])
    # Below the crossing the steady state is unstable, above it stable (SNES finds no steady state just
    # above it from its default start: the slowly damped oscillation, so the check is at 1.5 λ_crit).
    for factor, sign in [(0.9, 1), (1.5, -1)]:
        m = aggkit.Model("brownian", a=0.95, lam=h["lambda_crit"] * factor, size=512, truncation="cutoff")
        assert sign * aggkit.rightmost_eigenvalues(m, aggkit.steady_state(m), 2)[0].real > 0


def test_keyword_defaults_are_the_option_tables():
    # One declaration: the signature's default of every option is the table's value, and a keyword left out
    # runs the engine's own default — DSMC's seed 1, as the command line.
    import inspect
    for function, engine in [(aggkit.integrate, "cvode"), (aggkit.steady_state, "snes"), (aggkit.dsmc, "dsmc"),
                             (aggkit.ed, "ed"), (aggkit.ts, "ts"), (aggkit.dem, "dem")]:
        parameters = inspect.signature(function).parameters
        for row in aggkit.engine_options(engine):
            if row["key"] in parameters and row["key"] != "particles":  # dsmc's particles is required
                assert parameters[row["key"]].default == row["value"], (engine, row["key"])
    assert inspect.signature(aggkit.dsmc).parameters["seed"].default == 1
    model = aggkit.Model("constant", size=100)
    left_out = aggkit.dsmc(model, particles=2000, times=[1.0], observables=["M2"])
    given = aggkit.dsmc(model, particles=2000, times=[1.0], observables=["M2"], seed=1)
    other = aggkit.dsmc(model, particles=2000, times=[1.0], observables=["M2"], seed=0)
    assert left_out.series["M2"][0] == given.series["M2"][0]
    assert other.series["M2"][0] != given.series["M2"][0]
    positional = aggkit.dsmc(model, 2000, [1.0], "ar", 1, 1, ["M2"])  # method, runs, seed keep their places
    assert positional.series["M2"][0] == given.series["M2"][0]


def test_an_engine_without_a_function_of_its_own_gets_one_from_the_registry():
    # The closed-form engine has no hand-written function: the registry gives aggkit.exact, against CVODE.
    model = aggkit.Model("constant", size=4096)
    exact = aggkit.exact(model, [1.0, 5.0], observables=["M0"])
    cvode = aggkit.integrate(model, [1.0, 5.0], rtol=1e-10)
    assert np.allclose(exact.series["M0"], cvode.moment(0), rtol=1e-8)
    assert "exact" in aggkit.__all__


def test_graded_grid_from_python():
    # The graded grid (sizes 1..16, then sections growing by 10 % up to N = 2^30). Every scheme keeps number
    # and mass, so the constant kernel's M0 = 2/(t+2) and M1 = 1 are exact on it (to rtol). Four-moment
    # shares (the default) also keep x² and x³, and dM2/dt = M1², dM3/dt = 3 M1 M2 are closed, so
    # M2 = 1 + t and M3 = 1 + 3t + 1.5t² are exact too; fixed
    # pivots make M2 second order in r - 1 (1.6e-2 at r = 1.2 and 4e-3 at 1.1 with K = 8,
    # bench/graded_grid_convergence.cpp), so 2 % at r = 1.1, K = 16 holds with room and 1e-6 does not.
    model = aggkit.Model("constant", size=2 ** 30, grid={"resolved": 16, "ratio": 1.1})
    t = np.array([10.0, 100.0])
    s = aggkit.integrate(model, t, rtol=1e-9)
    assert s.n.shape[1] == len(s.sizes) < 300
    assert s.sizes[15] == 16 and s.sizes[-1] == 2 ** 30
    assert np.allclose(s.moment(0), 2 / (t + 2), rtol=1e-7)
    assert np.allclose(s.moment(1), 1.0, rtol=1e-10)
    assert np.allclose(s.moment(2), 1 + t, rtol=1e-6)
    assert np.allclose(s.moment(3), 1 + 3 * t + 1.5 * t * t, rtol=1e-6)
    # The densities the numbers stand for, against n_k = 4/(t+2)² (t/(t+2))^(k-1) where n_k ≥ 1e-6 of its
    # largest: 2.9 % (t = 10) and 1.9 % (t = 100) measured, at the first spacing jump just above K = 16
    # (tests/solvers/test_graded_grid.cpp follows them as r - 1 falls), where N_i / Δ_i, the numbers over
    # the pivots' widths, is off by ~10 %.
    with np.errstate(under="ignore"):
        exact = 4 / (t[:, None] + 2) ** 2 * (t[:, None] / (t[:, None] + 2)) ** (s.sizes[None, :] - 1)
    keep = exact > 1e-6 * exact.max(axis=1, keepdims=True)
    assert s.density.shape == s.n.shape
    assert np.max(np.abs(s.density[keep] / exact[keep] - 1)) < 0.035
    widths = 0.5 * (np.append(s.sizes[1:], 2 * s.sizes[-1] - s.sizes[-2]) - np.insert(s.sizes[:-1], 0, 0.0))
    assert np.max(np.abs(s.n[keep] / widths[np.nonzero(keep)[1]] / exact[keep] - 1)) > 0.05
    pivots = aggkit.integrate(aggkit.Model("constant", size=2 ** 30, grid={"resolved": 16, "ratio": 1.1,
                                                                           "scheme": "fixed-pivot"}), t, rtol=1e-9)
    assert np.allclose(pivots.moment(0), 2 / (t + 2), rtol=1e-7)
    assert np.allclose(pivots.moment(2), 1 + t, rtol=2e-2)
    assert not np.allclose(pivots.moment(2), 1 + t, rtol=1e-4)
    with pytest.raises(ValueError, match="grid"):
        aggkit.Model("constant", size=100, grid={"resolved": 16})
    with pytest.raises(ValueError, match="grid.scheme"):
        aggkit.integrate(aggkit.Model("constant", size=100, grid={"resolved": 16, "ratio": 1.1, "scheme": "cell"}), [1.0])
        aggkit.integrate(aggkit.Model("constant", size=100, grid={"resolved": 16, "ratio": 9.0}), [1.0])
