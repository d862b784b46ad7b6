#!/usr/bin/python3
"""jamio's writers of the open run format (docs/cross-simulator.md) and the HOOMD-blue import.

write_run read back by validate_run and by h5py (every attribute, type and dataset as the format
says); every malformed input refused with one line naming the field and the value, and nothing
left behind (a pre-existing file kept, no `.partial`, also when the write fails midway);
validate_run on hand-made malformed files (a 2-D or undeclared-huge packing_fraction refused by
its shape before a value is read, array attributes, decreasing phi, phi off phi_init exp(D rate
t), missing attributes, wrong units, integer datasets) and on a run file of jam's own (`jam
sim`); write_frames' file (attributes, shapes, units) and its refusals; import_gsd on GSD files
written here with gsd.hoomd (a 2D system of 64 particles whose box shrinks exactly at the stated
rate, with a logged pressure): the pressure, packing and time arrays equal what was logged and
constructed; malformed trajectories (tilt, a non-square box, wrong diameters, a box off the
rate, a missing pressure key or a frame without it, phi_init off the first frame) refused with
the field named and nothing written; the command line (exit 2, one line); the frames path with
a stand-in jam (the argument vector, the frames file it gets, its failure passed on, a run it
writes that is refused); and with the real jam (`import frames`: p, Z and E compared with a
direct sum over pairs).

Usage (ctest runs it): test_jamio_write.py --jam build/jam --source .
Prints one line per case and a last line `N passed, M failed`; exit status 1 if any failed.
"""

import argparse
import contextlib
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ARGS = None
KEY = "log/md/compute/ThermodynamicQuantities/pressure"
N, DIM, RATE, DT, PHI_INIT, RATIO = 64, 2, 1e-2, 0.005, 0.8, 1.4
STEPS = (1000, 1100, 1200, 1400, 1600, 2000)


def jamio():
    import jamio as module
    return module


def refused(call, *words):
    """call() must raise JamioError, one line containing every word; its message."""
    try:
        call()
    except jamio().JamioError as e:
        message = str(e)
        if "\n" in message:
            raise AssertionError(f"message of more than one line: {message!r}")
        missing = [w for w in words if w not in message]
        if missing:
            raise AssertionError(f"message lacks {missing}: {message}")
        return message
    raise AssertionError(f"not refused (expected a message with {words})")


def only(directory, names=()):
    """The directory holds exactly `names` (nothing left behind)."""
    found = sorted(os.listdir(directory))
    if found != sorted(names):
        raise AssertionError(f"{directory} holds {found}, expected {sorted(names)}")


def check(condition, what):
    if not condition:
        raise AssertionError(what)


def series(m=6, phi_init=PHI_INIT, rate=RATE, dim=DIM):
    t = np.linspace(0.0, 3.0, m)
    phi = phi_init * np.exp(dim * rate * t)
    return t, phi


def good_run(**change):
    """The arguments of a valid write_run call (with every optional series), changed."""
    t, phi = series()
    kw = dict(packing_fraction=phi, pressure=np.linspace(0.0, 2e-3, len(t)), dim=DIM, n=N,
              rate=RATE, phi_init=PHI_INIT, simulator="my-gpu-code", simulator_version="1.2",
              sample=3, contacts_per_particle=np.linspace(0.0, 4.1, len(t)),
              energy_per_particle=np.linspace(0.0, 1e-4, len(t)), time=t)
    kw.update(change)
    return kw


def write(path, **change):
    kw = good_run(**change)
    return jamio().write_run(path, kw.pop("packing_fraction"), kw.pop("pressure"), **kw)


# ---- write_run and validate_run ------------------------------------------------------------------

