"""Scenes from Python values: a small TOML writer, so that keyword arguments reach the C++ core as a scene
and are checked there exactly as in a scene file (same keys, same messages)."""
import math
import numbers

import numpy as np


def _key(name):
    name = str(name)
    if name and all(c.isalnum() or c in "-_" for c in name):
        return name
    return _string(name)


def _string(text):
    out = ['"']
    for c in str(text):
        if c == '"':
            out.append('\\"')
        elif c == "\\":
            out.append("\\\\")
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append("\\u%04x" % ord(c))
        else:
            out.append(c)
    out.append('"')
    return "".join(out)


def value(x):
    """A Python value as TOML (inline tables for dicts)."""
    if isinstance(x, (bool, np.bool_)):
        return "true" if x else "false"
    if isinstance(x, numbers.Integral):
        return str(int(x))
    if isinstance(x, numbers.Real):
        x = float(x)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(x, str):
        return _string(x)
    if isinstance(x, dict):
        return "{ " + ", ".join(_key(k) + " = " + value(v) for k, v in x.items()) + " }" if x else "{}"
    if isinstance(x, (list, tuple, np.ndarray)):
        return "[" + ", ".join(value(v) for v in list(x)) + "]"
    raise ValueError(f"{x!r}: a number, string, boolean, list or dict (TOML has no {type(x).__name__})")


def section(name, entries):
    lines = [f"[{name}]"] + [f"{_key(k)} = {value(v)}" for k, v in entries.items() if v is not None]
    return "\n".join(lines) + "\n"


def scene(name, model=None, particles=None, times=None, engine=None, observe=None):
    """The text of a scene with one engine."""
    times = np.asarray(times, dtype=float).ravel()
    if times.size == 0:
        raise ValueError("times = []: at least one output time > 0")
    text = f"name = {_string(name)}\n"
    if model is not None:
        text += section("model", model)
    if particles is not None:
        text += section("particles", particles)
    text += section("time", {"end": float(times[-1]), "outputs": [float(t) for t in times]})
    text += "[[engine]]\n" + "".join(f"{_key(k)} = {value(v)}\n" for k, v in engine.items() if v is not None)
    text += section("observe", observe)
    return text


def document(tree):
    """A whole scene given as a dict with the TOML structure (`aggkit.run({...})`): top-level tables become
    sections, lists of tables become [[arrays]], deeper tables inline tables."""
    def is_tables(v):
        return isinstance(v, list) and v and all(isinstance(e, dict) for e in v)

    text = "".join(f"{_key(k)} = {value(v)}\n" for k, v in tree.items() if not isinstance(v, dict) and not is_tables(v))
    for k, v in tree.items():
        if isinstance(v, dict):
            text += f"\n[{_key(k)}]\n" + "".join(f"{_key(kk)} = {value(vv)}\n" for kk, vv in v.items())
        elif is_tables(v):
            for e in v:
                text += f"\n[[{_key(k)}]]\n" + "".join(f"{_key(kk)} = {value(vv)}\n" for kk, vv in e.items())
    return text
