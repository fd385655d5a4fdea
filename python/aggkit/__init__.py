"""aggkit: aggregation kinetics, fast and checked — the Python interface.

The kinetic solvers (CVODE, SNES steady states), DSMC and the particle engines of the C++ suite, on numpy
arrays. Every call goes through the same engines and the same option tables as `aggkit run`: keyword
arguments are the scene keys, and bad input raises ValueError with the message the command line prints.

    import aggkit
    model = aggkit.Model("brownian", a=0.95, lam=0.01, size=2048)
    sol = aggkit.integrate(model, times=np.linspace(1, 2000, 2000))
    sol.moment(0)        # M0(t)
"""
import inspect
import json
import os
import warnings

import numpy as np

# FFTW's measured plans ("wisdom") are remembered across runs only if the caller opts in by setting
# AGGKIT_FFTW_WISDOM to a file before importing aggkit; the command line keeps ~/.cache/aggkit/fftw-wisdom.
os.environ.setdefault("AGGKIT_FFTW_WISDOM", "")

from . import _aggkit  # noqa: E402
from . import _scene  # noqa: E402
from . import analysis  # noqa: E402

__all__ = ["EngineWarning", "kernels", "Model", "Solution", "SteadyState", "EnsembleSolution", "ParticleRun", "integrate", "steady_state", "dsmc",
           "ed", "ts", "dem", "run", "analysis", "engine_options", "rightmost_eigenvalues", "spectrum", "limit_cycle", "locate_hopf", "hopf_normal_form"]


class EngineWarning(RuntimeWarning):
    """What an engine warns about a run that completed (the command line's "aggkit: warning: engine ..." lines,
    summary.json's `warnings`): densities negative beyond the tolerance (cvode), PETSc options no solver read
    (snes), a DEM time step above its contact or damping limit. Each result also keeps them as `warnings`."""


def _warn_engine(label, messages, stacklevel):
    for message in messages:
        warnings.warn(f"engine {label}: {message}", EngineWarning, stacklevel=stacklevel + 1)


def _run_engine(text, kernel, initial, lam, progress):
    """The scene's one engine run by the core; its warnings issued as EngineWarning at the user's line (every
    public function reaches here in two calls: integrate -> Model._run -> _run_engine, ed -> _particle_engine ->
    _run_engine)."""
    raw = _aggkit.run_engine(text, 0, kernel, initial, lam, progress)
    _warn_engine(raw["engine"], raw["warnings"], stacklevel=4)
    return raw


def kernels():
    """The named kernels, from the core's registry (what a scene and Model accept): a list of dicts with
    name, formula and parameters (each a dict with name, allowed and default; default None: required)."""
    return _aggkit.kernels()


def _kernel_lines():
    lines = []
    for k in kernels():
        parameters = ", ".join(p["allowed"] + ("" if p["default"] is None else f" (default {p['default']:g})")
                               for p in k["parameters"])
        lines.append(f"        {k['name']}: {k['formula']}" + (f"; {parameters}" if parameters else ""))
    return "\n".join(lines)


def engine_options(engine):
    """The option table of an engine: a list of dicts with key, default, allowed, doc."""
    return _aggkit.option_table(engine)


def _options_doc(engine):
    rows = engine_options(engine)
    return "\n".join(f"    {r['key']} (default {r['default']}; {r['allowed']}): {r['doc']}" for r in rows)