def case_round_trip(work):
    out = os.path.join(work, "run.h5")
    change = dict(dynamics="inertial", q=2.5, diameter_ratio=1.25, contact="hertzian",
                  jamming_packing_fraction=0.8412, source="/data/traj.gsd",
                  source_checksum="0123456789abcdef", interpolation="none: every step")
    given = good_run(**change)
    returned = write(out, **change)
    only(work, ["run.h5"])
    run = jamio().validate_run(out)
    expected = dict(format="jam-open-run", format_version=1, dim=DIM, n=N, diameter_ratio=1.25,
                    contact="hertzian", dynamics="inertial", q=2.5,
                    protocol="isotropic-compression", compression_rate=RATE, phi_init=PHI_INIT,
                    simulator="my-gpu-code", simulator_version="1.2", sample=3, units="jam",
                    jamming_packing_fraction=0.8412, source="/data/traj.gsd",
                    source_checksum="0123456789abcdef", interpolation="none: every step",
                    native=False)
    for name, value in expected.items():
        got = getattr(run, name)
        check(got == value and type(got) is type(value), f"{name}: {got!r}, wrote {value!r}")
    check(returned.path == run.path and returned.sample == 3, "write_run's return value")
    names = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle",
             "time")
    check(sorted(run.data) == sorted(names), f"series {sorted(run.data)}")
    for name in names:
        check(np.array_equal(run[name], np.asarray(given[name], dtype=np.float64)),
              f"{name} read back differs")
    units = {"packing_fraction": "1", "pressure": "k_e/d_s^D", "contacts_per_particle": "1",
             "energy_per_particle": "k_e", "time": "t0"}
    check(run.series_units == units, f"units {run.series_units}")
    check("my-gpu-code" in repr(run) and "\n" not in repr(run), f"repr {repr(run)}")
    # The file as h5py sees it: scalar attributes of the stated types, float64 datasets.
    with h5py.File(out, "r") as f:
        for name in expected:
            if name == "native":
                continue
            a = f.attrs.get_id(name)
            check(a.shape == (), f"attribute {name} has shape {a.shape}")
        check(f.attrs["format"] == b"jam-open-run" and f.attrs["units"] == b"jam", "strings")
        for name in ("format_version", "dim", "n", "sample"):
            check(f.attrs[name].dtype == np.int64, f"{name} is {f.attrs[name].dtype}")
        for name in ("diameter_ratio", "q", "compression_rate", "phi_init"):
            check(f.attrs[name].dtype == np.float64, f"{name} is {f.attrs[name].dtype}")
        check(sorted(f) == sorted(names), f"datasets {sorted(f)}")
        for name in names:
            check(f[name].dtype == np.float64 and f[name].shape == (6,), f"{name} type, shape")
            check(f[name].attrs["units"] == units[name].encode(), f"{name} units")
    # An overdamped run without the optional series: q absent, None back.
    minimal = os.path.join(work, "minimal.h5")
    t, phi = series()
    jamio().write_run(minimal, phi, np.zeros(6), dim=3, n=2, rate=RATE, phi_init=PHI_INIT,
                      simulator="x", sample=0)
    run = jamio().validate_run(minimal)
    check(run.q is None and run.dim == 3 and "time" not in run and run.source is None,
          f"minimal run {vars(run)}")
    with h5py.File(minimal, "r") as f:
        check("q" not in f.attrs and "source" not in f.attrs, "absent attributes written")


