"""The open run format (docs/cross-simulator.md): writing a run from Python and checking one.

    write_run(path, packing_fraction, pressure, *, dim, n, rate, phi_init, simulator, sample, ...)
                             one compression run of any simulator -> an open run file
    write_frames(path, box_length, positions, diameters, *, dim, n, rate, phi_init, ...)
                             configurations without pressure -> a frames file for
                             `jam import frames`
    validate_run(path)       an open run, or a run file of jam's own -> OpenRun (its attributes
                             and series), every field checked as the format's tables say

Every check of the format is made before anything is written, and again on the written file
before it gets its name: a file is written as `<path>.<pid>.partial` and renamed to `path` only
when complete, so nothing is left behind on an error and a file under its final name is always a
run the readers take. A violation raises JamioError, one line naming the file, the field and the
value (`run.h5: write_run: diameter_ratio 2.5 must be in [1, 2]`).
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import stat
from dataclasses import dataclass, field

import h5py
import numpy as np

from .errors import JamioError, cause, shown
from .hdf5 import MOST_STRING_BYTES, _check_size, _kind, _plain_type, read_hdf5, value

FORMAT = "jam-open-run"
FORMAT_VERSION = 1
PROTOCOL = "isotropic-compression"
UNITS = "jam"
CONTACTS = ("harmonic", "hertzian")
DYNAMICS = ("overdamped", "inertial")
# The series of an open run, each with the unit its `units` attribute must state when present.
SERIES_UNITS = {"packing_fraction": "1", "pressure": "k_e/d_s^D", "contacts_per_particle": "1",
                "energy_per_particle": "k_e", "time": "t0"}
REQUIRED_SERIES = ("packing_fraction", "pressure")
# The frames file's datasets and their units.
FRAMES_UNITS = {"box_length": "d_s", "positions": "d_s", "diameters": "d_s", "time": "t0"}
# The first packing may lie this far (relative) below phi_init: round-off.
PHI_INIT_SLACK = 1e-9
# phi(t) = phi_init exp(D rate t) must hold to this, relative.
RATE_TOLERANCE = 1e-6
# The order of the root attributes in the format's table (and in a written file's listing).
ATTRIBUTES = ("format", "format_version", "dim", "n", "diameter_ratio", "contact", "dynamics",
              "q", "protocol", "compression_rate", "phi_init", "simulator", "simulator_version",
              "sample", "units")
OPTIONAL_ATTRIBUTES = ("jamming_packing_fraction", "source", "source_checksum", "interpolation")


class Invalid(ValueError):
    """One field of a run that the format refuses; its message names the field and the value."""


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


def _n(v):
    n = _integer("n", v)
    if n < 2 or n % 2:
        raise Invalid(f"n {n} must be even and >= 2 (half small, half big)")
    return n


def _diameter_ratio(v):
    r = _number("diameter_ratio", v)
    if not 1.0 <= r <= 2.0:
        raise Invalid(f"diameter_ratio {shown(r)} must be in [1, 2]")
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


def _sample(v):
    k = _integer("sample", v)
    if k < 0:
        raise Invalid(f"sample {k} must be >= 0")
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


def _jamming_packing_fraction(v):
    x = _number("jamming_packing_fraction", v)
    if not (math.isnan(x) or 0.0 < x < 1.0):
        raise Invalid(f"jamming_packing_fraction {shown(x)} must be in (0, 1), or NaN when "
                      "not found")
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


def _model(a):
    """The root attributes of an open run (a dict; absent optional ones None), checked in the
    order of the format's table; the values as Python values."""
    out = {"format": _equal("format", a["format"], FORMAT),
           "format_version": _equal("format_version", a["format_version"], FORMAT_VERSION),
           "dim": _dim(a["dim"]), "n": _n(a["n"]),
           "diameter_ratio": _diameter_ratio(a["diameter_ratio"]),
           "contact": _one_of("contact", a["contact"], CONTACTS),
           "dynamics": _one_of("dynamics", a["dynamics"], DYNAMICS)}
    out["q"] = _q(out["dynamics"], a.get("q"), zero_is_absent=a.get("_native", False))
    out["protocol"] = _equal("protocol", a["protocol"], PROTOCOL)
    out["compression_rate"] = _positive("compression_rate", a["compression_rate"])
    out["phi_init"] = _phi_init(a["phi_init"])
    out["simulator"] = _simulator(a["simulator"])
    out["simulator_version"] = _string("simulator_version", a["simulator_version"])
    out["sample"] = None if a.get("sample") is None else _sample(a["sample"])
    out["units"] = _equal("units", a["units"], UNITS)
    checks = {"jamming_packing_fraction": _jamming_packing_fraction,
              "source": lambda v: _string("source", v),
              "source_checksum": _source_checksum,
              "interpolation": lambda v: _string("interpolation", v)}
    for name, check in checks.items():
        out[name] = None if a.get(name) is None else check(a[name])
    return out


