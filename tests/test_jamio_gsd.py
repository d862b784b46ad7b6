#!/usr/bin/python3
"""jamio's HOOMD-blue import (python3 -m jamio.gsd_import, docs/cross-simulator.md).

import_gsd on GSD files written here with gsd.hoomd (a 2D system of 64 particles whose box
shrinks exactly at the stated rate, with a logged pressure): the pressure, packing and time
arrays equal what was logged and constructed; malformed trajectories (tilt, a non-square box,
wrong diameters, a box off the rate, a missing pressure key or a frame without it, phi_init off
the first frame) refused with the field named and nothing written; the command line (exit 2,
one line); the frames path with a stand-in jam (the argument vector, the frames file it gets,
its failure passed on, a run it writes that is refused); and with the real jam (`import
frames`: p, Z and E compared with a direct sum over pairs).

Usage (ctest runs it): python3 -m pytest tests/test_jamio_gsd.py --jam build/jam --source .
"""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from jamio_write_fixture import DIM, DT, KEY, N, PHI_INIT, RATE, RATIO, STEPS, jamio, only, refused


@pytest.fixture
def work(tmp_path):
    """The test's scratch directory, as a string."""
    return str(tmp_path)


def gsd_modules():
    import gsd
    import gsd.hoomd
    major = int(gsd.__version__.split(".")[0])
    frame_class = getattr(gsd.hoomd, "Frame", None) or gsd.hoomd.Snapshot
    return gsd.hoomd, frame_class, "w" if major >= 3 else "wb"


def solids(dim=DIM, n=N, ratio=RATIO):
    one = math.pi / 4 if dim == 2 else math.pi / 6
    return n / 2 * one * (1 + ratio ** dim)


def write_gsd(path, steps=STEPS, dim=DIM, n=N, phi_init=PHI_INIT, rate=RATE, dt=DT,
              ratio=RATIO, change=None, log=True):
    """A GSD trajectory of a box shrinking exactly at `rate` from phi_init at steps[0]; each
    frame's pressure logged (KEY). change(i, frame) may spoil frame i. Returns what was
    constructed: t, phi (exact), box (as stored, float32), pressure (as logged)."""
    hoomd, frame_class, mode = gsd_modules()
    t = (np.asarray(steps) - steps[0]) * dt
    phi = phi_init * np.exp(dim * rate * t)
    box = (solids(dim, n, ratio) / phi) ** (1 / dim)
    pressure = np.linspace(1e-4, 3e-3, len(steps)) ** 1.5
    rng = np.random.default_rng(7)
    typeid = rng.permutation(np.arange(n) % 2).astype(np.uint32)
    with hoomd.open(path, mode) as traj:
        for i, step in enumerate(steps):
            f = frame_class()
            f.configuration.step = int(step)
            f.configuration.dimensions = dim
            f.configuration.box = [box[i], box[i], box[i] if dim == 3 else 0, 0, 0, 0]
            f.particles.N = n
            f.particles.types = ["small", "big"]
            f.particles.typeid = typeid
            f.particles.diameter = np.where(typeid == 0, 1.0, ratio).astype(np.float32)
            x = np.zeros((n, 3), dtype=np.float32)
            x[:, :dim] = rng.uniform(-0.5, 0.5, (n, dim)) * box[i]
            f.particles.position = x
            if log:
                f.log[KEY[4:]] = np.array([pressure[i]], dtype=np.float64)
                f.log["md/compute/ThermodynamicQuantities/potential_energy"] = np.array([1.0])
            if change:
                change(i, f)
            traj.append(f)
    return dict(t=t, phi=phi, box=box.astype(np.float32), pressure=pressure, typeid=typeid)


def gsd_positions(path):
    """The positions of every frame, as stored (single precision) in float64."""
    hoomd, _, mode = gsd_modules()
    with hoomd.open(path, mode.replace("w", "r")) as traj:
        return np.array([np.asarray(f.particles.position, dtype=np.float64) for f in traj])