def case_write_refused(work):
    """Each malformed input: refused, naming the field and the value; nothing written."""
    t, phi = series()
    out = os.path.join(work, "run.h5")
    cases = [
        (dict(dim=4), ("dim 4",)), (dict(dim=2.0), ("dim 2.0", "integer")),
        (dict(dim=True), ("dim True",)), (dict(n=63), ("n 63", "even")), (dict(n=0), ("n 0",)),
        (dict(diameter_ratio=2.5), ("write_run: diameter_ratio 2.5 must be in [1, 2]",)),
        (dict(diameter_ratio=0.9), ("diameter_ratio 0.9",)),
        (dict(diameter_ratio="1.4"), ("diameter_ratio '1.4'", "number")),
        (dict(contact="lj"), ("contact 'lj'", "harmonic")),
        (dict(dynamics="brownian"), ("dynamics 'brownian'",)),
        (dict(q=2.0), ("q 2.0", "inertial")), (dict(dynamics="inertial"), ("q missing",)),
        (dict(dynamics="inertial", q=-1.0), ("q -1.0",)),
        (dict(rate=0.0), ("compression_rate 0.0",)),
        (dict(rate=float("inf")), ("compression_rate inf",)),
        (dict(phi_init=1.2), ("phi_init 1.2",)), (dict(phi_init=0), ("phi_init 0",)),
        (dict(simulator=""), ("simulator ''",)), (dict(simulator=7), ("simulator 7",)),
        (dict(simulator_version=None), ("simulator_version None",)),
        (dict(sample=-1), ("sample -1",)), (dict(sample=1.5), ("sample 1.5", "integer")),
        (dict(sample=None), ("sample missing",)),
        (dict(jamming_packing_fraction=1.5), ("jamming_packing_fraction 1.5",)),
        (dict(source_checksum="xyz"), ("source_checksum 'xyz'", "16 hex")),
        (dict(source=b"bytes"), ("source b'bytes'",)),
        (dict(packing_fraction=phi[::-1]), ("packing_fraction[1]", "increase")),
        (dict(packing_fraction=phi.reshape(2, 3)), ("packing_fraction", "(2, 3)")),
        (dict(packing_fraction=np.where(np.arange(6) == 2, 1.5, phi)),
         ("packing_fraction[2] = 1.5",)),
        (dict(packing_fraction=phi * 0.99), ("packing_fraction[0]", "below phi_init")),
        (dict(packing_fraction=phi * (1 + 1e-4)), ("packing_fraction[0]", "rate")),
        (dict(packing_fraction=["a"] * 6), ("packing_fraction", "numbers")),
        (dict(pressure=-np.ones(6)), ("pressure[0] = -1.0",)),
        (dict(pressure=np.where(np.arange(6) == 4, np.nan, 0.0)), ("pressure[4] = nan",)),
        (dict(pressure=np.zeros(5)), ("pressure has 5 values", "packing_fraction 6")),
        (dict(packing_fraction=phi[:1], pressure=[0.0], time=t[:1],
              contacts_per_particle=None, energy_per_particle=None), ("at least 2",)),
        (dict(contacts_per_particle=-np.ones(6)), ("contacts_per_particle[0] = -1.0",)),
        (dict(energy_per_particle=np.full(6, np.inf)), ("energy_per_particle[0] = inf",)),
        (dict(time=t * 2), ("packing_fraction[1]", "time", "does not shrink")),
        (dict(time=t - 1), ("time[0] = -1.0",)),
        (dict(time=t[::-1], packing_fraction=phi), ("time",)),
    ]
    for change, words in cases:
        try:
            refused(lambda: write(out, **change), "run.h5", *words)
            only(work)
        except AssertionError as e:
            raise AssertionError(f"{change}: {e}") from None
    # A file already there is kept; overwrite=True replaces it.
    with open(out, "wb") as f:
        f.write(b"keep me")
    refused(lambda: write(out), "exists", "overwrite")
    only(work, ["run.h5"])
    with open(out, "rb") as f:
        check(f.read() == b"keep me", "the existing file was changed")
    write(out, overwrite=True)
    check(jamio().validate_run(out).sample == 3, "overwritten run")
    only(work, ["run.h5"])
    # A directory, a FIFO (not waited on), a directory that does not exist.
    directory = os.path.join(work, "dir.h5")
    os.mkdir(directory)
    refused(lambda: write(directory, overwrite=True), "is a directory")
    fifo = os.path.join(work, "fifo.h5")
    os.mkfifo(fifo)
    refused(lambda: write(fifo, overwrite=True), "not a regular file")
    refused(lambda: write(os.path.join(work, "nowhere", "run.h5")), "does not exist")
    only(work, ["dir.h5", "fifo.h5", "run.h5"])


def case_write_fails_midway(work):
    """A failure after the partial file was written (the check before the rename) leaves
    nothing, also when interrupted; a file that appears under the name meanwhile is kept."""
    module = sys.modules["jamio.write"]
    saved = module.validate_run
    out = os.path.join(work, "run.h5")

    def disk_full(path):
        check(os.path.exists(path) and path.endswith(".partial"), f"checked {path}")
        raise OSError(28, "No space left on device")

    def interrupt(path):
        raise KeyboardInterrupt

    def another_writer(path):  # a file appears under the name while the run is written
        with open(out, "wb") as f:
            f.write(b"the other writer's")

    try:
        module.validate_run = disk_full
        refused(lambda: write(out), "run.h5", "cannot be written", "no space left")
        only(work)
        module.validate_run = interrupt
        try:
            write(out)
            raise AssertionError("the interrupt was swallowed")
        except KeyboardInterrupt:
            pass
        only(work)
        module.validate_run = another_writer
        refused(lambda: write(out), "run.h5", "exists")
        only(work, ["run.h5"])
        with open(out, "rb") as f:
            check(f.read() == b"the other writer's", "a file that appeared was overwritten")
    finally:
        module.validate_run = saved


def malformed_copy(work, name, change):
    """A valid run (write_run) copied to `name` and changed by change(h5py file)."""
    good = os.path.join(work, "good.h5")
    if not os.path.exists(good):
        write(good)
    path = os.path.join(work, name)
    shutil.copy(good, path)
    with h5py.File(path, "r+") as f:
        change(f)
    return path


def replace(name, data, **attrs):
    def change(f):
        del f[name]
        d = f.create_dataset(name, data=data)
        for k, v in attrs.items():
            d.attrs[k] = v
    return change


def set_attribute(name, v):
    def change(f):
        f.attrs[name] = v
    return change


def delete_attribute(name):
    def change(f):
        del f.attrs[name]
    return change


def huge(name, shape):
    """A dataset declaring `shape` of float64 and holding nothing: reading it would allocate
    shape's bytes."""
    def change(f):
        del f[name]
        f.create_dataset(name, shape=shape, dtype=np.float64)
    return change


