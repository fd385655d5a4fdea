#!/usr/bin/python3
"""Scene fuzzer: mutates the shipped scenes and checks how `aggkit run` / `aggkit scan` handle them.

    /usr/bin/python3 tests/fuzz/fuzz_scenes.py build/aggkit --seed 1 --budget 45 --timeout 10 --out DIR

Every shipped scene in validation/scenes/ is first shrunk (model.size, particles.count, DSMC particles,
time.end, realizations, scan grids ... capped) so that a valid scene runs in a fraction of a second: the
point is to exercise input handling, not to run long physics. Each execution then applies one mutation,
either to one key of the parsed scene (delete it, set a number to 0, -1, 1e-300, 1e300, nan, inf, a huge
integer, a float where an integer is expected, a string, an empty or nested table, a long string,
control characters, another valid or invalid name, an unknown or misplaced key, a section from another
scene) or to the serialised text (truncate at a byte, duplicate or drop a line, insert random bytes, deep
nesting, an oversized file), and runs aggkit on the result with a fresh --out folder. The contract checked
is the CLI's exit status (0 pass, 1 comparison/engine failure, 2 bad input naming key, value and what is
allowed, 3 internal error). A finding is:

    crash            killed by a signal (negative return code) or an exit status outside 0..3
    internal-error   exit status 3
    timeout          no exit within the per-run timeout (a hang, or a valid scene that runs far too long)
    bad-message      exit 2 whose stderr lacks the "KEY = VALUE: ALLOWED" form (no " = " and ": ")
    missing-summary  exit 0/1 with summary.json (scan.csv for a scan) missing or empty
    invalid-summary  exit 0/1 with a summary.json that is not strict JSON (NaN/Infinity, truncated ...)
    output-on-bad-input  exit 2 that left a summary.json (scan.csv) in the fresh --out folder

Findings are deduplicated by (kind, mutated key path, exit status); the output folder receives
findings.json (scene text, command, exit status, stderr tail, the values that triggered it), one
finding-NN.toml per finding to rerun by hand, and stats.json. Exit status 0 without findings, 1 with.

The sequence of mutants depends on the seed only; the time budget decides how long a prefix of it runs.
Python standard library only (tomllib: Python >= 3.11); run it with /usr/bin/python3.
"""
import argparse
import copy
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import time
import tomllib

# ---------------------------------------------------------------------------------------------------------
# TOML serialisation. tomllib only reads, so the mutants are written by this small writer: top-level
# values, then one [section] per table and one [[name]] per table of an array of tables; anything deeper is
# written inline. Raw values are emitted verbatim: they carry what Python values cannot (dates, hex
# integers, integers beyond 64 bits, raw control characters).


class Raw(str):
    """A TOML value written as is."""


BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def toml_string(s):
    out = ['"']
    for ch in s:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif ch == "\r":
            out.append("\\r")
        elif code < 0x20 or code == 0x7F:
            out.append("\\u%04X" % code)
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def toml_key(k):
    return k if BARE_KEY.fullmatch(k) else toml_string(k)


def toml_float(x):
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    text = repr(x)  # shortest round-trip form: 1e-300, 0.5, 1e+300, 2.0
    if not any(c in text for c in ".eE"):
        text += ".0"
    return text


def toml_value(v):
    if isinstance(v, Raw):
        return str(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return toml_float(v)
    if isinstance(v, str):
        return toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(e) for e in v) + "]"
    if isinstance(v, dict):
        if not v:
            return "{}"
        return "{ " + ", ".join(toml_key(k) + " = " + toml_value(e) for k, e in v.items()) + " }"
    return str(v)  # dates and times as tomllib returns them print in TOML form


def is_table_array(v):
    return isinstance(v, list) and bool(v) and all(isinstance(e, dict) for e in v)


def toml_dump(doc):
    lines = []
    for k, v in doc.items():
        if not isinstance(v, dict) and not is_table_array(v):
            lines.append(f"{toml_key(k)} = {toml_value(v)}")
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append("")
            lines.append(f"[{toml_key(k)}]")
            lines.extend(f"{toml_key(sk)} = {toml_value(sv)}" for sk, sv in v.items())
        elif is_table_array(v):
            for table in v:
                lines.append("")
                lines.append(f"[[{toml_key(k)}]]")
                lines.extend(f"{toml_key(sk)} = {toml_value(sv)}" for sk, sv in table.items())
    return "\n".join(lines).lstrip("\n") + "\n"


# ---------------------------------------------------------------------------------------------------------
# Shrinking: caps that keep a valid scene (and most mutants of it) well under a second.

MAX_SIZE = 64          # model.size
MAX_PARTICLES = 36     # particles.count (a square: the 2-D lattice start)
MAX_DSMC = 200         # dsmc particles
MAX_RUNS = 4           # dsmc runs, particles.realizations
MAX_END = 2.0          # time.end of a run scene
MAX_OUTPUTS = 20       # outputs of an `every` grid
SCAN_END = 40.0        # a scan needs >= 16 outputs in the classified tail
SCAN_GRID = 2          # values per scan axis