def _array(name, v, ndim=1):
    """An array-like of numbers as float64 of `ndim` dimensions (checked before converting)."""
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


def _lengths(series):
    """All series of one length M >= 2 (shapes only: nothing read)."""
    first, m = next(iter(series.items()))
    for name, length in series.items():
        if length != m:
            raise Invalid(f"{name} has {length} values and {first} {m}: the series must have "
                          "equal lengths")
    if m < 2:
        raise Invalid(f"{first} has {m} values; a run needs at least 2 points")
    return m


def _packing(name, phi, phi_init):
    _finite(name, phi)
    k = _first_bad((phi <= 0) | (phi >= 1))
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(phi[k]))} must be in (0, 1)")
    _increasing(name, phi)
    if phi[0] < phi_init * (1 - PHI_INIT_SLACK):
        raise Invalid(f"{name}[0] = {shown(float(phi[0]))} is below phi_init {shown(phi_init)}")


def _time(t):
    _finite("time", t)
    _not_negative("time", t)
    _increasing("time", t)


def _at_rate(name, phi, t, phi_init, rate, dim):
    """phi(t) = phi_init exp(D rate t) to RATE_TOLERANCE, relative."""
    expected = phi_init * np.exp(dim * rate * t)
    off = phi / expected - 1
    k = _first_bad(~(np.abs(off) <= RATE_TOLERANCE))
    if k is not None:
        raise Invalid(f"{name}[{k}] = {shown(float(phi[k]))} at time {shown(float(t[k]))} is not "
                      f"phi_init exp(D rate t) = {shown(float(expected[k]))} (relative difference "
                      f"{float(off[k]):.3g}, at most {RATE_TOLERANCE:g}): the box does not shrink "
                      f"at compression_rate {shown(rate)}")


def _series(data, model):
    """The series of a run (name -> float64 array, absent ones left out), checked as the
    format's table says."""
    for name in REQUIRED_SERIES:
        if name not in data:
            raise Invalid(f"dataset '{name}' missing")
    _lengths({k: len(v) for k, v in data.items()})
    _packing("packing_fraction", data["packing_fraction"], model["phi_init"])
    for name in ("pressure", "contacts_per_particle", "energy_per_particle"):
        if name in data:
            _finite(name, data[name])
            _not_negative(name, data[name])
    if "time" in data:
        _time(data["time"])
        _at_rate("packing_fraction", data["packing_fraction"], data["time"], model["phi_init"],
                 model["compression_rate"], model["dim"])


# ---- writing ------------------------------------------------------------------------------------