def case_validate_malformed(work):
    t, phi = series()
    rows = np.vstack([phi[:3], phi[3:]])
    cases = [
        ("phi_2d.h5", replace("packing_fraction", rows), ("packing_fraction", "(2, 3)")),
        # Shape before value: 10^12 x 10^12 declared, refused without reading (8 TB otherwise).
        ("phi_huge_2d.h5", huge("packing_fraction", (10 ** 6, 10 ** 6)),
         ("packing_fraction", "(1000000, 1000000)")),
        ("phi_huge.h5", huge("pressure", (10 ** 11,)), ("pressure", "100000000000")),
        ("dim_array.h5", set_attribute("dim", np.array([2, 2])), ("'dim'", "array")),
        ("dim_one_element.h5", set_attribute("dim", np.array([2])), ("'dim'", "array")),
        ("dim_float.h5", set_attribute("dim", 2.0), ("dim 2.0", "integer")),
        ("phi_decreasing.h5", replace("packing_fraction", phi[::-1]),
         ("packing_fraction[1]", "increase")),
        ("phi_off_rate.h5", set_attribute("compression_rate", 2 * RATE),
         ("packing_fraction[1]", "does not shrink", "compression_rate 0.02")),
        ("no_ratio.h5", delete_attribute("diameter_ratio"), ("'diameter_ratio' missing",)),
        ("no_sample.h5", delete_attribute("sample"), ("'sample' missing",)),
        ("pressure_units.h5", replace("pressure", np.zeros(6), units=b"k_e"),
         ("pressure", "units 'k_e'", "k_e/d_s^D")),
        ("root_units.h5", set_attribute("units", b"lj"), ("units 'lj'", "'jam'")),
        ("format.h5", set_attribute("format", b"other"), ("format 'other'",)),
        ("format_version.h5", set_attribute("format_version", 2), ("format_version 2",)),
        ("no_format.h5", delete_attribute("format"), ("'format' missing", "checksum")),
        ("protocol.h5", set_attribute("protocol", b"shear"), ("protocol 'shear'",)),
        ("no_pressure.h5", lambda f: f.__delitem__("pressure"), ("'pressure' missing",)),
        ("pressure_int.h5", replace("pressure", np.zeros(6, dtype=np.int64)),
         ("pressure", "integer", "floating point")),
        ("pressure_short.h5", replace("pressure", np.zeros(5)), ("pressure has 5 values",)),
        ("pressure_group.h5", lambda f: (f.__delitem__("pressure"), f.create_group("pressure")),
         ("'pressure' is not a dataset",)),
        ("q_overdamped.h5", set_attribute("q", 3.0), ("q 3.0", "inertial")),
        ("time_negative.h5", replace("time", t - 1), ("time[0] = -1.0",)),
        ("z_negative.h5", replace("contacts_per_particle", -np.ones(6)),
         ("contacts_per_particle[0] = -1.0",)),
        ("simulator_empty.h5", set_attribute("simulator", b""), ("simulator ''",)),
        ("sample_bool.h5", set_attribute("sample", np.True_), ("sample True",)),
    ]
    for name, change, words in cases:
        path = malformed_copy(work, name, change)
        try:
            refused(lambda: jamio().validate_run(path), path, *words)
        except AssertionError as e:
            raise AssertionError(f"{name}: {e}") from None
    not_hdf5 = os.path.join(work, "text.h5")
    with open(not_hdf5, "w") as f:
        f.write("not HDF5\n")
    refused(lambda: jamio().validate_run(not_hdf5), "text.h5", "not a readable run file")
    e = None
    try:
        jamio().validate_run(os.path.join(work, "absent.h5"))
    except jamio().JamioError as error:
        e = error
    check(e is not None and e.missing, "a missing file is not JamioError(missing=True)")
    refused(lambda: jamio().validate_run(work), "is a directory")
    # The file as written passes.
    check(jamio().validate_run(os.path.join(work, "good.h5")).points == 6, "good.h5")


