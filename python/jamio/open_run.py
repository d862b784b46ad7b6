"""The open run format (docs/cross-simulator.md): its rules, and the reader of an open run.

    validate_run(path)       an open run, or a run file of jam's own -> OpenRun (its attributes
                             and series), every field checked as the format's tables say

The rules (`_model`, `_series` in open_run_series.py, and the field checks they call; the
schema in open_run_format.py) are those the writers
(write.py) apply before anything is written. A violation raises JamioError, one line naming the
file, the field and the value.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field

import h5py
import numpy as np

from .errors import JamioError, cause, shown
from .hdf5 import (MOST_STRING_BYTES, _check_size, _kind, _plain_type, member, read_hdf5,
                   value)
# The format's schema and the series' checks live beside this file; their names are jamio's
# open_run names as before (write.py, runs.py, gsd_import.py and grid.py import them here).
from .open_run_format import (ATTRIBUTES, CONTACTS, DYNAMICS, FORMAT, FORMAT_VERSION,  # noqa: F401
                              FRAMES_UNITS, LIMITS, MAX_CONTACTS, MAX_POINTS, MAX_WHOLE,
                              OPTIONAL_ATTRIBUTES, PHI_INIT_SLACK, PROTOCOL, RATE_TOLERANCE,
                              REQUIRED_SERIES, SCHEMA, SERIES_UNITS, UNITS, Invalid, Schema,
                              load_schema)
from .open_run_series import (_array, _at_rate, _finite, _first_bad, _increasing,  # noqa: F401
                              _lengths, _not_negative, _packing, _series, _time)


# ---- the checks, shared by the writers and the reader -------------------------------------------

def _integer(name, v):
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
        raise Invalid(f"{name} {shown(v)} must be an integer")
    return int(v)


def _number(name, v):
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise Invalid(f"{name} {shown(v)} must be a number")
    return float(v)


def _string(name, v):
    if not isinstance(v, str):
        raise Invalid(f"{name} {shown(v)} must be a string")
    if "\0" in v:
        raise Invalid(f"{name} {shown(v)} must not contain a NUL character")
    return v


def _one_of(name, v, allowed):
    v = _string(name, v)
    if v not in allowed:
        words = " or ".join(repr(a) for a in allowed)
        raise Invalid(f"{name} {shown(v)} must be {words}")
    return v


def _positive(name, v):
    x = _number(name, v)
    if not (math.isfinite(x) and x > 0):
        raise Invalid(f"{name} {shown(x)} must be > 0 and finite")
    return x


def _dim(v):
    d = _integer("dim", v)
    if d not in (2, 3):
        raise Invalid(f"dim {d} must be 2 or 3")
    return d


def _n(v, schema=SCHEMA):
    n = _integer("n", v)
    if n < 2 or n % 2 or n > schema.limits["max_whole"]["value"]:
        raise Invalid(f"n {n} must be even, >= 2 (half small, half big) and at most 2^53")
    return n


def _diameter_ratio(v, schema=SCHEMA):
    r = _number("diameter_ratio", v)
    low, high = schema.limits["diameter_ratio"]["min"], schema.limits["diameter_ratio"]["max"]
    if not low <= r <= high:
        raise Invalid(f"diameter_ratio {shown(r)} must be in [{low:g}, {high:g}]")
    return r


def _phi_init(v):
    x = _number("phi_init", v)
    if not 0.0 < x < 1.0:
        raise Invalid(f"phi_init {shown(x)} must be in (0, 1)")
    return x


def _simulator(v):
    s = _string("simulator", v)
    if not s.strip():
        raise Invalid(f"simulator {shown(s)} must not be empty")
    return s


def _sample(v, schema=SCHEMA):
    k = _integer("sample", v)
    if k < 0 or k > schema.limits["max_whole"]["value"]:
        raise Invalid(f"sample {k} must be >= 0 and at most 2^53")
    return k


def _q(dynamics, v, zero_is_absent=False):
    """Q: > 0 with inertial dynamics, absent with overdamped (jam's own files store 0 there)."""
    if dynamics == "inertial":
        if v is None:
            raise Invalid("q missing: dynamics 'inertial' needs the quality factor q > 0")
        return _positive("q", v)
    if v is None or (zero_is_absent and not isinstance(v, (str, bool)) and v == 0):
        return None
    raise Invalid(f"q {shown(v)} is only for dynamics 'inertial' (dynamics is {shown(dynamics)})")


def _jamming_packing_fraction(v, schema=SCHEMA):
    x = _number("jamming_packing_fraction", v)
    low = schema.limits["jamming_packing_fraction"]["above"]
    high = schema.limits["jamming_packing_fraction"]["below"]
    if not (math.isnan(x) or low < x < high):
        raise Invalid(f"jamming_packing_fraction {shown(x)} must be in ({low:g}, {high:g}), or "
                      "NaN when not found")
    return x


def _source_checksum(v):
    s = _string("source_checksum", v)
    if not re.fullmatch("[0-9a-fA-F]{16}", s):
        raise Invalid(f"source_checksum {shown(s)} must be 16 hex digits (FNV-1a of the source)")
    return s


def _equal(name, v, expected):
    if isinstance(expected, str):
        v = _string(name, v)
    else:
        v = _integer(name, v)
    if v != expected:
        raise Invalid(f"{name} {shown(v)} must be {shown(expected)}")
    return v


def _model(a, schema=SCHEMA):
    """The root attributes of an open run (a dict; absent optional ones None), checked in the
    order of the format's table; the values as Python values."""
    out = {"format": _equal("format", a["format"], schema.format),
           "format_version": _equal("format_version", a["format_version"],
                                    schema.format_version),
           "dim": _dim(a["dim"]), "n": _n(a["n"], schema),
           "diameter_ratio": _diameter_ratio(a["diameter_ratio"], schema),
           "contact": _one_of("contact", a["contact"], schema.contacts),
           "dynamics": _one_of("dynamics", a["dynamics"], schema.dynamics)}
    out["q"] = _q(out["dynamics"], a.get("q"), zero_is_absent=a.get("_native", False))
    out["protocol"] = _equal("protocol", a["protocol"], schema.protocol)
    out["compression_rate"] = _positive("compression_rate", a["compression_rate"])
    out["phi_init"] = _phi_init(a["phi_init"])
    out["simulator"] = _simulator(a["simulator"])
    out["simulator_version"] = _string("simulator_version", a["simulator_version"])
    out["sample"] = None if a.get("sample") is None else _sample(a["sample"], schema)
    out["units"] = _equal("units", a["units"], schema.units)
    checks = {"jamming_packing_fraction": lambda v: _jamming_packing_fraction(v, schema),
              "source": lambda v: _string("source", v),
              "source_checksum": _source_checksum,
              "interpolation": lambda v: _string("interpolation", v)}
    for name, check in checks.items():
        out[name] = None if a.get(name) is None else check(a[name])
    return out


# ---- reading ------------------------------------------------------------------------------------

@dataclass(repr=False)
class OpenRun:
    """A run as the open run format sees it: the root attributes (absent optional ones None;
    `q` None unless inertial, `sample` None for a run file of jam's own outside a campaign),
    `data` (series name -> float64 array: packing_fraction, pressure and those of
    contacts_per_particle, energy_per_particle, time present) and `units` (series -> its units
    attribute, where stored). `native`: a run file of jam's own (simulator "jam",
    simulator_version its `version`; `format`, `format_version`, `protocol`, `units` None)."""

    path: str
    native: bool
    dim: int
    n: int
    diameter_ratio: float
    contact: str
    dynamics: str
    q: float | None
    compression_rate: float
    phi_init: float
    simulator: str
    simulator_version: str
    sample: int | None
    format: str | None = None
    format_version: int | None = None
    protocol: str | None = None
    units: str | None = None
    jamming_packing_fraction: float | None = None
    source: str | None = None
    source_checksum: str | None = None
    interpolation: str | None = None
    data: dict = field(default_factory=dict)
    series_units: dict = field(default_factory=dict)

    @property
    def points(self):
        return len(self.data["packing_fraction"])

    def __getitem__(self, key):
        return self.data[key]

    def __contains__(self, key):
        return key in self.data

    def __repr__(self):
        phi = self.data["packing_fraction"]
        version = f" {self.simulator_version}" if self.simulator_version else ""
        sample = "" if self.sample is None else f", sample {self.sample}"
        return (f"OpenRun {os.path.basename(self.path)}: {self.simulator}{version}, D {self.dim}, "
                f"N {self.n}, rate {self.compression_rate:.4g}, phi_init {self.phi_init:.6g}"
                f"{sample}, {len(phi)} points (phi {phi[0]:.6g} to {phi[-1]:.6g})")


def _scalar_attribute(obj, key, where="attribute"):
    """One attribute: one value (a scalar dataspace, not an array) of a number or string type,
    its shape and type checked before its value is read."""
    attribute = obj.attrs.get_id(key)
    shape, dtype = attribute.shape, attribute.dtype
    if shape is None:
        raise Invalid(f"{where} '{key}' holds no value (a null dataspace)")
    if shape != ():
        raise Invalid(f"{where} '{key}' is an array of shape {shape}, expected one value")
    if not _plain_type(dtype):
        raise Invalid(f"{where} '{key}' is {_kind(dtype)}, expected a number or a string")
    if dtype.kind == "S" and dtype.itemsize > MOST_STRING_BYTES:
        raise Invalid(f"{where} '{key}' is a string of {dtype.itemsize} bytes "
                      f"(at most {MOST_STRING_BYTES})")
    try:
        return value(obj.attrs[key])
    except (ValueError, TypeError, OverflowError) as e:  # UnicodeDecodeError included
        raise Invalid(f"{where} '{key}' cannot be read ({cause(e)})") from e


def _root_attributes(f, schema=SCHEMA):
    """The format's root attributes of f (absent: not in the dict), and whether f is a run
    file of jam's own."""
    native = "format" not in f.attrs and "checksum" in f.attrs
    if "format" not in f.attrs and not native:
        raise Invalid("attribute 'format' missing: neither an open run (format "
                      f"{FORMAT!r}) nor a run file of jam's own (attribute 'checksum')")
    names = (schema.attributes + schema.optional_attributes
             + (("version", "checksum") if native else ()))
    a = {k: _scalar_attribute(f, k) for k in names if k in f.attrs}
    if native:
        # jam's own run files: simulator "jam" at its version; protocol and units need not be
        # stated (their `units` is a sentence), q is 0 for overdamped runs, sample is there
        # for campaign runs only; files from before the contact law was a choice are harmonic.
        version = _string("version", a.get("version", ""))
        a.update(format=schema.format, format_version=schema.format_version,
                 protocol=schema.protocol, units=schema.units, simulator="jam",
                 simulator_version=version, _native=True)
        a.setdefault("contact", "harmonic")
    for k in schema.attributes:
        if k not in a and k not in ("q", "sample"):
            raise Invalid(f"attribute '{k}' missing")
    if not native and "sample" not in a:
        raise Invalid("attribute 'sample' missing")
    return a, native


def _read_series(f, schema=SCHEMA):
    """The series of f as float64 arrays: each an HDF5 dataset of one dimension of floats, all
    of one length, its units attribute (if any) the format's; shapes, types and sizes checked
    before any value is read."""
    datasets = {}
    for name in schema.series_units:
        try:
            d = member(f, name)
        except ValueError as e:  # a link out of the file, or soft links without end
            raise Invalid(str(e)) from e
        if d is None:
            if name in schema.required_series:
                raise Invalid(f"dataset '{name}' missing")
            continue
        if not isinstance(d, h5py.Dataset):
            raise Invalid(f"'{name}' is not a dataset")
        if len(d.shape) != 1:
            raise Invalid(f"dataset '{name}' has shape {d.shape}, expected one dimension")
        if d.dtype.kind != "f" or d.dtype.names or d.dtype.subdtype is not None:
            raise Invalid(f"dataset '{name}' is {_kind(d.dtype)}, expected floating point")
        datasets[name] = d
    _lengths({k: d.shape[0] for k, d in datasets.items()}, schema)
    units = {}
    for name, d in datasets.items():
        if "units" in d.attrs:
            u = _scalar_attribute(d, "units", where=f"dataset '{name}': attribute")
            if u != schema.series_units[name]:
                raise Invalid(f"dataset '{name}' has units {shown(u)}, expected "
                              f"{shown(schema.series_units[name])}")
            units[name] = u
    data = {}
    for name, d in datasets.items():
        try:
            _check_size(d)
        except ValueError as e:
            raise Invalid(str(e)) from e
        data[name] = np.asarray(d[()], dtype=np.float64)
    return data, units


def _read_run(path, f, schema):
    try:
        a, native = _root_attributes(f, schema)
        model = _model(a, schema)
        data, units = _read_series(f, schema)
        _series(data, model, schema)
    except Invalid as e:
        raise JamioError(path, str(e)) from None
    del model["format"], model["format_version"], model["protocol"], model["units"]
    run = OpenRun(path=path, native=native, data=data, series_units=units, **model)
    if not native:
        run.format, run.format_version, run.protocol, run.units = (
            schema.format, schema.format_version, schema.protocol, schema.units)
    return run


def validate_run(path, schema=None):
    """Reads the run file at `path` and checks it as the open run format says
    (docs/cross-simulator.md): every root attribute one value of its type and within its
    range, the series one-dimensional float datasets of one length (shapes before values),
    their units attributes, values and the compression rate. A run file of jam's own
    (recognised by its `checksum` and no `format`) is read as simulator "jam" at its
    `version`; its checksum is not verified here (jam does that).

    `schema`: a Schema (load_schema) other than jam's own, for example that of a jam built with
    another contact law; by default the schema file jamio ships.

    Returns an OpenRun; raises JamioError, one line naming the file, the field and the value."""
    path = os.fspath(path)
    schema = SCHEMA if schema is None else schema
    return read_hdf5(path, "run file", lambda f: _read_run(path, f, schema))


__all__ = ["OpenRun", "Schema", "load_schema", "validate_run"]
