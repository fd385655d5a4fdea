"""Particle engines, scenes, analysis and bad input from Python."""
import os
import signal
import threading

import numpy as np
import pytest

import aggkit
from aggkit import analysis

PARTICLES = dict(dimension=2, count=100, radius=0.5, volume_fraction=0.2, boundary="reflecting")


def test_ed_series_final_values_and_final_configuration():
    r = aggkit.ed([1.0, 2.0, 5.0], PARTICLES, final=["clusters", "contacts"], stop="one_cluster", realizations=3, seed=4)
    assert r.series["clusters"].shape == (3,) and r.stderr["clusters"].shape == (3,)
    assert np.all(np.diff(r.series["clusters"]) <= 0)
    assert r.final["clusters"] == (1.0, 0.0)
    assert r.positions.shape == (100, 3) and r.cluster.shape == (100,)
    assert np.all(r.cluster == 0)  # one cluster at the end
    # The analysis functions on the returned configuration give the engine's own final observable (run 1).
    one = aggkit.ed([1.0], PARTICLES, final=["contacts"], stop="one_cluster", seed=4)
    contacts = analysis.relative_contacts(one.positions[:, :2], 0.5, box=list(one.box[:2]), periodic=False)
    assert contacts == pytest.approx(one.final["contacts"][0], rel=1e-15)
    labels = analysis.contact_clusters(one.positions[:, :2], 0.5)
    sizes, counts = analysis.size_distribution(labels)
    assert list(sizes) == [100] and list(counts) == [1]


def test_ts_runs_to_one_cluster_on_the_same_particles():
    r = aggkit.ts([1.0, 2.0], PARTICLES, final=["clusters"], stop="one_cluster", seed=2)
    assert r.final["clusters"][0] == 1.0
    assert np.all(r.cluster == 0)


def test_dem_binary_collision_returns_the_calibrated_restitution():
    # Two spheres head-on in open space, calibration "exact": the relative speed after the contact is e times
    # the speed before (the file start gives the pair).
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        start = os.path.join(folder, "pair.csv")
        with open(start, "w") as f:
            f.write("x,y,z,vx,vy,vz,radius,mass\n-1.5,0,0,1,0,0,1,1\n1.5,0,0,-1,0,0,1,1\n")
        r = aggkit.dem([3.0], dict(dimension=3, boundary="open", initial={"file": start}), series=["kinetic_energy"],
                       final=[], restitution=0.5, contact_time=0.1, calibration="exact")
    v = r.velocities
    assert (v[1, 0] - v[0, 0]) / 2.0 == pytest.approx(0.5, abs=1e-3)


def test_analysis_on_a_hand_made_configuration():
    # Three touching discs in a row and one apart.
    x = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [10.0, 0.0]])
    labels = analysis.contact_clusters(x, 0.5)
    assert labels[0] == labels[1] == labels[2] != labels[3]
    g = analysis.gyration(x[:3])
    assert g["radius_of_gyration"] == pytest.approx(np.sqrt(2 / 3))
    r, p = analysis.pair_distribution(x, 0.5, r=[1.5, 2.5])
    assert list(p) == pytest.approx([4 / 4, 6 / 4])  # pairs within r, counted from both ends, per particle


def test_run_a_scene_file_and_a_dict():
    here = os.path.dirname(os.path.abspath(__file__))
    scene = os.path.join(here, "..", "..", "validation", "scenes", "constant-exact.toml")
    summary = aggkit.run(scene)
    assert summary["pass"] is True and summary["exit_code"] == 0
    d = {"name": "dict", "model": {"kernel": {"name": "constant"}, "size": 64}, "time": {"end": 2.0},
         "engine": [{"name": "cvode", "rtol": 1e-9}, {"name": "exact"}], "observe": {"series": ["M0"]},
         "compare": {"reference": "exact", "tolerance": {"M0": 1e-5}}}
    assert aggkit.run(d)["comparisons"][0]["pass"] is True


@pytest.mark.parametrize("call, message", [
    (lambda: aggkit.integrate(aggkit.Model("constant", size=64), [1.0], rtol=-1), "engine[0].rtol = -1"),
    (lambda: aggkit.integrate(aggkit.Model("constant", size=64), [1.0], rtl=1e-6), "engine[0].rtl"),
    (lambda: aggkit.integrate(aggkit.Model("gravity", size=64), [1.0]), "model.kernel.name = \"gravity\""),
    (lambda: aggkit.integrate(aggkit.Model("constant", lam=-0.5, size=64), [1.0]), "model.lambda = -0.5"),
    (lambda: aggkit.Model("constant"), "size = None"),
    (lambda: aggkit.integrate(aggkit.Model("constant", lam=lambda t: 0.1 - t, size=64), [1.0]), "lam = callable"),
    (lambda: aggkit.integrate(aggkit.Model("constant", size=64), []), "times = []"),
    (lambda: aggkit.ed([1.0], dict(PARTICLES, radius=-1.0)), "particles.radius = -1"),
    (lambda: aggkit.ed([1.0], PARTICLES, stop="never"), "engine[0].stop"),
    (lambda: aggkit.run({"name": "x"}), "time"),
    (lambda: aggkit.run("/no/such/scene.toml"), "/no/such/scene.toml"),
    (lambda: analysis.gyration(np.zeros((3, 4))), "positions"),
])
def test_bad_input_raises_ValueError_with_the_command_line_message(call, message):
    with pytest.raises(ValueError) as e:
        call()
    assert message in str(e.value)


def test_ctrl_c_interrupts_a_long_run_within_a_second():
    import time
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        aggkit.dsmc(aggkit.Model("constant", lam=0.5, size=100), particles=2_000_000, times=[1e6], observables=["M0"])
    assert time.monotonic() - started < 0.5 + 1.5
    timer.join()