def case_jam_native(work):
    """A run file of jam's own (`jam sim`): recognised by its checksum, simulator "jam"."""
    out = os.path.join(work, "jam.h5")
    subprocess.run([ARGS.jam, "sim", "--n", "64", "--phi-init", "0.7", "--phi-stop", "0.72",
                    "--rate", "1e-2", "--phi-step", "0.005", "--quiet", "--out", out],
                   check=True, capture_output=True, timeout=600)
    run = jamio().validate_run(out)
    with h5py.File(out, "r") as f:
        version = f.attrs["version"].decode()
        check(np.array_equal(run["pressure"], f["pressure"][()]), "pressure")
        check(run.phi_init == float(f.attrs["phi_init"]), "phi_init")
    check(run.native and run.simulator == "jam" and run.simulator_version == version,
          f"native {run.native}, simulator {run.simulator} {run.simulator_version}")
    check(run.q is None and run.sample is None and run.format is None and run.dim == 2
          and run.n == 64 and run.contact == "harmonic", f"attributes {vars(run)}")
    # Its checks apply: a rate it did not run at is refused.
    bad = os.path.join(work, "jam_rate.h5")
    shutil.copy(out, bad)
    with h5py.File(bad, "r+") as f:
        f.attrs["compression_rate"] = 0.02
    refused(lambda: jamio().validate_run(bad), "does not shrink")


# ---- write_frames --------------------------------------------------------------------------------

def frames_input(m=4, n=8, dim=2, phi_init=0.5, rate=RATE):
    t = np.arange(m) * 0.5
    phi = phi_init * np.exp(dim * rate * t)
    box = (jamio().write.packing_fraction_of(dim, n, RATIO, 1.0) / phi) ** (1 / dim)
    rng = np.random.default_rng(1)
    x = rng.uniform(-1.0, 1.0, (m, n, dim)) * box[:, None, None] / 2
    d = np.where(np.arange(n) % 2 == 0, 1.0, RATIO)
    return dict(box_length=box, positions=x, diameters=d, dim=dim, n=n, rate=rate,
                phi_init=phi_init, simulator="hoomd-blue", simulator_version="4.2", sample=1,
                time=t, source="/data/traj.gsd")


def case_write_frames(work):
    path = os.path.join(work, "frames.h5")
    kw = frames_input()
    jamio().write_frames(path, **kw)
    only(work, ["frames.h5"])
    with h5py.File(path, "r") as f:
        a = {k: f.attrs[k] for k in f.attrs}
        expected = dict(format=b"jam-open-run", format_version=1, dim=2, n=8, diameter_ratio=1.4,
                        contact=b"harmonic", dynamics=b"overdamped",
                        protocol=b"isotropic-compression", compression_rate=RATE, phi_init=0.5,
                        simulator=b"hoomd-blue", simulator_version=b"4.2", sample=1, units=b"jam",
                        source=b"/data/traj.gsd")
        check(a == expected, f"attributes {a}")
        shapes = {k: f[k].shape for k in f}
        check(shapes == {"box_length": (4,), "positions": (4, 8, 2), "diameters": (8,),
                         "time": (4,)}, f"datasets {shapes}")
        for k in f:
            check(f[k].dtype == np.float64, f"{k} is {f[k].dtype}")
            check(np.array_equal(f[k][()], kw[k]), f"{k} differs from what was given")
        check({k: f[k].attrs["units"] for k in f} == {"box_length": b"d_s", "positions": b"d_s",
                                                     "diameters": b"d_s", "time": b"t0"},
              "units")
    out = os.path.join(work, "bad.h5")
    x, box, t = kw["positions"], kw["box_length"], kw["time"]
    cases = [
        (dict(diameters=np.ones(8)), ("diameters hold 8 of 1 and 0 of 1.4", "4 of each")),
        (dict(diameters=np.full(8, 1.2)), ("diameters[0] = 1.2",)),
        (dict(diameters=np.ones(7)), ("diameters has shape (7,)",)),
        (dict(positions=x[:, :, :1]), ("positions has shape (4, 8, 1)", "(4, 8, 2)")),
        (dict(positions=x[0]), ("positions has shape (8, 2)",)),
        (dict(positions=np.where(np.arange(8)[None, :, None] == 5, np.nan, x)),
         ("positions[0, 5]", "finite")),
        (dict(box_length=box * 1.001), ("packing fraction from box_length[0]", "phi_init")),
        (dict(box_length=box[[0, 0, 1, 2]]), ("packing fraction from box_length[1]",
                                              "increase")),
        (dict(box_length=box * np.exp(-np.arange(4) * 1e-3)), ("does not shrink",)),
        (dict(box_length=-box), ("box_length[0]",)),
        (dict(time=t[:3]), ("time has 3 values", "box_length 4")),
        (dict(box_length=box[:1], positions=x[:1], time=t[:1]), ("at least 2",)),
        (dict(n=10), ("positions has shape (4, 8, 2)", "(4, 10, 2)")),
        (dict(diameter_ratio=3.0), ("diameter_ratio 3.0",)),
    ]
    for change, words in cases:
        try:
            refused(lambda: jamio().write_frames(out, **dict(kw, **change)), "write_frames",
                    "bad.h5", *words)
            only(work, ["frames.h5"])
        except AssertionError as e:
            raise AssertionError(f"{sorted(change)}: {e}") from None
    refused(lambda: jamio().write_frames(path, **kw), "exists")
    # Without time the rate is not checked (there is nothing to check it against).
    no_time = dict(kw, time=None, box_length=box * np.exp(-np.arange(4) * 1e-3))
    jamio().write_frames(out, **no_time)
    with h5py.File(out, "r") as f:
        check("time" not in f, "time written though not given")