def test_gsd_import_pressure(source, work):
    from jamio.gsd_import import import_gsd
    gsd_path = os.path.join(work, "traj.gsd")
    made = write_gsd(gsd_path)
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out = os.path.join(outs, "run.h5")
    run = import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=4, phi_init=PHI_INIT,
                     simulator_version="4.2.1", pressure_key=KEY)
    only(outs, ["run.h5"])
    assert run.path == out, "returned run"
    run = jamio().validate_run(out)
    assert np.array_equal(run["pressure"], made["pressure"]), \
        f"pressure {run['pressure']} != logged {made['pressure']}"
    assert np.allclose(run["time"], made["t"], rtol=1e-15, atol=0), f"time {run['time']}"
    assert run["time"][0] == 0.0 and run["time"][-1] == (STEPS[-1] - STEPS[0]) * DT, \
        "time relative to the first frame"
    assert np.allclose(run["packing_fraction"], made["phi"], rtol=1e-14, atol=0), \
        f"packing {run['packing_fraction']} != constructed {made['phi']}"
    from_box = solids() / made["box"].astype(np.float64) ** 2  # the single-precision box
    assert np.all(np.abs(run["packing_fraction"] / from_box - 1) <= 1e-6), "packing vs box"
    assert run.phi_init == PHI_INIT and run.compression_rate == RATE and run.sample == 4, \
        "phi_init, rate, sample"
    assert (run.simulator, run.simulator_version) == ("hoomd-blue", "4.2.1"), "simulator"
    assert run.dim == 2 and run.n == N and run.diameter_ratio == RATIO, "dim, n, ratio"
    assert run.source == os.path.abspath(gsd_path), f"source {run.source}"
    assert run.interpolation.startswith("none"), f"interpolation {run.interpolation}"
    assert set(run.data) == {"packing_fraction", "pressure", "time"}, f"series {set(run.data)}"
    # phi_init left out: the first frame's (from its single-precision box); the key given
    # without its `log/`.
    out2 = os.path.join(outs, "run2.h5")
    run = import_gsd(gsd_path, out2, rate=RATE, dt=DT, sample=0, pressure_key=KEY[4:])
    assert math.isclose(run.phi_init, from_box[0], rel_tol=1e-15, abs_tol=0), \
        f"phi_init {run.phi_init} != frame 0's {from_box[0]}"
    assert np.allclose(run["packing_fraction"], from_box[0] * np.exp(2 * RATE * made["t"]),
                       rtol=1e-14, atol=0), "packing from the first frame's phi"
    # 3D, and the command line.
    gsd3 = os.path.join(work, "traj3.gsd")
    made3 = write_gsd(gsd3, dim=3, n=32, phi_init=0.6)
    out3 = os.path.join(outs, "run3.h5")
    r = subprocess.run([sys.executable, "-m", "jamio.gsd_import", gsd3, "--out", out3,
                        "--rate", str(RATE), "--dt", str(DT), "--sample", "2",
                        "--phi-init", "0.6", "--pressure-key", KEY], capture_output=True,
                       text=True, env=python_env(source), timeout=300)
    assert r.returncode == 0, f"command line exited {r.returncode}: {r.stderr}"
    run = jamio().validate_run(out3)
    assert run.dim == 3 and run.n == 32 and run.sample == 2, "3D attributes"
    assert np.array_equal(run["pressure"], made3["pressure"]), "3D pressure"
    assert np.allclose(run["packing_fraction"], made3["phi"], rtol=1e-14, atol=0), "3D packing"
    only(outs, ["run.h5", "run2.h5", "run3.h5"])


def python_env(source):
    path = os.path.join(source, "python")
    old = os.environ.get("PYTHONPATH")
    return dict(os.environ, PYTHONPATH=path + (os.pathsep + old if old else ""))


# Malformed trajectories: each changes one frame (i) of write_gsd's, f a gsd frame.


def tilt(i, f):
    if i == 2:
        f.configuration.box = list(f.configuration.box[:3]) + [0.1, 0, 0]


def oblong(i, f):
    if i == 1:
        b = list(f.configuration.box)
        f.configuration.box = [b[0], b[1] * 1.01] + b[2:]


def all_small(i, f):
    f.particles.diameter = np.ones(N, dtype=np.float32)


def ratio_12(i, f):
    f.particles.diameter = np.where(np.arange(N) % 2 == 0, 1.0, 1.2).astype(np.float32)


def off_rate(i, f):
    if i == 3:
        f.configuration.box = [b * 0.999 if k < 2 else b
                               for k, b in enumerate(f.configuration.box)]


def no_pressure(i, f):
    if i == 3:
        del f.log[KEY[4:]]


def same_step(i, f):
    if i == 2:
        f.configuration.step = STEPS[1]


def to_3d(i, f):
    if i == 4:
        f.configuration.dimensions = 3
        f.configuration.box = list(f.configuration.box[:2]) + [f.configuration.box[0],
                                                                 0, 0, 0]


def nan_position(i, f):
    if i == 1:
        f.particles.position[5, 0] = np.nan


