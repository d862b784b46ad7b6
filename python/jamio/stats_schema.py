"""The stats.h5 schema (reference/schema/stats.toml, here as schema/stats.toml) applied to an
open file: the same rules jam applies (stats/stats_schema.cpp), read from the same file, in the
same order, so that both name the same field first; tests/test_stats_schema.py feeds both one
corpus. Each refusal is a ValueError naming the object, the field and its value:
"attribute 'dim' of '/' is 7, not 2 or 3", "dataset '/ensembles/e/constant_phi/sample_ids'
holds 1.5, not a whole number"."""

from __future__ import annotations

import math
import os

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11: the same parser under its earlier name
    import tomli as tomllib

import h5py
import numpy as np

from .hdf5 import _attribute, _check_size, _is_string, _kind, member
from .errors import shown, visible

SCHEMA_PATH = os.path.join(os.path.dirname(__file__), "schema", "stats.toml")

with open(SCHEMA_PATH, "rb") as _f:
    SCHEMA = tomllib.load(_f)

# Paths in messages are shown whole up to this length (jam shows them whole).
_LONGEST_PATH = 300


def _path(p):
    """A path as messages show it (control characters as escapes); a long one keeps its end,
    which names the field."""
    text = visible(repr(p), longest=len(repr(p)) * 4 + 1)
    return text if len(text) <= _LONGEST_PATH else text[:100] + "..." + text[-150:]


# 2^53: every whole number up to it is exact in a double (sim/io/whole_number.hpp).
MOST_EXACT_WHOLE = 2 ** 53


def _rules(group):
    """A [[group]]'s attributes and datasets, those of its included sets first (as jam)."""
    attributes, datasets = [], []
    for name in group.get("include", []):
        attributes += SCHEMA["sets"][name].get("attributes", [])
        datasets += SCHEMA["sets"][name].get("datasets", [])
    return attributes + group.get("attributes", []), datasets + group.get("datasets", [])


def number(v):
    """A number as jam's messages show it: 7, 0.5, nan (a whole float without its .0)."""
    if isinstance(v, bool):
        return repr(v)
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    v = float(v)
    if math.isfinite(v) and v.is_integer() and abs(v) < 1e16:
        return str(int(v))
    return repr(v)


def _allowed_words(allowed):
    words = [repr(a) if isinstance(a, str) else number(a) for a in allowed]
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _allows(allowed, v):
    if not allowed:
        return True
    if isinstance(v, str):
        return any(isinstance(a, str) and a == v for a in allowed)
    return any(not isinstance(a, str) and a == v for a in allowed)


def _child(base, name):
    return "/" + name if base == "/" else f"{base}/{name}"


def _instances(f, pattern):
    """The groups a pattern names ("ensembles/*/constant_phi"), in name order; a member where
    `*` stands, or a named step that is not a group, is refused."""
    bases = [f["/"]]
    for part in ([] if pattern == "/" else pattern.split("/")):
        found = []
        for base in bases:
            for name in (sorted(base) if part == "*" else [part]):
                obj = member(base, name)
                if obj is None:
                    continue
                if not isinstance(obj, h5py.Group):
                    raise ValueError(f"{_path(_child(base.name, name))} is not a group")
                found.append(obj)
        bases = found
    return bases


def _check_required(f, pattern):
    if pattern == "/":
        return
    parent, _, last = pattern.rpartition("/")
    for base in _instances(f, parent or "/"):
        if member(base, last) is None:
            raise ValueError(f"group {_path(_child(base.name, last))} missing")


def _needed(obj, rule):
    unless = rule.get("required_unless")
    return rule.get("required", False) or (unless is not None and unless not in obj.attrs)


def _check_attribute(obj, rule):
    name = rule["name"]
    where = f"attribute {shown(name)} of {_path(obj.name)}"
    if name not in obj.attrs:
        if _needed(obj, rule):
            raise ValueError(f"{where} missing")
        return
    v = _attribute(obj, name)  # one value, of a number or string type
    dtype = obj.attrs.get_id(name).dtype
    kind = rule["type"]
    if kind == "string":
        if not _is_string(dtype):
            raise ValueError(f"{where} is {shown(v)}, not a string")
    elif _is_string(dtype) or dtype.kind not in ("iu" if kind == "integer" else "iuf"):
        raise ValueError(f"{where} is {shown(v)}, not "
                         f"{'a whole number' if kind == 'integer' else 'a number'}")
    shown_v = shown(v) if kind == "string" else number(v)
    if rule.get("finite") and not math.isfinite(v):
        raise ValueError(f"{where} is {shown_v}, not a finite number")
    if "min" in rule and not v >= rule["min"]:
        raise ValueError(f"{where} is {shown_v}, less than {number(rule['min'])}")
    if not _allows(rule.get("allowed"), v):
        raise ValueError(f"{where} is {shown_v}, not {_allowed_words(rule['allowed'])}")