# ---- GSD import ----------------------------------------------------------------------------------

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


def case_gsd_import_pressure(work):
    from jamio.gsd_import import import_gsd
    gsd_path = os.path.join(work, "traj.gsd")
    made = write_gsd(gsd_path)
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out = os.path.join(outs, "run.h5")
    run = import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=4, phi_init=PHI_INIT,
                     simulator_version="4.2.1", pressure_key=KEY)
    only(outs, ["run.h5"])
    check(run.path == out, "returned run")
    run = jamio().validate_run(out)
    check(np.array_equal(run["pressure"], made["pressure"]),
          f"pressure {run['pressure']} != logged {made['pressure']}")
    check(np.allclose(run["time"], made["t"], rtol=1e-15, atol=0), f"time {run['time']}")
    check(run["time"][0] == 0.0 and run["time"][-1] == (STEPS[-1] - STEPS[0]) * DT,
          "time relative to the first frame")
    check(np.allclose(run["packing_fraction"], made["phi"], rtol=1e-14, atol=0),
          f"packing {run['packing_fraction']} != constructed {made['phi']}")
    from_box = solids() / made["box"].astype(np.float64) ** 2  # the single-precision box
    check(np.all(np.abs(run["packing_fraction"] / from_box - 1) <= 1e-6), "packing vs box")
    check(run.phi_init == PHI_INIT and run.compression_rate == RATE and run.sample == 4,
          "phi_init, rate, sample")
    check((run.simulator, run.simulator_version) == ("hoomd-blue", "4.2.1"), "simulator")
    check(run.dim == 2 and run.n == N and run.diameter_ratio == RATIO, "dim, n, ratio")
    check(run.source == os.path.abspath(gsd_path), f"source {run.source}")
    check(run.interpolation.startswith("none"), f"interpolation {run.interpolation}")
    check(set(run.data) == {"packing_fraction", "pressure", "time"}, f"series {set(run.data)}")
    # phi_init left out: the first frame's (from its single-precision box); the key given
    # without its `log/`.
    out2 = os.path.join(outs, "run2.h5")
    run = import_gsd(gsd_path, out2, rate=RATE, dt=DT, sample=0, pressure_key=KEY[4:])
    check(math.isclose(run.phi_init, from_box[0], rel_tol=1e-15, abs_tol=0),
          f"phi_init {run.phi_init} != frame 0's {from_box[0]}")
    check(np.allclose(run["packing_fraction"], from_box[0] * np.exp(2 * RATE * made["t"]),
                      rtol=1e-14, atol=0), "packing from the first frame's phi")
    # 3D, and the command line.
    gsd3 = os.path.join(work, "traj3.gsd")
    made3 = write_gsd(gsd3, dim=3, n=32, phi_init=0.6)
    out3 = os.path.join(outs, "run3.h5")
    r = subprocess.run([sys.executable, "-m", "jamio.gsd_import", gsd3, "--out", out3,
                        "--rate", str(RATE), "--dt", str(DT), "--sample", "2",
                        "--phi-init", "0.6", "--pressure-key", KEY], capture_output=True,
                       text=True, env=python_env(), timeout=300)
    check(r.returncode == 0, f"command line exited {r.returncode}: {r.stderr}")
    run = jamio().validate_run(out3)
    check(run.dim == 3 and run.n == 32 and run.sample == 2, "3D attributes")
    check(np.array_equal(run["pressure"], made3["pressure"]), "3D pressure")
    check(np.allclose(run["packing_fraction"], made3["phi"], rtol=1e-14, atol=0), "3D packing")
    only(outs, ["run.h5", "run2.h5", "run3.h5"])


def python_env():
    path = os.path.join(ARGS.source, "python")
    old = os.environ.get("PYTHONPATH")
    return dict(os.environ, PYTHONPATH=path + (os.pathsep + old if old else ""))