# (file, write_gsd's arguments, import_gsd's, words of the refusal)
KW = dict(rate=RATE, dt=DT, sample=0, pressure_key=KEY)
GSD_REFUSALS = [
    ("tilt.gsd", dict(change=tilt), KW, ("frame 2", "configuration/box", "xy")),
    ("oblong.gsd", dict(change=oblong), KW, ("frame 1", "configuration/box", "not square")),
    ("small.gsd", dict(change=all_small), KW,
     ("frame 0", "particles/diameter", "64 of 1 and 0 of 1.4", "32 of each")),
    ("ratio.gsd", dict(change=ratio_12), KW,
     ("frame 0", "particles/diameter[1] = 1.20000005", "neither 1 nor diameter_ratio 1.4")),
    ("off_rate.gsd", dict(change=off_rate), KW,
     ("frame 3", "step 1400", "does not shrink at the stated rate")),
    ("rate.gsd", {}, dict(KW, rate=2 * RATE), ("frame 1", "rate 0.02", "does not shrink")),
    ("no_key.gsd", dict(log=False), KW, ("pressure key", KEY, "not in the file")),
    ("frame_no_pressure.gsd", dict(change=no_pressure), KW, ("frame 3 has no", KEY)),
    ("same_step.gsd", dict(change=same_step), KW,
     ("frame 2", "configuration/step 1100", "frame 1's 1100")),
    ("dims.gsd", dict(change=to_3d), KW, ("frame 4", "configuration/dimensions 3")),
    ("nan.gsd", dict(change=nan_position), dict(KW, pressure_key=None, jam="/nonexistent"),
     ("frame 1", "particles/position[5]", "finite")),
    ("phi_init.gsd", {}, dict(KW, phi_init=0.79), ("phi_init 0.79", "frame 0")),
    ("one_frame.gsd", dict(steps=STEPS[:1]), KW, ("1 frame", "at least 2")),
    ("ratio_arg.gsd", {}, dict(KW, diameter_ratio=2.5), ("diameter_ratio 2.5",)),
    ("dt.gsd", {}, dict(KW, dt=0.0), ("dt 0.0",)),
    ("q.gsd", {}, dict(KW, q=3.0), ("q 3.0", "inertial")),
]


@pytest.mark.parametrize("name, make, args, words", GSD_REFUSALS, ids=[c[0] for c in GSD_REFUSALS])
def test_gsd_refused(work, name, make, args, words):
    """Refused with the field named, nothing written."""
    from jamio.gsd_import import import_gsd
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    path = os.path.join(work, name)
    write_gsd(path, **make)
    refused(lambda: import_gsd(path, os.path.join(outs, "run.h5"), **args), *words)
    only(outs)


def test_gsd_not_a_trajectory_and_an_existing_output(work):
    from jamio.gsd_import import import_gsd
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out = os.path.join(outs, "run.h5")
    kw = KW
    not_gsd = os.path.join(work, "text.gsd")
    with open(not_gsd, "w") as f:
        f.write("not GSD\n")
    refused(lambda: import_gsd(not_gsd, out, **kw), "text.gsd", "not a readable GSD file")
    refused(lambda: import_gsd(os.path.join(work, "absent.gsd"), out, **kw), "absent.gsd",
            "missing")
    only(outs)
    # An existing output is kept (before the trajectory is read).
    with open(out, "wb") as f:
        f.write(b"keep me")
    good = os.path.join(work, "good.gsd")
    write_gsd(good)
    refused(lambda: import_gsd(good, out, **kw), "run.h5", "exists")
    with open(out, "rb") as f:
        assert f.read() == b"keep me", "the existing output was changed"
    import_gsd(good, out, overwrite=True, **kw)
    assert jamio().validate_run(out).points == len(STEPS), "overwritten"
    os.unlink(out)


def command_lines(work, out, good):
    """The command line's refusals: (arguments, words of the one line)."""
    return [
        ([os.path.join(work, "tilt.gsd"), "--out", out, "--rate", str(RATE), "--dt", str(DT),
          "--sample", "0", "--pressure-key", KEY], ("tilt.gsd", "xy")),
        ([good, "--out", out, "--rate", "-1", "--dt", str(DT), "--sample", "0"],
         ("compression_rate -1.0",)),
        ([good, "--out", out, "--rate", str(RATE), "--sample", "0"], ("--dt",)),
        ([good, "--out", out, "--rate", "fast", "--dt", str(DT), "--sample", "0"], ("--rate",)),
        ([good, "--out", out, "--rate", str(RATE), "--dt", str(DT), "--sample", "0",
          "--contact", "lj"], ("--contact", "lj")),
    ]