def _target(path, overwrite):
    """Refuses a path that cannot take the file: a directory or special file (by its stat), an
    existing file unless overwrite, a directory that does not exist."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        parent = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(parent):
            raise Invalid(f"directory {shown(parent)} does not exist") from None
        if os.path.lexists(path) and not overwrite:  # a symbolic link to nothing
            raise Invalid("exists (a symbolic link); not overwritten (overwrite=True replaces it)")
        return
    except OSError as e:
        raise Invalid(f"cannot be written ({cause(e)})") from e
    if stat.S_ISDIR(mode):
        raise Invalid("is a directory; a run is written to a file")
    if not stat.S_ISREG(mode):
        raise Invalid("is not a regular file (a FIFO, device or socket); not written")
    if not overwrite:
        raise Invalid("exists; not overwritten (overwrite=True replaces it)")


def _publish(partial, path, overwrite):
    """Gives the finished `partial` the name `path`: without overwrite by a hard link, which
    fails if path appeared meanwhile (then, where links are not supported, by a rename after a
    last look)."""
    if overwrite:
        os.replace(partial, path)
        return
    try:
        os.link(partial, path)
    except FileExistsError:
        raise Invalid("exists; not overwritten (overwrite=True replaces it)") from None
    except OSError:
        if os.path.lexists(path):
            raise Invalid("exists; not overwritten (overwrite=True replaces it)") from None
        os.rename(partial, path)
        return
    os.unlink(partial)


def _attribute_value(v):
    """A Python value as jam writes it: int64, float64 or a fixed-length UTF-8 string."""
    if isinstance(v, str):
        return np.bytes_(v.encode("utf-8"))
    if isinstance(v, int):
        return np.int64(v)
    return np.float64(v)


def _write_attributes(f, attributes):
    for name, v in attributes.items():
        if v is not None:
            f.attrs[name] = _attribute_value(v)


def _write_datasets(f, data, units):
    for name, x in data.items():
        d = f.create_dataset(name, data=x, dtype=np.float64, track_times=False)
        d.attrs["units"] = np.bytes_(units[name].encode("utf-8"))


def _write_atomically(path, what, overwrite, write, check):
    """Writes `path` through `<path>.<pid>.partial`: write(h5py file), then check(partial) (a
    JamioError naming the partial file is a bug here, reported against path), then the
    rename; the partial file is removed on any error."""
    path = os.fspath(path)
    try:
        _target(path, overwrite)
    except Invalid as e:
        raise JamioError(path, f"{what}: {e}") from None
    partial = f"{path}.{os.getpid()}.partial"
    try:
        with h5py.File(partial, "w") as f:
            write(f)
        check(partial)
        _publish(partial, path, overwrite)
    except Invalid as e:
        raise JamioError(path, f"{what}: {e}") from None
    except JamioError as e:
        raise JamioError(path, f"{what}: the written file was refused ({e.problem})") from e
    except (OSError, RuntimeError, ValueError, TypeError) as e:
        raise JamioError(path, f"{what}: cannot be written ({cause(e)})") from e
    finally:
        with contextlib.suppress(OSError):
            os.unlink(partial)  # nothing left behind (gone already once renamed)


def _root(what, dim, n, rate, phi_init, simulator, simulator_version, sample, diameter_ratio,
          contact, dynamics, q, jamming_packing_fraction, source, source_checksum, interpolation,
          path):
    """The root attributes of an open run, checked; a JamioError naming path otherwise."""
    given = {"format": FORMAT, "format_version": FORMAT_VERSION, "dim": dim, "n": n,
             "diameter_ratio": diameter_ratio, "contact": contact, "dynamics": dynamics, "q": q,
             "protocol": PROTOCOL, "compression_rate": rate, "phi_init": phi_init,
             "simulator": simulator, "simulator_version": simulator_version, "sample": sample,
             "units": UNITS, "jamming_packing_fraction": jamming_packing_fraction,
             "source": source, "source_checksum": source_checksum,
             "interpolation": interpolation}
    try:
        if sample is None:
            raise Invalid("sample missing: every run has a sample id >= 0")
        return _model(given)
    except Invalid as e:
        raise JamioError(path, f"{what}: {e}") from None


def write_run(path, packing_fraction, pressure, *, dim, n, rate, phi_init, simulator,
              simulator_version="", sample, diameter_ratio=1.4, contact="harmonic",
              dynamics="overdamped", q=None, contacts_per_particle=None,
              energy_per_particle=None, time=None, jamming_packing_fraction=None, source=None,
              source_checksum=None, interpolation=None, overwrite=False):
    """Writes one compression run as an open run file (docs/cross-simulator.md) at `path`.

    packing_fraction, pressure (and the optional contacts_per_particle, energy_per_particle,
    time): one value per output point, in jam's units (lengths d_s, energies k_e, times t0,
    pressure k_e/d_s^D). rate is the strain rate (attribute compression_rate), q the quality
    factor of inertial dynamics (only with dynamics="inertial"). Every field is checked as the
    format says before anything is written; the file is written as `<path>.<pid>.partial` and
    renamed when complete. An existing path is refused unless overwrite=True; a directory or
    special file always. Returns the run as validate_run reads it back (an OpenRun).
    Raises JamioError, one line naming path, the field and the value."""
    path = os.fspath(path)
    what = "write_run"
    model = _root(what, dim, n, rate, phi_init, simulator, simulator_version, sample,
                  diameter_ratio, contact, dynamics, q, jamming_packing_fraction, source,
                  source_checksum, interpolation, path)
    given = {"packing_fraction": packing_fraction, "pressure": pressure,
             "contacts_per_particle": contacts_per_particle,
             "energy_per_particle": energy_per_particle, "time": time}
    try:
        data = {k: _array(k, v) for k, v in given.items() if v is not None}
        _series(data, model)
    except Invalid as e:
        raise JamioError(path, f"{what}: {e}") from None

    def write(f):
        _write_attributes(f, {k: model[k] for k in ATTRIBUTES + OPTIONAL_ATTRIBUTES})
        _write_datasets(f, data, SERIES_UNITS)

    _write_atomically(path, what, overwrite, write, validate_run)
    return validate_run(path)


# ---- configuration frames (`jam import frames`) -------------------------------------------------

def particle_volume(dim, diameter):
    """The area (2D) or volume (3D) of a particle of the given diameter."""
    return math.pi * diameter ** 2 / 4 if dim == 2 else math.pi * diameter ** 3 / 6


def packing_fraction_of(dim, n, diameter_ratio, box_length):
    """phi of N/2 small (d = 1) and N/2 big (d = diameter_ratio) particles in a square or cubic
    box of side box_length (a number or an array)."""
    solids = n / 2 * (particle_volume(dim, 1.0) + particle_volume(dim, diameter_ratio))
    return solids / np.asarray(box_length, dtype=np.float64) ** dim


def _diameters(d, n, ratio):
    """Each diameter exactly 1 or the ratio, N/2 of each (all 1 when the ratio is 1)."""
    small, big = int(np.count_nonzero(d == 1.0)), int(np.count_nonzero(d == ratio))
    other = _first_bad((d != 1.0) & (d != ratio))
    if other is not None:
        raise Invalid(f"diameters[{other}] = {shown(float(d[other]))} is neither 1 nor "
                      f"diameter_ratio {shown(ratio)}")
    if ratio != 1.0 and (small, big) != (n // 2, n // 2):
        raise Invalid(f"diameters hold {small} of 1 and {big} of {shown(ratio)}; expected "
                      f"{n // 2} of each (half small, half big)")


def write_frames(path, box_length, positions, diameters, *, dim, n, rate, phi_init, simulator,
                 simulator_version="", sample, diameter_ratio=1.4, contact="harmonic",
                 dynamics="overdamped", q=None, time=None, source=None, source_checksum=None,
                 overwrite=False):
    """Writes a configuration frames file (docs/cross-simulator.md, "Configuration frames"),
    the input of `jam import frames FRAMES --out RUN`, which measures p, Z and the energy
    itself: the root attributes of an open run, and the datasets box_length (M), positions
    (M, N, D), diameters (N) and optionally time (M), float64, in d_s and t0.

    Checked before anything is written, as jam will: the attributes as in write_run; M >= 2
    frames; shapes; finite positions; each diameter 1 or diameter_ratio, N/2 of each; the
    packing fraction from box_length and the diameters in (0, 1), increasing strictly, the
    first not below phi_init, and with time phi(t) = phi_init exp(D rate t) to 1e-6. Written
    through `<path>.<pid>.partial` as write_run does. Raises JamioError naming path, the field
    and the value."""
    path = os.fspath(path)
    what = "write_frames"
    model = _root(what, dim, n, rate, phi_init, simulator, simulator_version, sample,
                  diameter_ratio, contact, dynamics, q, None, source, source_checksum, None,
                  path)
    d, m_n = model["dim"], model["n"]
    try:
        lengths = _array("box_length", box_length)
        x = _array("positions", positions, ndim=3)
        diam = _array("diameters", diameters)
        series = {"box_length": len(lengths)}
        t = None
        if time is not None:
            t = _array("time", time)
            series["time"] = len(t)
        m = _lengths(series)
        if x.shape != (m, m_n, d):
            raise Invalid(f"positions has shape {x.shape}, expected (frames, n, dim) = "
                          f"{(m, m_n, d)}")
        if diam.shape != (m_n,):
            raise Invalid(f"diameters has shape {diam.shape}, expected (n,) = ({m_n},)")
        _finite("box_length", lengths)
        k = _first_bad(lengths <= 0)
        if k is not None:
            raise Invalid(f"box_length[{k}] = {shown(float(lengths[k]))} must be > 0")
        bad = np.flatnonzero(~np.isfinite(x).all(axis=2))
        if bad.size:
            frame, particle = divmod(int(bad[0]), m_n)
            raise Invalid(f"positions[{frame}, {particle}] = {x[frame, particle].tolist()} "
                          "must be finite")
        _diameters(diam, m_n, model["diameter_ratio"])
        phi = packing_fraction_of(d, m_n, model["diameter_ratio"], lengths)
        _packing("packing fraction from box_length", phi, model["phi_init"])
        if t is not None:
            _time(t)
            _at_rate("packing fraction from box_length", phi, t, model["phi_init"],
                     model["compression_rate"], d)
    except Invalid as e:
        raise JamioError(path, f"{what}: {e}") from None
    data = {"box_length": lengths, "positions": x, "diameters": diam}
    if t is not None:
        data["time"] = t

    def write(f):
        _write_attributes(f, {k: model[k] for k in ATTRIBUTES + OPTIONAL_ATTRIBUTES})
        _write_datasets(f, data, FRAMES_UNITS)

    _write_atomically(path, what, overwrite, write, lambda p: None)


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


def _root_attributes(f):
    """The format's root attributes of f (absent: not in the dict), and whether f is a run
    file of jam's own."""
    native = "format" not in f.attrs and "checksum" in f.attrs
    if "format" not in f.attrs and not native:
        raise Invalid("attribute 'format' missing: neither an open run (format "
                      f"{FORMAT!r}) nor a run file of jam's own (attribute 'checksum')")
    names = ATTRIBUTES + OPTIONAL_ATTRIBUTES + (("version", "checksum") if native else ())
    a = {k: _scalar_attribute(f, k) for k in names if k in f.attrs}
    if native:
        # jam's own run files: simulator "jam" at its version; protocol and units need not be
        # stated (their `units` is a sentence), q is 0 for overdamped runs, sample is there
        # for campaign runs only; files from before the contact law was a choice are harmonic.
        version = _string("version", a.get("version", ""))
        a.update(format=FORMAT, format_version=FORMAT_VERSION, protocol=PROTOCOL, units=UNITS,
                 simulator="jam", simulator_version=version, _native=True)
        a.setdefault("contact", "harmonic")
    for k in ATTRIBUTES:
        if k not in a and k not in ("q", "sample"):
            raise Invalid(f"attribute '{k}' missing")
    if not native and "sample" not in a:
        raise Invalid("attribute 'sample' missing")
    return a, native