def case_gsd_refused(work):
    from jamio.gsd_import import import_gsd
    outs = os.path.join(work, "out")
    os.mkdir(outs)
    out = os.path.join(outs, "run.h5")

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

    kw = dict(rate=RATE, dt=DT, sample=0, pressure_key=KEY)
    cases = [
        ("tilt.gsd", dict(change=tilt), kw, ("frame 2", "configuration/box", "xy")),
        ("oblong.gsd", dict(change=oblong), kw, ("frame 1", "configuration/box", "not square")),
        ("small.gsd", dict(change=all_small), kw,
         ("frame 0", "particles/diameter", "64 of 1 and 0 of 1.4", "32 of each")),
        ("ratio.gsd", dict(change=ratio_12), kw,
         ("frame 0", "particles/diameter[1] = 1.20000005", "neither 1 nor diameter_ratio 1.4")),
        ("off_rate.gsd", dict(change=off_rate), kw,
         ("frame 3", "step 1400", "does not shrink at the stated rate")),
        ("rate.gsd", {}, dict(kw, rate=2 * RATE), ("frame 1", "rate 0.02", "does not shrink")),
        ("no_key.gsd", dict(log=False), kw, ("pressure key", KEY, "not in the file")),
        ("frame_no_pressure.gsd", dict(change=no_pressure), kw, ("frame 3 has no", KEY)),
        ("same_step.gsd", dict(change=same_step), kw,
         ("frame 2", "configuration/step 1100", "frame 1's 1100")),
        ("dims.gsd", dict(change=to_3d), kw, ("frame 4", "configuration/dimensions 3")),
        ("nan.gsd", dict(change=nan_position), dict(kw, pressure_key=None, jam="/nonexistent"),
         ("frame 1", "particles/position[5]", "finite")),
        ("phi_init.gsd", {}, dict(kw, phi_init=0.79), ("phi_init 0.79", "frame 0")),
        ("one_frame.gsd", dict(steps=STEPS[:1]), kw, ("1 frame", "at least 2")),
        ("ratio_arg.gsd", {}, dict(kw, diameter_ratio=2.5), ("diameter_ratio 2.5",)),
        ("dt.gsd", {}, dict(kw, dt=0.0), ("dt 0.0",)),
        ("q.gsd", {}, dict(kw, q=3.0), ("q 3.0", "inertial")),
    ]
    for name, make, args, words in cases:
        path = os.path.join(work, name)
        write_gsd(path, **make)
        try:
            refused(lambda: import_gsd(path, out, **args), *words)
            only(outs)
        except AssertionError as e:
            raise AssertionError(f"{name}: {e}") from None
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
        check(f.read() == b"keep me", "the existing output was changed")
    import_gsd(good, out, overwrite=True, **kw)
    check(jamio().validate_run(out).points == len(STEPS), "overwritten")
    os.unlink(out)
    # The command line: one line, exit status 2, nothing written.
    base = [sys.executable, "-m", "jamio.gsd_import"]
    lines = [
        ([os.path.join(work, "tilt.gsd"), "--out", out, "--rate", str(RATE), "--dt", str(DT),
          "--sample", "0", "--pressure-key", KEY], ("tilt.gsd", "xy")),
        ([good, "--out", out, "--rate", "-1", "--dt", str(DT), "--sample", "0"],
         ("compression_rate -1.0",)),
        ([good, "--out", out, "--rate", str(RATE), "--sample", "0"], ("--dt",)),
        ([good, "--out", out, "--rate", "fast", "--dt", str(DT), "--sample", "0"], ("--rate",)),
        ([good, "--out", out, "--rate", str(RATE), "--dt", str(DT), "--sample", "0",
          "--contact", "lj"], ("--contact", "lj")),
    ]
    for argv, words in lines:
        r = subprocess.run(base + argv, capture_output=True, text=True, env=python_env(),
                           timeout=300)
        said = r.stderr.strip()
        check(r.returncode == 2, f"{argv}: exit status {r.returncode} ({said})")
        check("\n" not in said and all(w in said for w in words),
              f"{argv}: stderr {said!r} lacks {words}")
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


