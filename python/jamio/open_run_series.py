"""The checks of an open run's series (its datasets: packing_fraction, time, pressure, ...),
shared by the writers (write.py) and the reader (open_run.py), which re-exports `_series` and
`_array`."""

from __future__ import annotations

import numpy as np

from .errors import cause, shown
from .open_run_format import SCHEMA, Invalid


def _array(name, v, ndim=1):
    """An array-like of numbers as float64 of `ndim` dimensions (checked before converting).
    A masked array with a masked value is refused: converting it would write the raw values
    hidden behind its mask."""
    if isinstance(v, np.ma.MaskedArray) and np.ma.getmaskarray(v).any():
        k = int(np.flatnonzero(np.ma.getmaskarray(v))[0])
        raise Invalid(f"{name} has a masked value (at flat index {k}): fill or drop masked "
                      "points before writing")
    try:
        x = np.asarray(v)
    except (ValueError, TypeError) as e:
        raise Invalid(f"{name} is not an array of numbers ({cause(e)})") from e
    if x.dtype.kind not in "iuf":
        raise Invalid(f"{name} holds {x.dtype} values, expected numbers")
    if x.ndim != ndim:
        expected = "one dimension" if ndim == 1 else f"{ndim} dimensions"
        raise Invalid(f"{name} has shape {x.shape}, expected {expected}")
    return np.ascontiguousarray(x, dtype=np.float64)


def _first_bad(mask):
    """The first index where mask holds, or None."""
    where = np.flatnonzero(mask)
    return int(where[0]) if where.size else None


def _finite(name, x):
    k = _first_bad(~np.isfinite(x))
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(x[k]))} must be finite")


def _increasing(name, x):
    k = _first_bad(np.diff(x) <= 0)
    if k is not None:
        raise Invalid(f"{name}[{k + 1}] = {shown(float(x[k + 1]))} is not above {name}[{k}] = "
                      f"{shown(float(x[k]))} (must increase strictly)")


def _not_negative(name, x):
    k = _first_bad(x < 0)
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(x[k]))} must be >= 0")


def _lengths(series, schema=SCHEMA):
    """All series of one length M >= 2 (shapes only: nothing read)."""
    first, m = next(iter(series.items()))
    for name, length in series.items():
        if length != m:
            raise Invalid(f"{name} has {length} values and {first} {m}: the series must have "
                          "equal lengths")
    if m < 2:
        raise Invalid(f"{first} has {m} values; a run needs at least 2 points")
    most = schema.limits["max_points"]["value"]
    if m > most:
        raise Invalid(f"{first} has {m} values, at most {most}")
    return m


def _packing(name, phi, phi_init, schema=SCHEMA):
    _finite(name, phi)
    k = _first_bad((phi <= 0) | (phi >= 1))
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(phi[k]))} must be in (0, 1)")
    _increasing(name, phi)
    if phi[0] < phi_init * (1 - schema.limits["phi_init_slack"]["value"]):
        raise Invalid(f"{name}[0] = {shown(float(phi[0]))} is below phi_init {shown(phi_init)}")


def _time(t):
    _finite("time", t)
    _not_negative("time", t)
    _increasing("time", t)


def _at_rate(name, phi, t, phi_init, rate, dim, schema=SCHEMA):
    """phi(t) = phi_init exp(D rate t) to the schema's rate_tolerance, relative."""
    tolerance = schema.limits["rate_tolerance"]["value"]
    expected = phi_init * np.exp(dim * rate * t)
    off = phi / expected - 1
    k = _first_bad(~(np.abs(off) <= tolerance))
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(phi[k]))} at time {shown(float(t[k]))} is not "
                      f"phi_init exp(D rate t) = {shown(float(expected[k]))} (relative difference "
                      f"{float(off[k]):.3g}, at most {tolerance:g}): the box does not shrink "
                      f"at compression_rate {shown(rate)}")


def _series(data, model, schema=SCHEMA):
    """The series of a run (name -> float64 array, absent ones left out), checked as the
    format's table says."""
    for name in schema.required_series:
        if name not in data:
            raise Invalid(f"dataset '{name}' missing")
    _lengths({k: len(v) for k, v in data.items()}, schema)
    _packing("packing_fraction", data["packing_fraction"], model["phi_init"], schema)
    for name in ("pressure", "contacts_per_particle", "energy_per_particle"):
        if name in data:
            _finite(name, data[name])
            _not_negative(name, data[name])
    if "contacts_per_particle" in data:
        z = data["contacts_per_particle"]
        most = schema.limits["max_contacts_per_particle"]["value"]
        k = _first_bad(z > most)
        if k is not None:
            raise Invalid(f"contacts_per_particle[{k}] = {shown(float(z[k]))} must be in "
                          f"[0, {most:g}]")
    if "time" in data:
        _time(data["time"])
        _at_rate("packing_fraction", data["packing_fraction"], data["time"], model["phi_init"],
                 model["compression_rate"], model["dim"], schema)