@pytest.mark.parametrize("k", range(5))
def test_gsd_command_line_refused(source, work, k):
    """One line, exit status 2, nothing written."""
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out, good = os.path.join(outs, "run.h5"), os.path.join(work, "good.gsd")
    write_gsd(good)
    write_gsd(os.path.join(work, "tilt.gsd"), change=tilt)
    argv, words = command_lines(work, out, good)[k]
    r = subprocess.run([sys.executable, "-m", "jamio.gsd_import"] + argv, capture_output=True,
                       text=True, env=python_env(source), timeout=300)
    said = r.stderr.strip()
    assert r.returncode == 2, f"{argv}: exit status {r.returncode} ({said})"
    assert "\n" not in said and all(w in said for w in words), \
        f"{argv}: stderr {said!r} lacks {words}"
    only(outs)


# ---- the frames path: a stand-in jam, then the real one ------------------------------------------

FAKE_JAM = r'''#!/usr/bin/python3
# A stand-in for `jam import frames FRAMES --out RUN`: records what it was given and writes an
# open run with jamio (pressure 0), or fails as FAKE_JAM_MODE says.
import json, os, sys
sys.path.insert(0, {python!r})
import h5py, numpy as np, jamio
argv = sys.argv[1:]
mode = os.environ.get("FAKE_JAM_MODE", "ok")
record = {{"argv": argv}}
if len(argv) == 5 and argv[:2] == ["import", "frames"] and argv[3] == "--out":
    with h5py.File(argv[2], "r") as f:
        record["attrs"] = {{k: (v.decode() if isinstance(v, bytes) else v.item())
                           for k, v in f.attrs.items()}}
        record["data"] = {{k: f[k][()].tolist() for k in f}}
with open(os.environ["FAKE_JAM_RECORD"], "w") as out:
    json.dump(record, out)
if mode == "fail":
    print("jam: frames.h5: positions: the solver diverged", file=sys.stderr)
    sys.exit(1)
if mode == "garbage":
    with open(argv[4], "w") as out:
        out.write("not a run")
    sys.exit(0)
a, d = record["attrs"], record["data"]
box, t = np.array(d["box_length"]), np.array(d["time"])
phi = jamio.write.packing_fraction_of(a["dim"], a["n"], a["diameter_ratio"], box)
jamio.write_run(argv[4], phi, np.zeros(len(box)), dim=a["dim"], n=a["n"],
                rate=a["compression_rate"], phi_init=a["phi_init"], simulator=a["simulator"],
                simulator_version=a["simulator_version"], sample=a["sample"],
                diameter_ratio=a["diameter_ratio"], contact=a["contact"], time=t,
                interpolation="none: measured by jam from configurations")
'''


