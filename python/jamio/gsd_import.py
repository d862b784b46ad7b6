"""A HOOMD-blue GSD trajectory of one compression run -> an open run (docs/cross-simulator.md).

    import_gsd(gsd_path, out_path, *, rate, dt, sample, ...)
    python3 -m jamio.gsd_import GSD --out RUN.h5 --rate R --dt DT --sample K [--pressure-key KEY]

Each frame is one output point. Read per frame: the box (square or cubic, without tilt), the
dimensions, N, the diameters (N/2 of 1 and N/2 of diameter_ratio), the positions and the step;
t = (step - first step) dt. The packing fraction from the box must follow phi_init exp(D rate t)
to 1e-6 relative (phi_init: the first frame's, or the one given, which must agree with it to
1e-6): a box that does not shrink at the stated rate is refused, naming the frame. GSD stores
the box in single precision, so the packing written is phi_init exp(D rate t) at each frame's
time, which the box has been checked to match.

With a pressure logged in the trajectory (`pressure_key`, a `log/...` chunk, e.g.
`log/md/compute/ThermodynamicQuantities/pressure`: it must be the virial of the contacts alone,
in jam's units) the run is written by write_run, simulator "hoomd-blue". Without one the frames
go to jam (`jam import frames FRAMES --out RUN`), which measures p, Z and the energy itself
with the contact law named; the frames file is written by write_frames, beside the output,
and removed afterwards. Nothing is left behind on an error.

Needs gsd (Debian: python3-gsd); the rest of jamio does not.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys

import numpy as np

from .errors import JamioError, cause, reading, require_file, shown
from .open_run import (CONTACTS, DYNAMICS, RATE_TOLERANCE, Invalid, _diameter_ratio, _one_of,
                       _phi_init, _positive, _sample, validate_run)
from .output import Unwritable, check_target, claim_temporary, publish, remove
from .write import packing_fraction_of, write_frames, write_run

SIMULATOR = "hoomd-blue"
# Diameters and boxes are single precision in a GSD file.
SINGLE = 1e-6
INTERPOLATION = ("none: one output point per GSD frame; packing_fraction is phi_init exp(D rate "
                 "t) at the frame's step, which its box (single precision) matches to 1e-6")


def _gsd():
    try:
        import gsd
        import gsd.hoomd
    except ImportError:
        raise ImportError("jamio.gsd_import needs gsd, which cannot be imported; install "
                          "python3-gsd (Debian) or pip install gsd") from None
    return gsd


def _open(gsd_module, path):
    """The trajectory, read only (the mode's name changed in gsd 3)."""
    major = int(str(gsd_module.__version__).split(".")[0])
    return gsd_module.hoomd.open(path, mode="r" if major >= 3 else "rb")


class Trajectory:
    """What import_gsd reads of a GSD file: dim, n, steps (M), box_lengths (M, D), diameters
    (N, as stored), positions (M, N, D) float64, pressure (M) or None."""

    def __init__(self, dim, n, steps, box_lengths, diameters, positions, pressure):
        self.dim, self.n, self.steps = dim, n, steps
        self.box_lengths, self.diameters, self.positions = box_lengths, diameters, positions
        self.pressure = pressure


def _log_key(key):
    key = key if key.startswith("log/") else f"log/{key}"
    if key == "log/":
        raise Invalid("pressure key '' names no log entry")
    return key


def _frame_box(i, box, dim):
    """The side lengths of frame i's box (D of them), refused unless square or cubic, without
    tilt, finite and positive."""
    box = np.asarray(box, dtype=np.float64).reshape(-1)
    if box.shape != (6,):
        raise Invalid(f"frame {i}: configuration/box has {box.size} values, expected 6")
    for name, tilt in zip(("xy", "xz", "yz"), box[3:]):
        if tilt != 0:
            raise Invalid(f"frame {i}: configuration/box tilt {name} = {shown(float(tilt))}; "
                          "only a square or cubic box without tilt is imported")
    sides = box[:dim]
    for name, length in zip("xyz", sides):
        if not (math.isfinite(length) and length > 0):
            raise Invalid(f"frame {i}: configuration/box L{name} = {shown(float(length))} must "
                          "be > 0 and finite")
    if np.max(np.abs(sides / sides[0] - 1)) > SINGLE:
        shape = " x ".join(f"{float(s):.9g}" for s in sides)
        raise Invalid(f"frame {i}: configuration/box is {shape}, not "
                      f"{'square' if dim == 2 else 'cubic'}")
    return sides


def _frame_diameters(i, d, n, ratio):
    """Frame i's diameters, each 1 or the ratio to single precision, N/2 of each; returned as
    the exact values."""
    d = np.asarray(d, dtype=np.float64)
    if d.shape != (n,):
        raise Invalid(f"frame {i}: particles/diameter has shape {d.shape}, expected ({n},)")
    small = np.abs(d - 1.0) <= SINGLE
    big = np.abs(d / ratio - 1.0) <= SINGLE
    other = np.flatnonzero(~(small | big))
    if other.size:
        k = int(other[0])
        raise Invalid(f"frame {i}: particles/diameter[{k}] = {float(d[k]):.9g} is neither 1 nor "
                      f"diameter_ratio {shown(ratio)}")
    if ratio == 1.0:
        return np.ones(n)
    counts = int(np.count_nonzero(small)), int(np.count_nonzero(big))
    if counts != (n // 2, n // 2):
        raise Invalid(f"frame {i}: particles/diameter holds {counts[0]} of 1 and {counts[1]} of "
                      f"{shown(ratio)}; expected {n // 2} of each (diameter_ratio "
                      f"{shown(ratio)}, half small, half big)")
    return np.where(small, 1.0, ratio)


def _pressure(traj, i, key):
    if not traj.file.chunk_exists(frame=i, name=key):
        raise Invalid(f"frame {i} has no {key} (the pressure key)")
    p = np.asarray(traj.file.read_chunk(frame=i, name=key))
    if p.size != 1 or p.dtype.kind not in "iuf":
        raise Invalid(f"frame {i}: {key} holds {p.size} values of {p.dtype}, expected one number")
    return float(p.reshape(-1)[0])


def read_trajectory(gsd_path, diameter_ratio=1.4, pressure_key=None, positions=True):
    """The frames of a GSD file, each checked (box, dimensions, N, diameters, steps increasing,
    the pressure if a key is given). Raises JamioError naming the file, the frame, the field
    and the value."""
    gsd_module = _gsd()
    path = os.fspath(gsd_path)
    require_file(path, "GSD file")
    with reading(path, "GSD file"), _open(gsd_module, path) as traj:
        try:
            return _read(traj, diameter_ratio, pressure_key, positions)
        except Invalid as e:  # inside: `reading` would take it for a damaged file
            raise JamioError(path, str(e)) from None


def _read(traj, ratio, pressure_key, positions):
    m = len(traj)
    if m < 2:
        raise Invalid(f"has {m} frame{'s' if m != 1 else ''}; a run needs at least 2")
    key = None
    if pressure_key is not None:
        key = _log_key(pressure_key)
        logged = traj.file.find_matching_chunk_names("log/")
        if key not in logged:
            have = ", ".join(sorted(logged)) or "none"
            raise Invalid(f"pressure key {shown(key)} is not in the file (logged: "
                          f"{shown(have, 200)})")
    first = traj[0]
    dim = int(first.configuration.dimensions)
    if dim not in (2, 3):
        raise Invalid(f"frame 0: configuration/dimensions {dim} must be 2 or 3")
    n = int(first.particles.N)
    steps, lengths, xs, pressure = [], [], [], []
    diameters = None
    for i in range(m):
        frame = first if i == 0 else traj[i]
        d = int(frame.configuration.dimensions)
        if d != dim:
            raise Invalid(f"frame {i}: configuration/dimensions {d} differs from frame 0's {dim}")
        if int(frame.particles.N) != n:
            raise Invalid(f"frame {i}: particles/N {int(frame.particles.N)} differs from frame "
                          f"0's {n}")
        lengths.append(_frame_box(i, frame.configuration.box, dim))
        exact = _frame_diameters(i, frame.particles.diameter, n, ratio)
        diameters = exact if diameters is None else diameters
        if not np.array_equal(exact, diameters):
            k = int(np.flatnonzero(exact != diameters)[0])
            raise Invalid(f"frame {i}: particles/diameter[{k}] = {exact[k]:g} differs from "
                          f"frame 0's {diameters[k]:g}")
        step = int(frame.configuration.step)
        if steps and step <= steps[-1]:
            raise Invalid(f"frame {i}: configuration/step {step} is not after frame {i - 1}'s "
                          f"{steps[-1]}")
        steps.append(step)
        if positions:
            x = np.asarray(frame.particles.position, dtype=np.float64).reshape(n, 3)[:, :dim]
            bad = np.flatnonzero(~np.isfinite(x).all(axis=1))
            if bad.size:
                raise Invalid(f"frame {i}: particles/position[{int(bad[0])}] = "
                              f"{x[bad[0]].tolist()} must be finite")
            xs.append(x)
        if key is not None:
            pressure.append(_pressure(traj, i, key))
    return Trajectory(dim, n, np.array(steps, dtype=np.int64), np.array(lengths), diameters,
                      np.array(xs) if positions else None,
                      np.array(pressure) if key is not None else None)


def _packing(traj, ratio, phi_init, rate, dt):
    """time, phi_init and the packing at each frame, phi_init exp(D rate t), after checking the
    boxes follow it to 1e-6."""
    t = (traj.steps - traj.steps[0]).astype(np.float64) * dt
    solids = packing_fraction_of(traj.dim, traj.n, ratio, 1.0)
    phi = solids / np.prod(traj.box_lengths, axis=1)
    if phi_init is None:
        phi_init = float(phi[0])
        if not 0 < phi_init < 1:
            raise Invalid(f"frame 0: the packing fraction {phi_init:.9g} from configuration/box "
                          f"{traj.box_lengths[0, 0]:.9g} must be in (0, 1)")
    elif abs(phi[0] / phi_init - 1) > RATE_TOLERANCE:
        raise Invalid(f"phi_init {shown(phi_init)} differs from frame 0's packing fraction "
                      f"{phi[0]:.9g} (configuration/box {traj.box_lengths[0, 0]:.9g}) by "
                      f"{phi[0] / phi_init - 1:.3g} relative (at most {RATE_TOLERANCE:g})")
    expected = phi_init * np.exp(traj.dim * rate * t)
    off = phi / expected - 1
    bad = np.flatnonzero(~(np.abs(off) <= RATE_TOLERANCE))
    if bad.size:
        k = int(bad[0])
        raise Invalid(f"frame {k} (step {int(traj.steps[k])}, t {t[k]:.9g}): packing fraction "
                      f"{phi[k]:.9g} from configuration/box {traj.box_lengths[k, 0]:.9g} is not "
                      f"phi_init exp(D rate t) = {expected[k]:.9g} at rate {shown(rate)} "
                      f"(relative difference {off[k]:.3g}, at most {RATE_TOLERANCE:g}): the box "
                      "does not shrink at the stated rate")
    return t, phi_init, expected


def _arguments(rate, dt, sample, phi_init, diameter_ratio, contact, dynamics, q):
    """The import's own arguments, checked before the trajectory is read."""
    _positive("compression_rate", rate)
    _positive("dt", dt)
    _sample(sample)
    if phi_init is not None:
        _phi_init(phi_init)
    _diameter_ratio(diameter_ratio)
    _one_of("contact", contact, CONTACTS)
    _one_of("dynamics", dynamics, DYNAMICS)
    if dynamics == "inertial" and q is None:
        raise Invalid("q missing: dynamics 'inertial' needs the quality factor q > 0")


def _run_jam(jam, frames, out):
    """jam import frames FRAMES --out OUT (an argument vector, no shell); its one-line error
    otherwise."""
    cmd = [jam, "import", "frames", frames, "--out", out]
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, errors="replace", check=False)
    except OSError as e:
        raise Invalid(f"jam {shown(jam, 1000)} cannot be run ({cause(e)}); give its path "
                      "(jam=..., --jam PATH)") from None
    if r.returncode != 0:
        lines = [line for line in r.stderr.splitlines() if line.strip()]
        said = lines[-1] if lines else "(no message)"
        raise Invalid(f"jam import frames exited {r.returncode}: {said}")


def import_gsd(gsd_path, out_path, *, rate, dt, sample, phi_init=None, simulator_version="",
               diameter_ratio=1.4, contact="harmonic", dynamics="overdamped", q=None,
               pressure_key=None, jam=None, overwrite=False):
    """Imports a HOOMD-blue GSD trajectory of one compression run as the open run out_path.

    rate: the strain rate, dL/dt = -rate L (1/t0); dt: the time step (t0), so that frame k is
    at t = (step_k - step_0) dt; sample: the run's sample id. phi_init: the packing fraction
    at t = 0 (default: the first frame's; if given it must agree with it to 1e-6). The box must
    follow phi_init exp(D rate t) to 1e-6 at every frame.

    pressure_key given (`log/...`): the pressure is taken from that log entry of every frame
    and the run written with write_run. Otherwise jam measures it: the frames are written with
    write_frames and `jam import frames` is run (jam: its path, default `jam` on PATH).
    out_path is refused if it exists (unless overwrite) or is a directory or special file.
    Returns the written run (validate_run). Raises JamioError, one line naming the file, the
    field and the value; nothing is written then."""
    gsd_path, out_path = os.fspath(gsd_path), os.fspath(out_path)
    try:
        check_target(out_path, overwrite, "run")
        _arguments(rate, dt, sample, phi_init, diameter_ratio, contact, dynamics, q)
    except (Invalid, Unwritable) as e:
        raise JamioError(out_path, f"import_gsd: {e}") from None
    traj = read_trajectory(gsd_path, float(diameter_ratio), pressure_key,
                           positions=pressure_key is None)
    try:
        t, phi_init, phi = _packing(traj, float(diameter_ratio),
                                    None if phi_init is None else float(phi_init), float(rate),
                                    float(dt))
    except Invalid as e:
        raise JamioError(gsd_path, str(e)) from None
    common = dict(dim=traj.dim, n=traj.n, rate=rate, phi_init=phi_init, simulator=SIMULATOR,
                  simulator_version=simulator_version, sample=sample,
                  diameter_ratio=diameter_ratio, contact=contact, dynamics=dynamics, q=q,
                  source=os.path.abspath(gsd_path))
    if pressure_key is not None:
        return write_run(out_path, phi, traj.pressure, time=t, interpolation=INTERPOLATION,
                         overwrite=overwrite, **common)
    # jam measures: the frames with the box of each frame's packing (as the run's), the
    # diameters exact; jam writes into a directory of ours, published when it validates.
    box = (packing_fraction_of(traj.dim, traj.n, float(diameter_ratio), 1.0) / phi) ** (
        1.0 / traj.dim)
    try:
        work = claim_temporary(out_path, directory=True)
    except (OSError, Unwritable) as e:
        raise JamioError(out_path, f"import_gsd: cannot be written ({cause(e)})") from e
    try:
        frames = os.path.join(work, "frames.h5")
        run = os.path.join(work, "run.h5")
        write_frames(frames, box, traj.positions, traj.diameters, time=t, **common)
        _run_jam(jam or "jam", frames, run)
        try:
            validate_run(run)
        except JamioError as e:
            raise Invalid(f"the run jam import frames wrote is refused: {e.problem}") from e
        publish(run, out_path, overwrite)
    except (Invalid, Unwritable) as e:
        raise JamioError(out_path, f"import_gsd: {e}") from None
    except JamioError as e:
        raise JamioError(out_path, f"import_gsd: {e.problem}") from e
    except OSError as e:
        raise JamioError(out_path, f"import_gsd: cannot be written ({cause(e)})") from e
    finally:
        remove(work)
    return validate_run(out_path)


# ---- command line -------------------------------------------------------------------------------

class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(2, f"{self.prog}: {message} (--help for usage)\n")


def main(argv=None):
    parser = _Parser(prog="python3 -m jamio.gsd_import",
                     description="A HOOMD-blue GSD trajectory of one compression run -> an open "
                                 "run file (docs/cross-simulator.md).")
    parser.add_argument("gsd", metavar="GSD", help="the trajectory, one frame per output point")
    parser.add_argument("--out", required=True, metavar="RUN.h5", help="the run file to write")
    parser.add_argument("--rate", required=True, type=float, help="strain rate, 1/t0")
    parser.add_argument("--dt", required=True, type=float, help="time step, t0 (t = step dt)")
    parser.add_argument("--sample", required=True, type=int, help="the run's sample id, >= 0")
    parser.add_argument("--pressure-key", metavar="KEY",
                        help="the logged pressure, e.g. "
                             "log/md/compute/ThermodynamicQuantities/pressure "
                             "(default: jam measures it from the configurations)")
    parser.add_argument("--phi-init", type=float, metavar="X",
                        help="packing fraction at t = 0 (default: the first frame's)")
    parser.add_argument("--diameter-ratio", type=float, default=1.4, metavar="R",
                        help="d_big / d_small (default 1.4)")
    parser.add_argument("--contact", default="harmonic", choices=CONTACTS,
                        help="contact law (default harmonic)")
    parser.add_argument("--dynamics", default="overdamped", choices=DYNAMICS,
                        help="default overdamped")
    parser.add_argument("--q", type=float, help="quality factor Q (inertial dynamics only)")
    parser.add_argument("--simulator-version", default="", metavar="TEXT",
                        help="HOOMD-blue's version (free text)")
    parser.add_argument("--jam", metavar="PATH", help="the jam binary (default: jam on PATH)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing RUN.h5")
    a = parser.parse_args(argv)
    try:
        run = import_gsd(a.gsd, a.out, rate=a.rate, dt=a.dt, sample=a.sample,
                         phi_init=a.phi_init, simulator_version=a.simulator_version,
                         diameter_ratio=a.diameter_ratio, contact=a.contact,
                         dynamics=a.dynamics, q=a.q, pressure_key=a.pressure_key, jam=a.jam,
                         overwrite=a.overwrite)
    except (JamioError, ImportError) as e:
        print(f"{parser.prog}: {e}", file=sys.stderr)
        return 2
    print(f"wrote {run.path}: {run.points} frames, phi {run['packing_fraction'][0]:.6g} to "
          f"{run['packing_fraction'][-1]:.6g}")
    return 0


__all__ = ["import_gsd", "main", "read_trajectory", "write_frames"]

if __name__ == "__main__":
    sys.exit(main())
