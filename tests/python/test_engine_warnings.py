"""What an engine warns about a completed run reaches Python as it reaches the command line: each warning is
issued as aggkit.EngineWarning at the caller's line and kept on the result (`warnings`; summary.json's
engines.<label>.warnings for aggkit.run)."""
import warnings

import pytest

import aggkit

# 20 spheres in open space; t_c = 0.05 allows dt up to t_c/2, and dt = 0.004 > t_c/20 = 0.0025 is warned about
# [Trivino2025, eq. 8]; the default step t_c/50 is not.
CLOUD = dict(dimension=3, count=20, radius=1.0, mass=1.0, boundary="open",
             initial={"cloud": "cube", "volume_fraction": 0.05, "speed": 0.3})
DT_WARNING = "dt = 0.004 > t_c/20 = 0.0025"


def _quietly(call):
    """The result of call() with every EngineWarning turned into an error: a quiet run must stay quiet."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", aggkit.EngineWarning)
        return call()


def test_engine_warning_is_a_runtime_warning_of_its_own():
    assert issubclass(aggkit.EngineWarning, RuntimeWarning)
    assert "EngineWarning" in aggkit.__all__


def test_dem_step_warning_reaches_python_at_the_callers_line_and_on_the_result():
    with pytest.warns(aggkit.EngineWarning, match="engine dem: " + DT_WARNING) as caught:
        run = aggkit.dem([1.0], CLOUD, restitution=0.5, contact_time=0.05, dt=0.004)
    assert [w.filename for w in caught] == [__file__] * len(caught)  # stacklevel: this line, not aggkit's
    assert len(run.warnings) == 1 and run.warnings[0].startswith(DT_WARNING)
    assert "[Trivino2025, eq. 8]" in run.warnings[0]
    quiet = _quietly(lambda: aggkit.dem([1.0], CLOUD, restitution=0.5, contact_time=0.05))
    assert quiet.warnings == []


def test_unread_petsc_options_of_snes_reach_python():
    model = aggkit.Model("brownian", a=0.0, lam=0.25, size=128, truncation="cutoff")
    with pytest.warns(aggkit.EngineWarning, match="PETSc options not read by SNES, KSP or PC.*-snes_no_such_option"):
        ss = aggkit.steady_state(model, petsc_options="-snes_no_such_option 3")
    assert ss.residual <= 1e-10  # the run completed: a warning, not an error
    assert len(ss.warnings) == 1 and "-snes_no_such_option" in ss.warnings[0]
    assert _quietly(lambda: aggkit.steady_state(model)).warnings == []


def test_cvode_negative_densities_beyond_the_tolerance_reach_python():
    # Explicit Dormand–Prince at rtol 1e-2 on the ballistic kernel with λ = 1 leaves far-tail densities below
    # -atol_k (measured: n_512 ≈ -1.2e-12 at t = 10); the default rtol 1e-6 does not.
    model = aggkit.Model("ballistic", lam=1.0, size=512)
    with pytest.warns(aggkit.EngineWarning, match="engine cvode: [0-9]+ densities below -atol_k at one output"):
        loose = aggkit.integrate(model, [0.5, 2.0, 10.0], rtol=1e-2, method="erk")
    assert len(loose.warnings) == 1 and "(tighten rtol or atol)" in loose.warnings[0]
    assert _quietly(lambda: aggkit.integrate(model, [0.5, 2.0, 10.0], method="erk")).warnings == []
    # On a coarse graded grid (r = 1.1) the four-moment shares undershoot at the steep front of the constant
    # kernel's tail (n_178 ≈ -3e-15 at t = 10, at any rtol): the warning names the grid's remedies instead;
    # fixed pivots keep every n_k >= 0 and give no warning.
    graded = aggkit.Model("constant", size=2 ** 30, grid={"resolved": 16, "ratio": 1.1})
    with pytest.warns(aggkit.EngineWarning, match="undershoot at a steep front"):
        coarse = aggkit.integrate(graded, [10.0], rtol=1e-9)
    assert len(coarse.warnings) == 1 and 'grid.scheme = "fixed-pivot"' in coarse.warnings[0]
    fixed = aggkit.Model("constant", size=2 ** 30, grid={"resolved": 16, "ratio": 1.1, "scheme": "fixed-pivot"})
    assert _quietly(lambda: aggkit.integrate(fixed, [10.0], rtol=1e-9)).warnings == []


def test_every_result_carries_its_warnings():
    # A run without anything to warn about has an empty list on every kind of result.
    model = aggkit.Model("constant", size=64)
    assert _quietly(lambda: aggkit.integrate(model, [1.0])).warnings == []
    assert _quietly(lambda: aggkit.dsmc(model, particles=1000, times=[1.0])).warnings == []
    particles = dict(dimension=2, count=50, radius=0.5, volume_fraction=0.2, boundary="reflecting")
    assert _quietly(lambda: aggkit.ed([1.0], particles)).warnings == []


def test_run_issues_the_warnings_of_summary_json(tmp_path):
    scene = {"name": "dem-warning", "particles": CLOUD, "time": {"end": 1.0},
             "engine": [{"name": "dem", "restitution": 0.5, "contact_time": 0.05, "dt": 0.004}],
             "observe": {"series": ["kinetic_energy"]}}
    with pytest.warns(aggkit.EngineWarning, match="engine dem: " + DT_WARNING) as caught:
        summary = aggkit.run(scene, tmp_path / "run")
    assert [w.filename for w in caught] == [__file__] * len(caught)
    assert summary["engines"]["dem"]["warnings"][0].startswith(DT_WARNING)
    del scene["engine"][0]["dt"]
    assert "warnings" not in _quietly(lambda: aggkit.run(scene, tmp_path / "quiet"))["engines"]["dem"]