def _engine_keywords(function, engine):
    """Gives `function` (which passes its **keywords on to `engine`) a signature with the engine's options as
    keyword-only parameters, their defaults those of the option table (None: none, or computed at run time as
    the table's `default` says; a keyword left out is not passed, so the run uses the engine's own default)."""
    signature = inspect.signature(function)
    values = {r["key"]: r["value"] for r in engine_options(engine)}
    # A named parameter that is an option (dsmc's method, runs, seed) shows the table's default.
    named = [p.replace(default=values[p.name]) if p.name in values and p.default is None else p
             for p in signature.parameters.values() if p.kind != inspect.Parameter.VAR_KEYWORD]
    rest = [p for p in signature.parameters.values() if p.kind == inspect.Parameter.VAR_KEYWORD]
    taken = {p.name for p in named}
    options = [inspect.Parameter(r["key"], inspect.Parameter.KEYWORD_ONLY, default=r["value"])
               for r in engine_options(engine) if r["key"] not in taken]
    function.__signature__ = signature.replace(parameters=named + options + rest)
    return function


class Model:
    """A truncated aggregation–shattering model.

    kernel: a name of aggkit.kernels() (listed below, with their parameters) or a Python callable
        K(i, j) -> float (called pair by pair on floats: the core samples it to build a low-rank
        factorisation; K must be symmetric and >= 0).
    lam: the shattering rate λ: a number, {"initial": λ0, "slope": s} (λ0 + s t),
        {"times": [...], "values": [...]} (piecewise linear) or a callable λ(t) >= 0 (called at every rate
        evaluation; checked at 1001 points of [0, t_end]).
    size: the truncation N >= 2.  truncation: "drop" or "cutoff".
    initial: None (unit monodisperse start) or an array n_1.. of densities (padded with zeros to N).
    grid: None (every size 1..N) or {"resolved": K, "ratio": r} (optionally "scheme": "four-moment", the
        default, "three-moment" or "fixed-pivot"): sizes 1..K one by one, then sections growing by r up to N
        (about K + ln(N/K)/ln r unknowns; N may then reach 2^62). Results then hold one entry per section:
        `sizes` are their pivots, `n` the numbers of clusters they stand for, `density` the density per unit
        size those numbers stand for.
    kernel_parameters: the kernel's parameters by name (a=0.95, mu=0.5, A=1, B=0).
    """

    def __init__(self, kernel, lam=0.0, size=None, truncation="drop", initial=None, grid=None, **kernel_parameters):
        if size is None:
            raise ValueError("size = None: the truncation N, an integer >= 2, is required")
        rows = _aggkit.grid_options()  # the core's grid keys: required ones have no value
        if grid is not None and (not isinstance(grid, dict) or not {r["key"] for r in rows if r["value"] is None} <= set(grid)
                                 or not set(grid) <= {r["key"] for r in rows}):
            keys = "; ".join(f"'{r['key']}': {r['allowed']}" + ("" if r["value"] is None else f" (default {r['default']})")
                             for r in rows)
            raise ValueError(f"grid = {grid!r}: None or a dict {{{keys}}}")
        self.grid = None if grid is None else dict(grid)
        self.kernel = kernel
        self.lam = lam
        self.size = size
        self.truncation = truncation
        self.initial = None if initial is None else np.ascontiguousarray(initial, dtype=float)
        self.kernel_parameters = dict(kernel_parameters)
        if callable(kernel) and kernel_parameters:
            raise ValueError("kernel parameters are for named kernels; a callable kernel takes none")

    def _section(self):
        name = "constant" if callable(self.kernel) else self.kernel  # a callable replaces it in the core
        lam = 0.0 if callable(self.lam) else self.lam  # a callable replaces it in the core
        section = {"kernel": {"name": name, **self.kernel_parameters}, "lambda": lam, "size": self.size,
                   "truncation": self.truncation}
        if self.grid is not None:
            section["grid"] = self.grid
        return section

    def _run(self, times, engine, series, distributions, progress):
        observe = {"series": list(series)}
        if distributions:
            observe["distributions"] = [float(t) for t in np.asarray(times, dtype=float).ravel()]
        text = _scene.scene("python", model=self._section(), times=times, engine=engine, observe=observe)
        return _run_engine(text, self.kernel if callable(self.kernel) else None, self.initial,
                           self.lam if callable(self.lam) else None, progress)

    def _text(self):
        return _scene.scene("python", model=self._section(), times=[1.0], engine={"name": "cvode"},
                            observe={"series": ["M0"]})

    def __repr__(self):
        k = "callable" if callable(self.kernel) else self.kernel
        grid = "" if self.grid is None else f", grid={self.grid!r}"
        return f"Model({k!r}, lam={self.lam!r}, size={self.size}, truncation={self.truncation!r}{grid})"