def scale_times(values, factor):
    return [v * factor if isinstance(v, (int, float)) and not isinstance(v, bool) else v for v in values]


def shrink(doc, is_scan):
    model = doc.get("model")
    if isinstance(model, dict) and isinstance(model.get("size"), int):
        model["size"] = min(model["size"], MAX_SIZE)
    particles = doc.get("particles")
    if isinstance(particles, dict):
        if isinstance(particles.get("count"), int):
            particles["count"] = min(particles["count"], MAX_PARTICLES)
        if isinstance(particles.get("realizations"), int):
            particles["realizations"] = min(particles["realizations"], 2)
    t = doc.get("time")
    if isinstance(t, dict) and isinstance(t.get("end"), (int, float)):
        end = float(t["end"])
        new_end = SCAN_END if is_scan else min(end, MAX_END)
        factor = new_end / end if end > 0 else 1.0
        t["end"] = new_end
        # Output and distribution times scale with the end time, so that they stay valid and matching.
        if isinstance(t.get("outputs"), list):
            t["outputs"] = scale_times(t["outputs"], factor)
        every = None
        if isinstance(t.get("every"), (int, float)) and t["every"] > 0:
            every = 1.0 if is_scan else new_end / min(MAX_OUTPUTS, max(1, math.floor(end / t["every"])))
            t["every"] = every
        observe = doc.get("observe")
        if isinstance(observe, dict) and isinstance(observe.get("distributions"), list):
            times = scale_times(observe["distributions"], factor)
            if every:  # onto the grid k * every, computed as aggkit computes it
                times = sorted({max(1, round(x / every)) * every for x in times})
            observe["distributions"] = times
        if isinstance(observe, dict) and isinstance(observe.get("window"), list):
            observe["window"] = [0.0, new_end]  # the series measures need >= 16 outputs in it: the whole run
    observe = doc.get("observe")
    if isinstance(observe, dict) and observe.get("snapshots") is True:
        observe["snapshots"] = False  # the snapshot PNG starts matplotlib: 0.7 s a run
    for engine in doc.get("engine", []) if isinstance(doc.get("engine"), list) else []:
        if not isinstance(engine, dict):
            continue
        if engine.get("name") == "dsmc":
            engine["particles"] = min(engine.get("particles", MAX_DSMC), MAX_DSMC)
            engine["runs"] = min(engine.get("runs", 1), MAX_RUNS)
            engine["threads"] = 1  # one core: the fuzzer shares the machine
        if engine.get("name") == "ed":
            engine["threads"] = 1
    scan = doc.get("scan")
    if isinstance(scan, dict) and isinstance(scan.get("hopf_grid"), dict):
        # The converged λ_crit curve on a fine graded grid takes a minute per a: a coarse one keeps the
        # same code paths (N doubling, 2K and (r-1)/2 refinements) at a fraction of a second.
        scan["hopf_grid"] = {"resolved": 8, "ratio": 1.3}
        # Small a and λ put λ_crit near 1e-7 and below, where the curve doubles N towards 2^60 (seconds per
        # a even on the coarse grid): keep the lower ends of a shipped scan's ranges where λ_crit is ≥ 1e-3.
        for axis, lowest in (("a", 0.8), ("lambda", 1e-3)):
            grid = scan.get(axis)
            if isinstance(grid, dict) and isinstance(grid.get("from"), (int, float)) and not isinstance(grid.get("from"), bool):
                grid["from"] = max(grid["from"], lowest)
    if isinstance(scan, dict):
        for axis in ("a", "lambda"):
            grid = scan.get(axis)
            if isinstance(grid, list):
                scan[axis] = grid[:SCAN_GRID]
            elif isinstance(grid, dict) and isinstance(grid.get("count"), int):
                grid["count"] = min(grid["count"], SCAN_GRID)
    return doc


# ---------------------------------------------------------------------------------------------------------
# Vocabulary: names aggkit accepts, harvested from `aggkit run --help` and `aggkit kernels` (so that new
# engines, options and observables are fuzzed without editing this file), plus fixed lists.

FIXED_NAMES = [
    "cvode", "exact", "dsmc", "ed", "snes", "constant", "sum", "product", "linear", "genproduct", "ballistic",
    "brownian", "drop", "cutoff", "monodisperse", "table", "periodic", "reflecting", "open", "square", "cubic",
    "cube", "sphere", "uniform", "normal", "lognormal", "one_cluster", "log", "linear", "M0", "M2", "n1",
    "bdf-gmres", "bdf-dense", "adams", "fast", "direct", "monomer", "jacobi", "none", "ar",
]
FIXED_KEYS = [
    "name", "label", "kernel", "lambda", "size", "truncation", "initial", "end", "outputs", "every", "series",
    "distributions", "final", "snapshots", "reference", "tolerance", "dimension", "count", "radius", "mass",
    "volume_fraction", "box", "boundary", "thermalize", "seed", "realizations", "a", "mu", "A", "B", "kind",
    "density", "n", "relative", "stderr", "from", "to", "spacing", "tail", "stability", "truncation_check",
    "points", "lambda_crit", "lattice", "cloud", "file", "speed", "directions", "components", "distribution",
    "mean", "sd", "min", "max", "initial", "slope", "times", "values", "stop", "clusters",
]