def _read_series(f):
    """The series of f as float64 arrays: each an HDF5 dataset of one dimension of floats, all
    of one length, its units attribute (if any) the format's; shapes, types and sizes checked
    before any value is read."""
    datasets = {}
    for name in SERIES_UNITS:
        if name not in f:
            if name in REQUIRED_SERIES:
                raise Invalid(f"dataset '{name}' missing")
            continue
        d = f.get(name)
        if not isinstance(d, h5py.Dataset):
            raise Invalid(f"'{name}' is not a dataset")
        if len(d.shape) != 1:
            raise Invalid(f"dataset '{name}' has shape {d.shape}, expected one dimension")
        if d.dtype.kind != "f" or d.dtype.names or d.dtype.subdtype is not None:
            raise Invalid(f"dataset '{name}' is {_kind(d.dtype)}, expected floating point")
        datasets[name] = d
    _lengths({k: d.shape[0] for k, d in datasets.items()})
    units = {}
    for name, d in datasets.items():
        if "units" in d.attrs:
            u = _scalar_attribute(d, "units", where=f"dataset '{name}': attribute")
            if u != SERIES_UNITS[name]:
                raise Invalid(f"dataset '{name}' has units {shown(u)}, expected "
                              f"{shown(SERIES_UNITS[name])}")
            units[name] = u
    data = {}
    for name, d in datasets.items():
        try:
            _check_size(d)
        except ValueError as e:
            raise Invalid(str(e)) from e
        data[name] = np.asarray(d[()], dtype=np.float64)
    return data, units


def _read_run(path, f):
    try:
        a, native = _root_attributes(f)
        model = _model(a)
        data, units = _read_series(f)
        _series(data, model)
    except Invalid as e:
        raise JamioError(path, str(e)) from None
    del model["format"], model["format_version"], model["protocol"], model["units"]
    run = OpenRun(path=path, native=native, data=data, series_units=units, **model)
    if not native:
        run.format, run.format_version, run.protocol, run.units = (
            FORMAT, FORMAT_VERSION, PROTOCOL, UNITS)
    return run


def validate_run(path):
    """Reads the run file at `path` and checks it as the open run format says
    (docs/cross-simulator.md): every root attribute one value of its type and within its
    range, the series one-dimensional float datasets of one length (shapes before values),
    their units attributes, values and the compression rate. A run file of jam's own
    (recognised by its `checksum` and no `format`) is read as simulator "jam" at its
    `version`; its checksum is not verified here (jam does that).

    Returns an OpenRun; raises JamioError, one line naming the file, the field and the value."""
    path = os.fspath(path)
    return read_hdf5(path, "run file", lambda f: _read_run(path, f))


__all__ = ["OpenRun", "packing_fraction_of", "validate_run", "write_frames", "write_run"]
