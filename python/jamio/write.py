"""Writing an open run (docs/cross-simulator.md) from Python, and a frames file for `jam import
frames`:

    write_run(path, packing_fraction, pressure, *, dim, n, rate, phi_init, simulator, sample, ...)
                             one compression run of any simulator -> an open run file
    write_frames(path, box_length, positions, diameters, *, dim, n, rate, phi_init, ...)
                             configurations without pressure -> a frames file

Every rule of the format (open_run.py) is checked before anything is written, and the written
file is read back with validate_run before it gets its name: it is written as
`<path>.<pid>.partial` and renamed to `path` only when complete, so nothing is left behind on an
error and a file under its final name is always a run the readers take. A violation raises
JamioError, one line naming the file, the field and the value (`run.h5: write_run:
diameter_ratio 2.5 must be in [1, 2]`).
"""

from __future__ import annotations

import math
import os

import h5py
import numpy as np

from .errors import JamioError, cause, shown
from .output import Unwritable, check_target, claim_temporary, publish, remove
from .open_run import (ATTRIBUTES, FORMAT, FORMAT_VERSION, FRAMES_UNITS, LIMITS,
                       OPTIONAL_ATTRIBUTES, PROTOCOL, SERIES_UNITS, UNITS, Invalid, OpenRun,
                       _array, _at_rate,
                       _finite, _first_bad, _lengths, _model, _packing, _series, _time,
                       validate_run)

# ---- writing ------------------------------------------------------------------------------------


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
    """Writes `path` through a temporary file of its own (claim_temporary): write(h5py file),
    then check(partial) (a JamioError naming the partial file is a bug here, reported against
    path), then the rename; the temporary file is removed on any error."""
    path = os.fspath(path)
    try:
        check_target(path, overwrite, "run")
    except Unwritable as e:
        raise JamioError(path, f"{what}: {e}") from None
    partial = None
    try:
        partial = claim_temporary(path)
        with h5py.File(partial, "w") as f:
            write(f)
        check(partial)
        publish(partial, path, overwrite)
        partial = None  # renamed: the name is no longer this call's to remove
    except (Invalid, Unwritable) as e:
        raise JamioError(path, f"{what}: {e}") from None
    except JamioError as e:
        raise JamioError(path, f"{what}: the written file was refused ({e.problem})") from e
    except (OSError, RuntimeError, ValueError, TypeError) as e:
        raise JamioError(path, f"{what}: cannot be written ({cause(e)})") from e
    finally:
        if partial is not None:  # nothing left behind, and nothing removed this call did not make
            remove(partial)


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
        # jam import frames reads the positions whole: its bounds on N and M (the schema's).
        for name, value, count in (("max_frame_particles", m_n, "n"),
                                   ("max_frames", m, "frames")):
            most = LIMITS[name]["value"]
            if value > most:
                raise Invalid(f"{count} {value} is more than a frames file holds (at most {most}: "
                              "jam import frames reads its positions whole)")
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


__all__ = ["OpenRun", "packing_fraction_of", "validate_run", "write_frames", "write_run"]