Model.__doc__ += "\n    Kernels (aggkit.kernels()):\n" + _kernel_lines() + "\n"


def _sizes(raw):
    """The sizes of the entries of raw["n"]: 1..N, or a graded grid's pivots."""
    if "sizes" in raw:
        return raw["sizes"]
    return np.arange(1, raw["n"].shape[-1] + 1, dtype=float)


def _moment(n, p, sizes=None):
    k = np.arange(1, n.shape[-1] + 1, dtype=float) if sizes is None else sizes
    return n @ (k ** p)


class Solution:
    """A CVODE solution: t (1-D), n (2-D, one row per time; numpy views of the core's buffer), sizes (the
    size of each column: 1..N, or a graded grid's pivots), density (n per unit size: n itself on the
    uniform grid; on a graded grid the density each pivot's number stands for), mass_leak, statistics
    (dict), moment(p)."""

    def __init__(self, raw):
        self.t = raw["t"]
        self.n = raw["n"]
        self.sizes = _sizes(raw)
        self.density = raw.get("density", raw["n"])
        self.mass_leak = raw["series"]["mass_leak"]
        self.statistics = raw["statistics"]
        self.warnings = raw["warnings"]

    def moment(self, p):
        """M_p(t) = Σ_k k^p n_k(t). The absolute tolerance controls M_p for p <= atol_exponent (3)."""
        return _moment(self.n, p, self.sizes)


def integrate(model, times, progress=None, **options):
    r = model._run(times, {"name": "cvode", **options}, ["M0", "mass_leak"], True, progress)
    return Solution(r)


integrate.__doc__ = """integrate(model, times, progress=None, **options) -> Solution

The truncated equations integrated by SUNDIALS CVODE to each of `times` (increasing, > 0). `progress`, if
given, is called with a line of text at most ten times a second; Ctrl-C interrupts. Options (the cvode
engine's option table):
""" + _options_doc("cvode")
_engine_keywords(integrate, "cvode")


class SteadyState:
    """n (the steady state), sizes (of n's entries), density (per unit size, as Solution.density), residual,
    leak_rate, newton_iterations, statistics."""

    def __init__(self, raw):
        self.n = raw["n"][0]
        self.sizes = _sizes(raw)
        self.density = raw.get("density", raw["n"])[0]
        self.statistics = raw["statistics"]
        self.warnings = raw["warnings"]
        self.residual = self.statistics["relative_residual"]
        self.leak_rate = self.statistics["leak_rate"]
        self.newton_iterations = self.statistics["newton_iterations"]

    def moment(self, p):
        return _moment(self.n, p, self.sizes)


def steady_state(model, progress=None, **options):
    return SteadyState(model._run([1.0], {"name": "snes", **options}, ["M0"], True, progress))


steady_state.__doc__ = """steady_state(model, progress=None, **options) -> SteadyState

The steady state of the truncated equations by PETSc SNES Newton–Krylov (λ > 0, constant). Options:
""" + _options_doc("snes")
_engine_keywords(steady_state, "snes")


class EnsembleSolution:
    """DSMC: t, n (mean distribution, one row per time), series and stderr (dicts of arrays: the means of the
    requested observables over the runs and their standard errors), statistics."""

    def __init__(self, raw):
        self.t = raw["t"]
        self.n = raw["n"]
        self.series = raw["series"]
        self.stderr = raw["stderr"]
        self.statistics = raw["statistics"]
        self.warnings = raw["warnings"]