def harvest_vocabulary(binary):
    names, keys = set(FIXED_NAMES), set(FIXED_KEYS)
    try:
        text = subprocess.run([binary, "run", "--help"], capture_output=True, text=True, timeout=30).stdout
        text += subprocess.run([binary, "kernels"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        text = ""
    for line in text.splitlines():
        m = re.match(r"^  ([a-z][a-z0-9_]*): ", line)
        if m:
            names.add(m.group(1))
        m = re.match(r"^    ([a-z_]+) \(default ([^;]*); (.*?)\): ", line)
        if m:
            keys.add(m.group(1))
            one_of = re.match(r"one of (.*)", m.group(3))
            if one_of:
                names.update(w.strip() for w in one_of.group(1).split(","))
        m = re.match(r"^  ([a-z][a-z_]*)\s+K_ij", line)
        if m:
            names.add(m.group(1))
        m = re.match(r"^  ([A-Za-z_]+)(<[pk]>)?: ", line)
        if m:
            if m.group(2) == "<p>":
                names.update([m.group(1) + "0", m.group(1) + "1.5", m.group(1) + "3", m.group(1) + "-1"])
            elif m.group(2) == "<k>":
                names.update([m.group(1) + "1", m.group(1) + "64", m.group(1) + "65", m.group(1) + "0"])
            else:
                names.add(m.group(1))
    return sorted(n for n in names if n), sorted(keys)


# ---------------------------------------------------------------------------------------------------------
# Values a mutation can put at a key.

LONG_STRING = "x" * 100_000
CONTROL_STRING = "a\x00b\x01c\x1b[31m\x7f\nd\te\r"

NUMBERS = [0, -1, 1e-300, 1e300, math.nan, math.inf, -math.inf, 2**63 - 1, -(2**63), 0.0, -0.0, 1.5, 2.5,
           5e-324, 2**53 + 1, 4294967296, 1, 2, 3]
OTHER_VALUES = ["", "x", LONG_STRING, CONTROL_STRING, "\u03a9\u00e9\U0001F600", "../../../../etc/passwd", True,
                False, [], {}, {"a": {"b": {"c": 1}}}, [[1, 2], [3]], [1, "a", True], [math.nan],
                Raw("1979-05-27T07:32:00Z"), Raw("1979-05-27"), Raw("07:32:00"), Raw("0xDEADBEEF"),
                Raw("9223372036854775808"), Raw("-9223372036854775809"), Raw("1e400"), Raw("-nan"),
                Raw('"a\x01b"'), Raw("'literal \\n'"), Raw('"""multi\nline"""')]
BAD_NAMES = ["", " ", "CVODE", "cvode ", " cvode", "cvode\x00", "Cvode", "unknown", "M", "M-1", "Mnan", "Minf",
             "M1e400", "n", "n0", "n-1", "n1e20", "n99999999999999999999", "M0 ", "mass leak", LONG_STRING,
             "\u00e9", "a/b", "..", "/"]
UNKNOWN_KEYS = ["unknown_key", "Name", "", " ", "a.b", "\u00f1", "k" * 10_000, "size ", "\x01"]


# Further forms of particular keys, by the last component of their path: most are valid somewhere (the
# [particles] starts and laws, λ(t) forms, kernels with parameters, ED stop rules), some just outside
# what is allowed. They reach the checks behind the type test, which random values rarely pass.
KEY_FORMS = {
    "initial": [
        {"cloud": "cube", "speed": 1.0}, {"cloud": "sphere", "size": 4.0}, {"cloud": "sphere", "volume_fraction": 0.2},
        {"cloud": "cube", "components": "uniform"}, {"cloud": "sphere", "size": 1e-300}, {"cloud": "cube", "size": 4.0},
        {"cloud": "sphere", "volume_fraction": 0.9}, {"lattice": "cubic"}, {"speed": 0.0}, {"speed": 1.0, "components": "uniform"},
        {"file": "start-2d.csv"}, {"file": "start-3d.csv"}, {"file": "start-bad.csv"}, {"file": "start-overlap.csv"},
        {"file": "start-outside.csv"}, {"file": "empty.csv"}, {"file": "header-only.csv"}, {"file": "missing.csv"},
        {"file": "/dev/null"}, {"file": "/dev/zero"}, {"file": "."}, {"file": ""}, {"file": "start-2d.csv", "speed": 1.0},
        {"kind": "table", "n": [1.0, 0.5, 0.25]}, {"kind": "table", "n": []}, {"kind": "table", "n": [0.0]},
        {"kind": "table", "n": [1.0] * 65}, {"kind": "table", "n": [-1.0, 2.0]}, {"kind": "monodisperse", "density": 2.0},
        {"kind": "monodisperse", "density": 1e300},
    ],
    # whole [particles] sections: the other starts, boundaries and laws, each within one key of the scene
    "particles": [
        {"dimension": 3, "count": 27, "radius": 0.2, "volume_fraction": 0.1, "boundary": "periodic",
         "initial": {"lattice": "cubic", "components": "uniform"}},
        {"dimension": 2, "count": 36, "radius": {"distribution": "uniform", "min": 0.1, "max": 0.3}, "box": 10.0,
         "boundary": "reflecting", "initial": {"cloud": "cube"}},
        {"dimension": 2, "count": 36, "radius": 0.2, "boundary": "open", "initial": {"cloud": "sphere", "volume_fraction": 0.2}},
        {"dimension": 2, "box": 5.0, "boundary": "periodic", "initial": {"file": "start-2d.csv"}},
        {"dimension": 3, "box": [2.0, 2.0, 2.0], "boundary": "reflecting", "initial": {"file": "start-3d.csv"}},
        {"dimension": 2, "count": 36, "radius": 0.2, "box": 10.0, "boundary": "periodic",
         "initial": {"cloud": "sphere", "size": 8.0, "speed": 2.0}, "thermalize": 5, "mass": {"density": 2.0}},
        {"dimension": 3, "count": 30, "radius": 0.2, "volume_fraction": 0.37, "boundary": "periodic", "initial": {"cloud": "cube"}},
        {"dimension": 2, "count": 2, "radius": 0.2, "box": [1.0, 1.0], "boundary": "reflecting", "realizations": 3},
    ],
    "radius": [
        {"distribution": "normal", "mean": 0.2, "sd": 0.02, "min": 0.1}, {"distribution": "lognormal", "mean": 0.2, "sd": 0.05},
        {"distribution": "uniform", "min": 0.1, "max": 0.3}, {"distribution": "normal", "mean": 0.2, "sd": 0.0, "min": 0.1},
        {"distribution": "normal", "mean": 0.2, "sd": 1e-300, "min": 0.1}, {"distribution": "uniform", "min": 0.3, "max": 0.1},
        {"distribution": "lognormal", "mean": 0.2, "sd": 1e300}, {"distribution": "normal", "mean": 0.2, "sd": 0.1, "min": 0.5},
        {"distribution": "uniform", "min": 0.2, "max": 0.2}, {"distribution": "normal", "mean": 1e300, "sd": 1.0, "min": 1.0},
    ],
    "mass": [{"density": 2.5}, {"density": 0.0}, {"density": 1e300}, {"distribution": "uniform", "min": 0.5, "max": 1.5},
             {"distribution": "lognormal", "mean": 1.0, "sd": 0.5}, {"density": 1.0, "mean": 1.0}],
    "lambda": [{"initial": 0.01, "slope": 0.001}, {"initial": 0.01, "slope": -1.0}, {"times": [0.0, 1.0], "values": [0.01, 0.02]},
               {"times": [], "values": []}, {"times": [1.0, 0.0], "values": [0.01, 0.02]}, {"times": [0.0], "values": [0.1, 0.2]},
               {"initial": 0.01}, {"initial": 0.01, "slope": 0.0, "times": [0.0]}],
    "boundary": ["open", "periodic", "reflecting"],
    "box": [[20.0, 10.0], 20.0, [20.0, 10.0, 5.0], [1e-300, 1e-300], [1e300, 1e300], 0.5],
    "stop": [{"clusters": 2}, {"clusters": 0}, {"clusters": 36}, {"clusters": 37}, "one_cluster", {}],
    "kernel": [{"name": "linear", "A": 1.0, "B": 0.5}, {"name": "genproduct", "mu": 0.5}, {"name": "brownian", "a": 0.5},
               {"name": "product"}, {"name": "ballistic"}, {"name": "constant", "a": 1.0}, {"name": "linear", "A": -1.0},
               {"name": "genproduct", "mu": 2.0}, {"name": "brownian"}],
    "tolerance": [{"M0": {"relative": 0.1}}, {"M0": 0.1}, {"M0": {"stderr": 3}}, {"M0": {}}, {"nope": 1.0}],
    "truncation_check": [{"points": [[0.95, 0.01]]}, {"points": [[2.0, -1.0]], "lambda_crit": True}, {"points": []},
                         {"points": [[0.95]]}, {"lambda_crit": True}],
    "series": [["largest_cluster", "orientation", "radius_of_gyration"], ["M1.5", "n64"], ["n65"], ["pair_distribution"],
               ["M0", "M0"], ["clusters", "contacts"], "M2", "M1"],
    "final": [["pair_distribution"], ["orientation", "radius_of_gyration", "largest_cluster"], ["M0"], ["clusters", "clusters"]],
    "dimension": [3, 2, 1, 4],
    "a": [[0.9, 0.95], [1.0, 0.9], [], [2.0], {"from": 1.0, "to": 0.5, "count": 3}, {"from": 0.5, "to": 0.5, "count": 1}],
    "distributions": [[2.0], [2.0, 2.0], [0.0], []],
    "outputs": [[1.0, 2.0], [2.0, 1.0], [1e-300, 2.0], [0.5, 0.5], []],
}

# Start files for {file = ...}: written into the folder of the mutant scene, which relative paths are read
# from. 36 particles match particles.count of the shrunk ballistic-ed scene (a 6 x 6 grid in its box).
START_FILES = {
    "start-2d.csv": "x,y,vx,vy,radius,mass\n" + "".join(
        f"{0.4 + 0.75 * i},{0.4 + 0.75 * j},{(-1) ** i * 0.5},{(-1) ** j * 0.5},0.2,1.0\n" for i in range(6) for j in range(6)),
    "start-3d.csv": "x,y,z,vx,vy,vz,radius,mass\n" + "".join(
        f"{0.4 + 0.75 * i},{0.4 + 0.75 * j},{0.4 + 0.75 * k},1.0,0.0,-1.0,0.2,1.0\n"
        for i in range(2) for j in range(2) for k in range(2)),
    "start-bad.csv": "x,y,vx,vy,radius,mass\n1,2,3\nnan,inf,1,1,0.2,1\n1e999,0,0,0,0.2,1\nx,y,z,w,v,u\n0.5,0.5,0,0,-0.2,0\n",
    "start-overlap.csv": "x,y,vx,vy,radius,mass\n1.0,1.0,1,0,0.2,1\n1.0,1.1,-1,0,0.2,1\n",
    "start-outside.csv": "x,y,vx,vy,radius,mass\n-5.0,1.0,1,0,0.2,1\n1e300,1.1,-1,0,0.2,1\n",
    "empty.csv": "",
    "header-only.csv": "x,y,vx,vy,radius,mass\n",
}


def numeric_variants(v):
    """Values derived from the current number: a float where an integer is expected and the converse,
    sign flips, off-by-one, scale changes. Integers are not scaled by moderate factors: a size or particle
    count ten times the shrunk one is still valid and can take seconds (a scan at N = 640 takes 12 s), which
    would turn the per-run timeout into a measure of machine load."""
    out = []
    if isinstance(v, bool):
        return out
    if isinstance(v, int):
        out += [float(v), v + 0.5, v + 1, v - 1, -v, v * 10**12, 0]
    elif isinstance(v, float) and math.isfinite(v):
        out += [-v, v * 10, v / 1e6, v * 1e12, math.nextafter(v, math.inf), v * (1 + 1e-12)]
        if v == int(v) and abs(v) < 2**62:
            out.append(int(v))  # an integer where a float is written
    return out


# ---------------------------------------------------------------------------------------------------------
# Paths into the document: tuples of keys and indices.


def all_paths(node, prefix=()):
    yield prefix, node
    if isinstance(node, dict):
        for k, v in node.items():
            yield from all_paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from all_paths(v, prefix + (i,))


def get_at(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def display_path(doc, path):
    """model.kernel.name, engine[dsmc-fast].particles, time.outputs[*]: tables of an array of tables are
    named by their label (else their name), other indices collapse, so that findings dedup by key rather
    than by position."""
    text, node = "", doc
    for p in path:
        if isinstance(p, int):
            item = node[p] if isinstance(node, list) and p < len(node) else None
            tag = item.get("label", item.get("name")) if isinstance(item, dict) else None
            if isinstance(tag, str) and BARE_KEY.fullmatch(tag):
                text += f"[{tag}]"
            else:
                text += "[*]"
            node = item
        else:
            text += ("." if text else "") + (p if BARE_KEY.fullmatch(p) else json.dumps(p[:40]))
            node = node.get(p) if isinstance(node, dict) else None
    return text or "(root)"


def short(v, limit=120):
    if isinstance(v, Raw):
        text = "raw:" + str(v)
    elif isinstance(v, float):
        text = toml_float(v)
    elif isinstance(v, bool):
        text = "true" if v else "false"
    else:
        text = json.dumps(v, ensure_ascii=True) if not isinstance(v, int) else str(v)
    if len(text) > limit:
        text = text[:limit] + f"...({len(text)} chars)"
    return text


# ---------------------------------------------------------------------------------------------------------
# Mutations. Each returns (description, key path for deduplication, mutant bytes).


class Mutator:
    def __init__(self, rng, scenes, names, keys):
        self.rng, self.scenes, self.names, self.keys = rng, scenes, names, keys

    def pick_value(self, current, key=None):
        forms = KEY_FORMS.get(key) if isinstance(key, str) else None
        if forms and self.rng.random() < 0.4:
            return copy.deepcopy(self.rng.choice(forms))
        r = self.rng.random()
        if r < 0.35:
            return self.rng.choice(NUMBERS)
        if r < 0.55 and numeric_variants(current):
            return self.rng.choice(numeric_variants(current))
        if r < 0.7:
            return self.rng.choice(self.names + BAD_NAMES)
        if r < 0.8:
            return self.random_section_value()
        return self.rng.choice(OTHER_VALUES)

    def random_section_value(self):
        """A value taken from a shipped scene (another section, engine table or array): type-correct
        somewhere else, so it reaches checks deeper than the type test."""
        name, doc, _ = self.rng.choice(self.scenes)
        candidates = [v for p, v in all_paths(doc) if p]
        return copy.deepcopy(self.rng.choice(candidates))

    def mutate_doc(self, doc):
        paths = [p for p, _ in all_paths(doc)]
        path = self.rng.choice(paths)
        target = get_at(doc, path)
        shown = display_path(doc, path)
        ops = []
        if path:
            ops += ["delete", "set", "set", "set"]
        if isinstance(target, str):
            ops += ["rename", "rename"]
        if isinstance(target, (int, float)) and not isinstance(target, bool):
            ops += ["number", "number"]
        if isinstance(target, dict):
            ops += ["add_key", "add_key"]
        if isinstance(target, list):
            ops += ["array", "array"]
        if path == ():
            ops += ["graft", "duplicate_engine"]
        op = self.rng.choice(ops)
        parent = get_at(doc, path[:-1]) if path else None
        last = path[-1] if path else None
        if op == "delete":
            if isinstance(parent, dict):
                del parent[last]
            else:
                parent.pop(last)
            return f"delete {shown}", shown, doc
        if op in ("set", "number", "rename"):
            if op == "number":
                value = self.rng.choice(NUMBERS + numeric_variants(target))
            elif op == "rename":
                value = self.rng.choice(self.names + BAD_NAMES)
            else:
                value = self.pick_value(target, last)
            parent[last] = value
            return f"set {shown} = {short(value)}", shown, doc
        if op == "add_key":
            r = self.rng.random()
            key = self.rng.choice(UNKNOWN_KEYS) if r < 0.4 else self.rng.choice(self.keys)
            value = self.pick_value(None, key)
            target[key] = value
            where = shown if path else ""
            key_shown = key if BARE_KEY.fullmatch(key) else json.dumps(key[:40])
            return (f"add {(where + '.') if where else ''}{key_shown} = {short(value)}",
                    f"{where + '.' if where else ''}+{key_shown if len(key_shown) < 50 else 'long'}", doc)
        if op == "array":
            kind = self.rng.choice(["empty", "append", "duplicate", "reverse", "long", "nested"])
            if kind == "empty":
                target.clear()
            elif kind == "append":
                target.append(self.pick_value(target[-1] if target else None))
            elif kind == "duplicate" and target:
                target.append(copy.deepcopy(self.rng.choice(target)))
            elif kind == "reverse":
                target.reverse()
            elif kind == "long":
                element = target[-1] if target and not isinstance(target[-1], dict) else 1.0
                target.extend([element] * 5000)
            else:
                target.append(list(target))
            return f"array {kind} {shown}", shown + "[]", doc
        if op == "graft":
            name, other, _ = self.rng.choice(self.scenes)
            section = self.rng.choice([k for k in other if k != "name"])
            doc[section] = copy.deepcopy(other[section])
            return f"graft [{section}] from {name}", f"graft:{section}", doc
        if op == "duplicate_engine" and isinstance(doc.get("engine"), list) and doc["engine"]:
            doc["engine"].append(copy.deepcopy(self.rng.choice(doc["engine"])))
            return "duplicate an [[engine]]", "engine[+]", doc
        return self.mutate_doc(doc)

    def mutate_text(self, data):
        rng = self.rng
        kind = rng.choice(["truncate", "truncate", "duplicate_line", "drop_line", "swap_lines", "insert_bytes",
                           "flip_byte", "deep_nesting", "oversized", "bom", "crlf"])
        lines = data.split(b"\n")
        if kind == "truncate":
            data = data[: rng.randrange(len(data) + 1)]
        elif kind == "duplicate_line":
            i = rng.randrange(len(lines))
            lines.insert(i, lines[i])
            data = b"\n".join(lines)
        elif kind == "drop_line":
            del lines[rng.randrange(len(lines))]
            data = b"\n".join(lines)
        elif kind == "swap_lines" and len(lines) > 1:
            i = rng.randrange(len(lines) - 1)
            lines[i], lines[i + 1] = lines[i + 1], lines[i]
            data = b"\n".join(lines)
        elif kind == "insert_bytes":
            junk = bytes(rng.choice([0, 1, 0x1B, 0x22, 0x27, 0x5B, 0x5D, 0x7B, 0x7D, 0x3D, 0x23, 0x5C, 0x0A,
                                     0x7F, 0x80, 0xC3, 0xE2, 0xFF, rng.randrange(256)])
                         for _ in range(rng.randint(1, 16)))
            at = rng.randrange(len(data) + 1)
            data = data[:at] + junk + data[at:]
        elif kind == "flip_byte" and data:
            at = rng.randrange(len(data))
            data = data[:at] + bytes([data[at] ^ (1 << rng.randrange(8))]) + data[at + 1:]
        elif kind == "deep_nesting":
            # around the parser's nesting limit, and far beyond it
            depth = rng.choice([63, 64, 65, 1000, 100_000])
            opener, closer = rng.choice([("[", "]"), ("{ a = ", " }")])
            data += f"\ndeep = {opener * depth}1{closer * depth}\n".encode()
        elif kind == "oversized":
            data += b"# " + b"x" * (4 * 1024 * 1024 + 16) + b"\n"  # beyond the 4 MiB scene limit
        elif kind == "bom":
            data = b"\xef\xbb\xbf" + data
        elif kind == "crlf":
            data = data.replace(b"\n", b"\r\n")
        return f"text {kind}", f"(text:{kind})", data


# ---------------------------------------------------------------------------------------------------------
# Running aggkit and judging the result.


def limit_child(memory_mb):
    def apply():
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if memory_mb > 0:
            limit = memory_mb * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    return apply


def run_aggkit(command, timeout, cwd, memory_mb):
    env = dict(os.environ, OMP_NUM_THREADS="1", MPLBACKEND="Agg")
    proc = subprocess.Popen(command, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env, start_new_session=True,
                            preexec_fn=limit_child(memory_mb))
    try:
        out, err = proc.communicate(timeout=timeout)
        return proc.returncode, out, err, False
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # the whole session: MPI helpers and plotters too
        except ProcessLookupError:
            pass
        out, err = proc.communicate()
        return None, out, err, True


def strict_json(text):
    def refuse(constant):
        raise ValueError(f"non-JSON constant {constant}")
    json.loads(text, parse_constant=refuse)


def progressing(stderr):
    """Whether a run killed at the timeout was still moving: its last two progress lines (printed about once
    a second, without --quiet) differ once their elapsed-seconds field is removed. A valid scene may ask
    for hours of work (2^32 DSMC particles, time.end = 1e12); that is not a hang as long as it shows
    progress. Frozen or absent progress is a hang."""
    lines = [re.sub(r", [0-9.]+ s$", "", line.strip()) for line in stderr.splitlines()
             if line.startswith("aggkit: engine") and " done in " not in line]
    return len(lines) >= 2 and lines[-1] != lines[-2]


def judge(rc, timed_out, stderr, out_dir, is_scan):
    """The finding kind, or None when aggkit kept its contract."""
    artifact = os.path.join(out_dir, "scan.csv" if is_scan else "summary.json")
    if timed_out:
        return None if not is_scan and progressing(stderr) else "timeout"
    if rc < 0 or rc not in (0, 1, 2, 3):
        return "crash"
    if rc == 3:
        return "internal-error"
    if rc == 2:
        if os.path.exists(artifact):
            return "output-on-bad-input"
        if " = " not in stderr or ": " not in stderr:
            return "bad-message"
        return None
    if not os.path.isfile(artifact) or os.path.getsize(artifact) == 0:
        return "missing-summary"
    if not is_scan:
        try:
            with open(artifact, encoding="utf-8") as f:
                strict_json(f.read())
        except (ValueError, UnicodeDecodeError):
            return "invalid-summary"
    return None


def exit_label(rc, timed_out):
    if timed_out:
        return "timeout"
    if rc < 0:
        try:
            return "signal " + signal.Signals(-rc).name
        except ValueError:
            return f"signal {-rc}"
    return str(rc)


# ---------------------------------------------------------------------------------------------------------


def load_scenes(folder, with_scan):
    scenes = []
    for file in sorted(os.listdir(folder)):
        if not file.endswith(".toml"):
            continue
        is_scan = file.startswith("scan-")
        if is_scan and not with_scan:
            continue
        with open(os.path.join(folder, file), "rb") as f:
            doc = tomllib.load(f)
        scenes.append((file[:-5], shrink(doc, is_scan), is_scan))
    return scenes


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("aggkit", help="the aggkit binary")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--budget", type=float, default=60.0, help="seconds of fuzzing (default 60)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds per aggkit run (default 10)")
    parser.add_argument("--out", required=True, help="output folder (findings.json, stats.json)")
    parser.add_argument("--scenes", default=os.path.join(here, "..", "..", "validation", "scenes"),
                        help="folder of the scenes to mutate (default validation/scenes)")
    parser.add_argument("--no-scan", action="store_true", help="leave out the scan-*.toml scenes")
    parser.add_argument("--memory-mb", type=int, default=4096,
                        help="address-space limit of each aggkit run in MiB (0: none; default 4096)")
    parser.add_argument("--text-fraction", type=float, default=0.2, help="share of whole-text mutations")
    args = parser.parse_args()

    binary = os.path.abspath(args.aggkit)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    for old in os.listdir(out):
        if old.startswith("finding-") or old in ("findings.json", "stats.json", "work"):
            path = os.path.join(out, old)
            shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
    work = os.path.join(out, "work")
    os.makedirs(work)
    for file, text in START_FILES.items():
        with open(os.path.join(work, file), "w") as f:
            f.write(text)

    rng = random.Random(args.seed)
    scenes = load_scenes(args.scenes, not args.no_scan)
    if not scenes:
        print(f"fuzz_scenes: no scenes in {args.scenes}", file=sys.stderr)
        return 2
    names, keys = harvest_vocabulary(binary)
    names += sorted(START_FILES)
    mutator = Mutator(rng, scenes, names, keys)
    # `aggkit scan` spends about 0.4 s in MPI_Init before it reads the scene, against about 0.06 s for a
    # whole shrunk `aggkit run`: scan scenes are drawn a quarter as often, so they do not take most of the time.
    weights = [0.25 if is_scan else 1.0 for _, _, is_scan in scenes]

    findings, exit_counts, mutation_counts = {}, {}, {}
    seconds_by_scene, slowest = {}, []  # where the time goes: for tuning the shrinking caps
    executions, start = 0, time.monotonic()
    while time.monotonic() - start < args.budget:
        scene_name, base, is_scan = rng.choices(scenes, weights)[0]
        doc = copy.deepcopy(base)
        if rng.random() < args.text_fraction:
            description, key_path, data = mutator.mutate_text(toml_dump(doc).encode("utf-8"))
        else:
            description, key_path, doc = mutator.mutate_doc(doc)
            data = toml_dump(doc).encode("utf-8", "surrogatepass")
        op = description.split()[0] + (" " + description.split()[1] if description.startswith("text") else "")
        mutation_counts[op] = mutation_counts.get(op, 0) + 1

        scene_file = os.path.join(work, f"{scene_name}.toml")
        with open(scene_file, "wb") as f:
            f.write(data)
        run_out = os.path.join(work, "out")
        shutil.rmtree(run_out, ignore_errors=True)  # a fresh --out for every run
        # Progress lines are kept for `run` (they tell a long run from a hang); scans stay quiet.
        command = [binary, "scan" if is_scan else "run", scene_file, "--out", run_out, "--no-plot"]
        if is_scan:
            command.append("--quiet")
        run_start = time.monotonic()
        rc, _, err, timed_out = run_aggkit(command, args.timeout, work, args.memory_mb)
        seconds = time.monotonic() - run_start
        executions += 1
        per_scene = seconds_by_scene.setdefault(scene_name, [0, 0.0])
        per_scene[0] += 1
        per_scene[1] += seconds
        slowest.append((seconds, f"{scene_name}: {description[:100]}"))
        slowest = sorted(slowest, reverse=True)[:5]
        stderr = err.decode("utf-8", "replace")
        label = exit_label(rc, timed_out)
        if timed_out and not is_scan and progressing(stderr):
            label = "timeout, progressing (a long valid run)"
        exit_counts[label] = exit_counts.get(label, 0) + 1
        kind = judge(rc, timed_out, stderr, run_out, is_scan)
        if kind is None:
            continue
        dedup = f"{kind}|{key_path}|{label}"
        if dedup in findings:
            finding = findings[dedup]
            finding["hits"] += 1
            if len(finding["also"]) < 10 and description not in finding["also"] and description != finding["mutation"]:
                finding["also"].append(f"{scene_name}: {description}")
            continue
        number = len(findings) + 1
        kept = os.path.join(out, f"finding-{number:02d}.toml")
        with open(kept, "wb") as f:
            f.write(data)
        findings[dedup] = {
            "kind": kind, "key": key_path, "exit": label, "scene": scene_name, "mutation": description,
            "command": " ".join([binary, "scan" if is_scan else "run", kept, "--out", "OUT", "--quiet", "--no-plot"]),
            "scene_file": kept, "stderr_tail": stderr[-2000:],
            "scene_text": data[:20000].decode("utf-8", "replace") + ("" if len(data) <= 20000 else
                                                                    f"\n... ({len(data)} bytes in all)"),
            "hits": 1, "also": [],
            "execution": executions,  # its place in the seed's sequence: how far a shorter budget must get
        }
    elapsed = time.monotonic() - start
    shutil.rmtree(work, ignore_errors=True)

    ordered = sorted(findings.values(), key=lambda f: (f["kind"], f["key"]))
    with open(os.path.join(out, "findings.json"), "w") as f:
        json.dump(ordered, f, indent=2)
    stats = {
        "seed": args.seed, "budget_s": args.budget, "timeout_s": args.timeout, "elapsed_s": round(elapsed, 2),
        "executions": executions, "executions_per_s": round(executions / elapsed, 2) if elapsed > 0 else 0.0,
        "exit_codes": dict(sorted(exit_counts.items())), "mutations": dict(sorted(mutation_counts.items())),
        "findings": len(findings), "finding_kinds": {},
        "mean_run_s_by_scene": {k: round(v[1] / v[0], 3) for k, v in sorted(seconds_by_scene.items())},
        "slowest_runs": [f"{s:.2f} s {what}" for s, what in slowest], "aggkit": binary,
    }
    for finding in ordered:
        stats["finding_kinds"][finding["kind"]] = stats["finding_kinds"].get(finding["kind"], 0) + 1
    with open(os.path.join(out, "stats.json"), "w") as f:
        json.dump(stats, f, indent=2)
    codes = " ".join(f"{k}:{v}" for k, v in stats["exit_codes"].items())
    print(f"fuzz_scenes: seed {args.seed}, {executions} executions in {elapsed:.1f} s "
          f"({stats['executions_per_s']}/s), exit codes {codes}, {len(findings)} findings -> {out}")
    for finding in ordered:
        print(f"  {finding['kind']:<20} exit {finding['exit']:<8} {finding['key']}: {finding['scene']}: "
              f"{finding['mutation'][:100]}")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