def test_gsd_frames_stand_in(source, work):
    """import_gsd without a pressure: the frames file and the argument vector jam gets, its
    output published, its failures passed on with nothing left behind."""
    from jamio.gsd_import import import_gsd
    fake = os.path.join(work, "fake-jam")
    with open(fake, "w") as f:
        f.write(FAKE_JAM.format(python=os.path.join(source, "python")))
    os.chmod(fake, 0o755)
    record = os.path.join(work, "record.json")
    gsd_path = os.path.join(work, "traj.gsd")
    made = write_gsd(gsd_path, log=False)
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out = os.path.join(outs, "run.h5")
    saved = {k: os.environ.get(k) for k in ("FAKE_JAM_MODE", "FAKE_JAM_RECORD")}
    os.environ["FAKE_JAM_RECORD"] = record
    try:
        os.environ["FAKE_JAM_MODE"] = "ok"
        run = import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=5, phi_init=PHI_INIT,
                         jam=fake, simulator_version="4.2.1")
        only(outs, ["run.h5"])
        with open(record) as f:
            seen = json.load(f)
        argv = seen["argv"]
        assert argv[:2] == ["import", "frames"] and argv[3] == "--out" and len(argv) == 5, \
            f"argument vector {argv}"
        assert (os.path.dirname(argv[2]) == os.path.dirname(argv[4]) and
                os.path.dirname(os.path.dirname(argv[2])) == outs), \
            f"frames and run not in a directory beside the output: {argv}"
        a, d = seen["attrs"], seen["data"]
        expected = dict(format="jam-open-run", format_version=1, dim=2, n=N, diameter_ratio=1.4,
                        contact="harmonic", dynamics="overdamped",
                        protocol="isotropic-compression", compression_rate=RATE,
                        phi_init=PHI_INIT, simulator="hoomd-blue", simulator_version="4.2.1",
                        sample=5, units="jam", source=os.path.abspath(gsd_path))
        assert a == expected, f"frames attributes {a}"
        assert np.allclose(d["time"], made["t"], rtol=1e-15, atol=0), "frames time"
        phi = jamio().write.packing_fraction_of(2, N, RATIO, np.array(d["box_length"]))
        assert np.allclose(phi, made["phi"], rtol=1e-14, atol=0), "frames box_length"
        assert np.array_equal(d["diameters"], np.where(made["typeid"] == 0, 1.0, 1.4)), \
            "frames diameters"
        positions = gsd_positions(gsd_path)[:, :, :2]
        assert np.array_equal(np.array(d["positions"]), positions), "frames positions"
        assert run.simulator == "hoomd-blue" and np.array_equal(run["pressure"], np.zeros(6)), \
            "the run jam wrote, published"
        os.unlink(out)
        os.environ["FAKE_JAM_MODE"] = "fail"
        refused(lambda: import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=5, jam=fake),
                "run.h5", "jam import frames exited 1", "the solver diverged")
        only(outs)
        os.environ["FAKE_JAM_MODE"] = "garbage"
        refused(lambda: import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=5, jam=fake),
                "run.h5", "the run jam import frames wrote is refused")
        only(outs)
        refused(lambda: import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=5,
                                   jam=os.path.join(work, "no-such-jam")),
                "no-such-jam", "cannot be run")
        only(outs)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def jam_has_import_frames(jam):
    r = subprocess.run([jam, "import", "--help"], capture_output=True, text=True,
                       timeout=60)
    return r.returncode == 0 and any(line.split()[:1] == ["frames"]
                                     for line in r.stdout.splitlines())


def direct_sums(x, d, box, dim):
    """p, Z, E per particle of the harmonic contacts, by a sum over all pairs (minimum image)."""
    n = len(d)
    r = x[:, None, :] - x[None, :, :]
    r -= box * np.round(r / box)
    dist = np.sqrt((r ** 2).sum(axis=2))
    dij = (d[:, None] + d[None, :]) / 2
    upper = np.triu(np.ones((n, n), dtype=bool), 1)
    touching = upper & (dist < dij)
    overlap = np.where(touching, 1 - dist / dij, 0.0)
    virial = (overlap / dij * dist).sum()  # f r, f = (1/d)(1 - r/d)
    return (virial / (dim * box ** dim), 2 * touching.sum() / n,
            (0.5 * overlap ** 2).sum() / n)


def test_gsd_frames_jam(jam, work):
    # jam measures the frames: a jam without `import frames` is a failure, not a skip.
    assert jam_has_import_frames(jam), "the jam given has no `import frames`"
    from jamio.gsd_import import import_gsd
    gsd_path = os.path.join(work, "traj.gsd")
    made = write_gsd(gsd_path, log=False)
    out = os.path.join(work, "run.h5")
    run = import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=1, phi_init=PHI_INIT,
                     jam=jam)
    only(work, ["run.h5", "traj.gsd"])
    assert run.simulator == "hoomd-blue" and run.contact == "harmonic", "attributes"
    assert np.allclose(run["packing_fraction"], made["phi"], rtol=1e-12, atol=0), "packing"
    assert np.allclose(run["time"], made["t"], rtol=1e-12, atol=0), "time"
    assert "contacts_per_particle" in run and "energy_per_particle" in run, "Z and E measured"
    positions = gsd_positions(gsd_path)[:, :, :2]
    d = np.where(made["typeid"] == 0, 1.0, RATIO)
    box = (solids() / made["phi"]) ** 0.5
    for k in range(len(STEPS)):
        p, z, e = direct_sums(positions[k], d, box[k], 2)
        got = (run["pressure"][k], run["contacts_per_particle"][k], run["energy_per_particle"][k])
        assert np.allclose(got, (p, z, e), rtol=1e-9, atol=0), \
            f"frame {k}: jam's p, Z, E {got} != direct sums {(p, z, e)}"
    # A jam that fails without a word: its exit status reaches the caller, nothing is left.
    bad = os.path.join(work, "bad")
    os.mkdir(bad)
    refused(lambda: import_gsd(gsd_path, os.path.join(bad, "run.h5"), rate=RATE, dt=DT,
                               sample=1, contact="hertzian", jam="/bin/false"),
            "jam import frames exited 1")
    only(bad)