def dsmc(model, particles, times, method=None, runs=None, seed=None, observables=("M0", "M1", "M2", "M3"), progress=None,
         **options):
    # method, runs and seed keep their places; None (not given) leaves the engine's default.
    given = {"method": method, "runs": runs, "seed": seed}
    engine = {"name": "dsmc", "particles": particles, **{k: v for k, v in given.items() if v is not None}, **options}
    return EnsembleSolution(model._run(times, engine, observables, True, progress))


dsmc.__doc__ = """dsmc(model, particles, times, method="ar", runs=1, seed=1, observables=("M0", "M1", "M2", "M3"),
     progress=None, **options) -> EnsembleSolution (the defaults are the option table's)

Direct Simulation Monte Carlo of the model; with runs > 1 every observable gets its standard error.
Options:
""" + _options_doc("dsmc")
_engine_keywords(dsmc, "dsmc")


class ParticleRun:
    """A particle engine's run: t, series and stderr (dicts of arrays over the realizations), final (dict:
    name -> (mean, standard error)), statistics, and the first realization's final configuration: positions
    (N×3), velocities, masses, radii, cluster (ids), box, periodic."""

    def __init__(self, raw):
        self.t = raw["t"]
        self.series = raw["series"]
        self.stderr = raw["stderr"]
        self.final = raw["final"]
        self.statistics = raw["statistics"]
        self.warnings = raw["warnings"]
        c = raw.get("configuration", {})
        self.positions = c.get("positions")
        self.velocities = c.get("velocities")
        self.masses = c.get("masses")
        self.radii = c.get("radii")
        self.cluster = c.get("cluster")
        self.box = c.get("box")
        self.periodic = c.get("periodic")


def _particle_engine(name, times, particles, series, final, progress, keywords):
    table = {r["key"] for r in engine_options(name)}
    engine = {"name": name}
    section = dict(particles or {})
    for key, v in keywords.items():
        (engine if key in table else section)[key] = v
    observe = {"series": list(series)}
    if final:
        observe["final"] = list(final)
    text = _scene.scene("python", particles=section, times=times, engine=engine, observe=observe)
    return ParticleRun(_run_engine(text, None, None, None, progress))


def ed(times, particles=None, series=("clusters", "kinetic_energy", "M2"), final=("clusters",), progress=None, **keywords):
    return _particle_engine("ed", times, particles, series, final, progress, keywords)


ed.__doc__ = """ed(times, particles=None, series=("clusters", "kinetic_energy", "M2"), final=("clusters",), progress=None,
   **keywords) -> ParticleRun

Event-driven ballistic aggregation of hard discs/spheres. The [particles] keys (dimension, count, radius,
volume_fraction or box, boundary, initial, seed, realizations, ...) come as the dict `particles` or as
keywords; keywords in the engine's option table go to the engine:
""" + _options_doc("ed")
_engine_keywords(ed, "ed")


def rightmost_eigenvalues(model, state, count=6):
    """The `count` rightmost eigenvalues of the Jacobian at `state` (a steady state n_1..n_N) on the mass
    shell (the trivial mass-conservation mode excluded), real part descending: dense for small N,
    shift-invert Arnoldi (Spectra) for large N. A positive real part means the state is unstable."""
    state = np.ascontiguousarray(state.n if isinstance(state, SteadyState) else state, dtype=float)
    return _aggkit.rightmost_eigenvalues(model._text(), model.kernel if callable(model.kernel) else None, state, count)