def _literal(row):
    """The default of an option row as a Python value, or None for an expression or an absence ("rtol/100")."""
    text = row["default"]
    if text in ("true", "false"):
        return text == "true"
    if row["allowed"].startswith("one of "):
        return text
    try:
        return int(text) if row["allowed"].startswith("an integer") else float(text)
    except ValueError:
        return None


def test_each_default_in_help_is_the_value_the_engine_runs_with():
    # The function's help lists every option; and passing an option at the default that help shows gives the
    # very same results as leaving it out (a default shown wrongly, or an option ignored, changes them).
    model = aggkit.Model("constant", lam=0.5, size=32)
    small = dict(dimension=2, count=16, radius=0.5, volume_fraction=0.2, boundary="reflecting")
    runs = {"cvode": (aggkit.integrate, lambda **o: aggkit.integrate(model, [0.5, 2.0], **o).n),
            "snes": (aggkit.steady_state, lambda **o: aggkit.steady_state(model, **o).n),
            "ed": (aggkit.ed, lambda **o: aggkit.ed([0.5, 1.0], small, seed=3, **o).series["clusters"])}
    checked = 0
    for name, (function, run) in runs.items():
        plain = np.array(run())
        for row in aggkit.engine_options(name):
            assert f"{row['key']} (default {row['default']};" in function.__doc__
            value = _literal(row)
            if value is None:
                continue
            np.testing.assert_array_equal(np.array(run(**{row["key"]: value})), plain, err_msg=f"{name}.{row['key']} = {value!r}")
            checked += 1
    assert checked >= 20  # 10 of cvode, 4 of snes, 4 of ed today

CHECKPOINT_SCENE = """name = "python-checkpoint"
[particles]
dimension = 3
count = 100
radius = 1.0
mass = 1.0
boundary = "open"
initial = { cloud = "cube", volume_fraction = 0.05, speed = 0.3 }
seed = 3
realizations = 2
[time]
end = 6.0
every = 0.25
[[engine]]
name = "dem"
restitution = 0.5
contact_time = 0.05
friction = 0.5
gravity = { G = 1.0, method = "direct" }
[observe]
series = ["clusters", "kinetic_energy"]
final = ["clusters"]
"""


def _text(path):
    with open(path) as f:
        return f.read()


def test_run_resumes_a_stopped_run_to_the_same_outputs(tmp_path):
    import subprocess
    import time
    scene = tmp_path / "scene.toml"
    scene.write_text(CHECKPOINT_SCENE)
    aggkit.run(scene, tmp_path / "whole")
    # The command line (beside the module in the build tree) stopped by SIGTERM after its first checkpoint.
    cli = os.path.join(os.path.dirname(aggkit.__file__), os.pardir, os.pardir, "aggkit")
    out = tmp_path / "stopped"
    process = subprocess.Popen([cli, "run", str(scene), "--out", str(out), "--quiet", "--no-plot", "--checkpoint-every", "0.001"],
                               stderr=subprocess.DEVNULL)
    while not (out / "checkpoint" / "dem.state").exists() and process.poll() is None:
        time.sleep(0.002)
    process.send_signal(signal.SIGTERM)
    assert process.wait() == 4  # the last checkpoint written
    summary = aggkit.run(scene, out, resume=True)
    assert summary["engines"]["dem"]["statistics"]["resumed_realizations"] >= 1  # continued, not run again
    assert _text(out / "dem" / "series.csv") == _text(tmp_path / "whole" / "dem" / "series.csv")
    assert not (out / "checkpoint").exists()
    # resume=True without checkpoints starts the run (with them), to the same outputs.
    fresh = tmp_path / "fresh"
    aggkit.run(scene, fresh, resume=True, checkpoint_every="1h")
    assert _text(fresh / "dem" / "series.csv") == _text(tmp_path / "whole" / "dem" / "series.csv")


def test_run_refuses_a_resume_of_a_changed_scene_and_checkpoints_without_a_folder(tmp_path):
    import subprocess
    import time
    scene = tmp_path / "scene.toml"
    scene.write_text(CHECKPOINT_SCENE)
    cli = os.path.join(os.path.dirname(aggkit.__file__), os.pardir, os.pardir, "aggkit")
    out = tmp_path / "stopped"
    process = subprocess.Popen([cli, "run", str(scene), "--out", str(out), "--quiet", "--no-plot", "--checkpoint-every", "0.001"],
                               stderr=subprocess.DEVNULL)
    while not (out / "checkpoint" / "dem.state").exists() and process.poll() is None:
        time.sleep(0.002)
    process.send_signal(signal.SIGTERM)
    assert process.wait() == 4
    scene.write_text(CHECKPOINT_SCENE.replace("seed = 3", "seed = 4"))
    with pytest.raises(ValueError, match="resume"):
        aggkit.run(scene, out, resume=True)
    with pytest.raises(ValueError, match="output folder"):
        aggkit.run(scene, None, resume=True)
    with pytest.raises(ValueError, match="checkpoint_every"):
        aggkit.run(scene, tmp_path / "x", checkpoint_every="10y")
    # The particle engines take checkpoint_every as an option; without an output folder it cannot be used.
    for engine in ("ed", "ts", "dem"):
        assert [o["value"] for o in aggkit.engine_options(engine) if o["key"] == "checkpoint_every"] == [0.0]
    with pytest.raises(ValueError, match="output folder"):
        aggkit.dem([1.0], dict(dimension=3, count=20, radius=1.0, mass=1.0, boundary="open",
                               initial={"cloud": "cube", "volume_fraction": 0.05, "speed": 0.3}),
                   restitution=0.5, contact_time=0.05, checkpoint_every=5)