def case_gsd_frames_stand_in(work):
    """import_gsd without a pressure: the frames file and the argument vector jam gets, its
    output published, its failures passed on with nothing left behind."""
    from jamio.gsd_import import import_gsd
    fake = os.path.join(work, "fake-jam")
    with open(fake, "w") as f:
        f.write(FAKE_JAM.format(python=os.path.join(ARGS.source, "python")))
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
        check(argv[:2] == ["import", "frames"] and argv[3] == "--out" and len(argv) == 5,
              f"argument vector {argv}")
        check(os.path.dirname(argv[2]) == os.path.dirname(argv[4]) and
              os.path.dirname(os.path.dirname(argv[2])) == outs,
              f"frames and run not in a directory beside the output: {argv}")
        a, d = seen["attrs"], seen["data"]
        expected = dict(format="jam-open-run", format_version=1, dim=2, n=N, diameter_ratio=1.4,
                        contact="harmonic", dynamics="overdamped",
                        protocol="isotropic-compression", compression_rate=RATE,
                        phi_init=PHI_INIT, simulator="hoomd-blue", simulator_version="4.2.1",
                        sample=5, units="jam", source=os.path.abspath(gsd_path))
        check(a == expected, f"frames attributes {a}")
        check(np.allclose(d["time"], made["t"], rtol=1e-15, atol=0), "frames time")
        phi = jamio().write.packing_fraction_of(2, N, RATIO, np.array(d["box_length"]))
        check(np.allclose(phi, made["phi"], rtol=1e-14, atol=0), "frames box_length")
        check(np.array_equal(d["diameters"], np.where(made["typeid"] == 0, 1.0, 1.4)),
              "frames diameters")
        positions = gsd_positions(gsd_path)[:, :, :2]
        check(np.array_equal(np.array(d["positions"]), positions), "frames positions")
        check(run.simulator == "hoomd-blue" and np.array_equal(run["pressure"], np.zeros(6)),
              "the run jam wrote, published")
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


def jam_has_import_frames():
    r = subprocess.run([ARGS.jam, "import", "--help"], capture_output=True, text=True,
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


def case_gsd_frames_jam(work):
    # jam measures the frames: a jam without `import frames` is a failure, not a skip.
    assert jam_has_import_frames(), "the jam given has no `import frames`"
    from jamio.gsd_import import import_gsd
    gsd_path = os.path.join(work, "traj.gsd")
    made = write_gsd(gsd_path, log=False)
    out = os.path.join(work, "run.h5")
    run = import_gsd(gsd_path, out, rate=RATE, dt=DT, sample=1, phi_init=PHI_INIT,
                     jam=ARGS.jam)
    only(work, ["run.h5", "traj.gsd"])
    check(run.simulator == "hoomd-blue" and run.contact == "harmonic", "attributes")
    check(np.allclose(run["packing_fraction"], made["phi"], rtol=1e-12, atol=0), "packing")
    check(np.allclose(run["time"], made["t"], rtol=1e-12, atol=0), "time")
    check("contacts_per_particle" in run and "energy_per_particle" in run, "Z and E measured")
    positions = gsd_positions(gsd_path)[:, :, :2]
    d = np.where(made["typeid"] == 0, 1.0, RATIO)
    box = (solids() / made["phi"]) ** 0.5
    for k in range(len(STEPS)):
        p, z, e = direct_sums(positions[k], d, box[k], 2)
        got = (run["pressure"][k], run["contacts_per_particle"][k], run["energy_per_particle"][k])
        check(np.allclose(got, (p, z, e), rtol=1e-9, atol=0),
              f"frame {k}: jam's p, Z, E {got} != direct sums {(p, z, e)}")
    # A jam that fails without a word: its exit status reaches the caller, nothing is left.
    bad = os.path.join(work, "bad")
    os.mkdir(bad)
    refused(lambda: import_gsd(gsd_path, os.path.join(bad, "run.h5"), rate=RATE, dt=DT,
                               sample=1, contact="hertzian", jam="/bin/false"),
            "jam import frames exited 1")
    only(bad)


CASES = [case_round_trip, case_write_refused, case_write_fails_midway, case_validate_malformed,
         case_jam_native, case_write_frames, case_gsd_import_pressure, case_gsd_refused,
         case_gsd_frames_stand_in, case_gsd_frames_jam]


def main():
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jam", required=True, help="the jam binary (build/jam)")
    parser.add_argument("--source", required=True, help="the source tree (holds python/)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    ARGS = parser.parse_args()
    ARGS.source = os.path.abspath(ARGS.source)
    if os.sep in ARGS.jam:
        ARGS.jam = os.path.abspath(ARGS.jam)
    sys.path.insert(0, os.path.join(ARGS.source, "python"))
    top = tempfile.mkdtemp(prefix="test_jamio_write.")
    passed = failed = skipped = 0
    try:
        for case in CASES:
            name = case.__name__.removeprefix("case_")
            work = os.path.join(top, name)
            os.mkdir(work)
            try:
                if case(work) == "skipped":
                    print(f"skipped {name}")
                    skipped += 1
                    continue
                print(f"passed  {name}")
                passed += 1
            except Exception as e:  # a case that crashes fails, the others still run
                print(f"FAILED  {name}: {type(e).__name__}: {e}")
                failed += 1
    finally:
        if ARGS.keep:
            print(f"kept {top}")
        else:
            with contextlib.suppress(OSError):
                shutil.rmtree(top)
    print(f"{passed} passed, {failed} failed" + (f", {skipped} skipped" if skipped else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