def hopf_normal_form(model, state):
    """The Hopf bifurcation's normal form at a steady state near lambda_crit (solvers/hopf_normal_form.hpp):
    a dict with mu (the rightmost complex eigenvalue), q (its eigenvector on the size classes, norm 1 on the
    mass shell), c1 (the cubic coefficient of dz/dt = mu z + c1 z|z|^2), lyapunov (the first Lyapunov
    coefficient Re c1 / Im mu), supercritical (lyapunov < 0: a stable cycle is born where the steady state
    loses stability), and the cycle it predicts where Re mu > 0: radius, frequency (angular) and
    m0_half_range (half the range of M0 over the cycle). Raises ValueError for a state of the wrong length and
    RuntimeError where the spectrum has no complex pair."""
    state = np.ascontiguousarray(state.n if isinstance(state, SteadyState) else state, dtype=float)
    return _aggkit.hopf_normal_form(model._text(), model.kernel if callable(model.kernel) else None, state)


def spectrum(model, state, count=6):
    """The rightmost eigenvalues at a steady state (as rightmost_eigenvalues) with the verdict they give: a dict
    with eigenvalues (real part descending), stable (every Re < 0), and kind: "stable node", "stable focus",
    "unstable focus" or "unstable node" from the rightmost eigenvalue."""
    values = rightmost_eigenvalues(model, state, count)
    top = values[0]
    stable = bool(top.real < 0)
    kind = ("stable " if stable else "unstable ") + ("focus" if top.imag != 0 else "node")
    return {"eigenvalues": values, "stable": stable, "kind": kind}


def limit_cycle(model, start=None, period=None, settle=2000.0, **options):
    """A periodic orbit of `model` computed directly: shooting on the period map (CVODE inside) with
    matrix-free Newton–Krylov, a mass row and a Poincaré phase condition; Floquet multipliers by Arnoldi on the
    monodromy matrix (solvers/limit_cycle.hpp). `start`: a state near the cycle (one density per size class)
    with `period` its period guess; without one, the state at the last upward crossing of M0 through its mean
    in a run of the model to t = settle. Options: rtol (1e-10), tolerance (1e-5), max_newton_iterations (30),
    linear_tolerance (1e-3), max_krylov_iterations (80), floquet_count (4), orbit_samples (200).

    Returns a dict: converged, period, m0_min, m0_max (the amplitude of M0), state, sizes, floquet (the
    nontrivial multipliers, |mu| descending), floquet_converged, stable (every nontrivial |mu| < 1), orbit
    (rows t, M0, M1, M2, M3 over one period), newton_iterations, krylov_iterations, period_maps, residual,
    seconds, note. Bad input raises ValueError naming the key."""
    if start is not None:
        start = np.ascontiguousarray(start.n if isinstance(start, SteadyState) else start, dtype=float)
    return _aggkit.limit_cycle(model._text(), model.kernel if callable(model.kernel) else None, start, period,
                               float(settle), dict(options))


def locate_hopf(model, a, lambda_lo, lambda_hi, tolerance=1e-3):
    """λ_crit(a) of the Brownian-type kernel (i/j)^a + (j/i)^a: where the rightmost complex pair of the
    steady state crosses Re = 0 for λ in [lambda_lo, lambda_hi] (continuation in λ). `model` gives N and the
    truncation. Returns a dict with found, lambda_crit, lambda_tolerance, omega, period, note."""
    return _aggkit.locate_hopf(model._text(), a, lambda_lo, lambda_hi, tolerance)


def ts(times, particles=None, series=("clusters", "kinetic_energy", "M2"), final=("clusters",), progress=None, **keywords):
    return _particle_engine("ts", times, particles, series, final, progress, keywords)


ts.__doc__ = """ts(times, particles=None, series=("clusters", "kinetic_energy", "M2"), final=("clusters",), progress=None,
   **keywords) -> ParticleRun

Time-stepping ballistic aggregation (damped Arrow–Hurwicz minimisation) on the same [particles] as ed;
keywords in the engine's option table go to the engine:
""" + _options_doc("ts")
_engine_keywords(ts, "ts")


def dem(times, particles=None, series=("kinetic_energy", "components_fraction"), final=("components_fraction",),
        progress=None, **keywords):
    return _particle_engine("dem", times, particles, series, final, progress, keywords)