def _extent(dims):
    return " x ".join(str(d) for d in dims) if dims else "scalar"


def _check_shape(where, names, dims, bound):
    """The extents against the named dimensions: the bound ones must agree, the others are
    bound here for the datasets after it."""
    expected = " x ".join(names)
    if all(n in bound for n in names):
        want = tuple(bound[n] for n in names)
        expected += " = " + _extent(want)
        count, wanted = math.prod(dims), math.prod(want)
        if count != wanted:
            raise ValueError(f"{where} has {count} values, expected {wanted} ({expected})")
        if tuple(dims) != want:
            raise ValueError(f"{where} has shape {_extent(dims)}, expected {expected}")
        return
    if len(dims) != len(names):
        raise ValueError(f"{where} has shape {_extent(dims)}, expected {expected}")
    for n, d in zip(names, dims):
        if n not in bound:
            bound[n] = d
        elif bound[n] != d:
            raise ValueError(f"{where} has shape {_extent(dims)}, expected {expected} with "
                             f"{n} = {bound[n]}")


def _check_values(where, rule, values):
    allowed = rule.get("allowed")
    for v in np.asarray(values, dtype=np.float64).ravel().tolist():
        if rule.get("whole") and not (math.isfinite(v) and v.is_integer()
                                      and abs(v) <= MOST_EXACT_WHOLE):
            raise ValueError(f"{where} holds {number(v)}, not a whole number")
        if rule.get("finite") and not math.isfinite(v):
            raise ValueError(f"{where} holds {number(v)}, not a finite number")
        if not math.isnan(v) and not _allows(allowed, v):
            raise ValueError(f"{where} holds {number(v)}, not {_allowed_words(allowed)}")


def _check_dataset(g, rule, bound):
    path = _child(g.name, rule["name"])
    where = f"dataset {_path(path)}"
    d = member(g, rule["name"])
    if d is None:
        if _needed(g, rule):
            raise ValueError(f"{where} missing")
        return
    if isinstance(d, h5py.Group):
        raise ValueError(f"{where} is a group")
    if _is_string(d.dtype) or d.dtype.names or d.dtype.subdtype is not None or d.dtype.kind != "f":
        raise ValueError(f"{where} is {_kind(d.dtype)}, expected floating point")
    if d.shape is None or d.shape == ():
        raise ValueError(f"{where} is not an array (a scalar or null dataspace)")
    _check_size(d)  # stored in the file, written, of a size the file can hold
    _check_shape(where, rule["shape"], d.shape, bound)
    if rule.get("whole") or rule.get("finite") or rule.get("allowed"):
        _check_values(where, rule, d[()])
    if "units" in d.attrs:
        unit = _attribute(d, "units")
        if unit != rule["unit"]:
            raise ValueError(f"attribute 'units' of {_path(path)} is {shown(unit)}, "
                             f"not {shown(rule['unit'])}")


def _check_group(g, rule):
    attributes, datasets = _rules(rule)
    for a in attributes:
        _check_attribute(g, a)
    one_of = rule.get("one_of")
    if one_of and all(member(g, name) is None for name in one_of):
        raise ValueError(f"group {_path(g.name)} has none of the datasets "
                         f"{_allowed_words(one_of)}")
    bound = {}  # each group instance binds its own dimensions
    for d in datasets:
        _check_dataset(g, d, bound)


def check_stats(f):
    """Raises ValueError naming the first group, attribute or dataset of the open stats.h5 `f`
    that breaks its rule in the schema."""
    for rule in SCHEMA["group"]:
        for pattern in rule["paths"]:
            if rule.get("required"):
                _check_required(f, pattern)
            for g in _instances(f, pattern):
                _check_group(g, rule)