dem.__doc__ = """dem(times, particles=None, series=("kinetic_energy", "components_fraction"), final=("components_fraction",),
    progress=None, **keywords) -> ParticleRun

3-D soft-sphere DEM with optional self-gravity on the [particles] keys (per-particle radii and masses, open
clouds, cold starts); keywords in the engine's option table go to the engine:
""" + _options_doc("dem")
_engine_keywords(dem, "dem")


def _seconds(duration, key):
    """A wall-time duration: seconds, or a string with the unit s, m, h or d ("10m", "1.5h")."""
    if isinstance(duration, str):
        units = {"s": 1, "m": 60, "h": 3600, "d": 86400}
        number, scale = (duration[:-1], units[duration[-1]]) if duration[-1:] in units else (duration, 1)
        try:
            return float(number) * scale
        except ValueError:
            raise ValueError(f"{key} = {duration!r}: a duration > 0: seconds, or a number with s, m, h or d") from None
    return float(duration)


def run(scene, out=None, force=False, plot=False, resume=False, checkpoint_every=None):
    """Runs a scene (a path to a TOML file, or a dict with its structure) through the harness, as
    `aggkit run`, and returns summary.json as a dict. `out`: the output folder (None: a scratch folder that
    is removed).

    Checkpoints (`out` needed): `checkpoint_every` (seconds, or "10m", "1.5h") writes each engine's state to
    out/checkpoint/ at output times at least that far apart (None: the engines' own option checkpoint_every);
    `resume=True` continues from the checkpoints in `out` when there are any (the scene must be unchanged,
    else ValueError) and otherwise starts the run with them — so a script that is killed can be run again
    as it is. Outputs of the particle engines and DSMC continue to the bit, CVODE's within its tolerance."""
    if isinstance(scene, (str, os.PathLike)):
        path = os.fspath(scene)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise ValueError(f"scene = {path}: a readable TOML file ({e.strerror})") from None
        source = path
    elif isinstance(scene, dict):
        text, source = _scene.document(scene), "scene"
    else:
        raise ValueError(f"scene = {scene!r}: a path to a scene file or a dict")
    every = 0.0 if checkpoint_every is None else _seconds(checkpoint_every, "checkpoint_every")
    summary = json.loads(_aggkit.run_scene(text, source, "" if out is None else os.fspath(out), force, plot, bool(resume), every))
    for label, engine in summary["engines"].items():
        _warn_engine(label, engine.get("warnings", []), stacklevel=2)
    return summary


def _generic_engine(kind):
    """The function of an engine without one of its own above (a new engine's, until it gets one): a particle
    engine's like ed, a kinetic engine's returning an EnsembleSolution of the requested observables."""
    name = kind["name"]
    if kind["particles"]:
        def run_particles(times, particles=None, series=("kinetic_energy",), final=(), progress=None, **keywords):
            return _particle_engine(name, times, particles, series, final, progress, keywords)
        function = run_particles
        head = f"""{name}(times, particles=None, series=("kinetic_energy",), final=(), progress=None, **keywords) -> ParticleRun"""
    else:
        def run_kinetic(model, times, observables=("M0",), progress=None, **options):
            return EnsembleSolution(model._run(times, {"name": name, **options}, observables, True, progress))
        function = run_kinetic
        head = f"""{name}(model, times, observables=("M0",), progress=None, **options) -> EnsembleSolution"""
    function.__name__ = function.__qualname__ = name
    function.__doc__ = f"""{head}

{kind["description"]}. Options:
""" + _options_doc(name)
    return _engine_keywords(function, name)


# Every engine of the registry is a function of the module: those above by name, any other generically.
for _kind in _aggkit.engine_kinds():
    if _kind["name"] not in globals() and _kind["name"] not in ("cvode", "snes"):
        globals()[_kind["name"]] = _generic_engine(_kind)
        __all__.append(_kind["name"])
