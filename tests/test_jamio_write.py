#!/usr/bin/python3
"""jamio's writers of the open run format (docs/cross-simulator.md).

write_run read back by validate_run and by h5py (every attribute, type and dataset as the format
says); every malformed input refused with one line naming the field and the value, and nothing
left behind (a pre-existing file kept, no `.partial`, also when the write fails midway; a
temporary name already taken neither written nor removed); validate_run on hand-made malformed
files (a 2-D or undeclared-huge packing_fraction refused by its shape before a value is read,
array attributes, decreasing phi, phi off phi_init exp(D rate t), missing attributes, wrong
units, integer datasets, a series kept in another file) and on a run file of jam's own (`jam
sim`); write_frames' file (attributes, shapes, units) and its refusals. The HOOMD-blue import:
tests/test_jamio_gsd.py.

Usage (ctest runs it): python3 -m pytest tests/test_jamio_write.py --jam build/jam --source .
"""

import os
import shutil
import subprocess
import tempfile

import h5py
import numpy as np
import pytest

from jamio_write_fixture import (DIM, N, PHI_INIT, RATE, RATIO, good_run, jamio, only, refused,
                                 series, write)


@pytest.fixture
def work(tmp_path):
    """The test's scratch directory, as a string."""
    return str(tmp_path)


@pytest.fixture
def short_work():
    """A scratch directory of a short path: a refusal shortens the long paths it quotes, and
    some must show the file name at their end (pytest's tmp_path is long)."""
    work = tempfile.mkdtemp(prefix="jamio-")
    yield work
    shutil.rmtree(work, ignore_errors=True)


def test_round_trip(work):
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
        assert got == value and type(got) is type(value), f"{name}: {got!r}, wrote {value!r}"
    assert returned.path == run.path and returned.sample == 3, "write_run's return value"
    names = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle",
             "time")
    assert sorted(run.data) == sorted(names), f"series {sorted(run.data)}"
    for name in names:
        assert np.array_equal(run[name], np.asarray(given[name], dtype=np.float64)), \
            f"{name} read back differs"
    units = {"packing_fraction": "1", "pressure": "k_e/d_s^D", "contacts_per_particle": "1",
             "energy_per_particle": "k_e", "time": "t0"}
    assert run.series_units == units, f"units {run.series_units}"
    assert "my-gpu-code" in repr(run) and "\n" not in repr(run), f"repr {repr(run)}"
    # The file as h5py sees it: scalar attributes of the stated types, float64 datasets.
    with h5py.File(out, "r") as f:
        for name in expected:
            if name == "native":
                continue
            a = f.attrs.get_id(name)
            assert a.shape == (), f"attribute {name} has shape {a.shape}"
        assert f.attrs["format"] == b"jam-open-run" and f.attrs["units"] == b"jam", "strings"
        for name in ("format_version", "dim", "n", "sample"):
            assert f.attrs[name].dtype == np.int64, f"{name} is {f.attrs[name].dtype}"
        for name in ("diameter_ratio", "q", "compression_rate", "phi_init"):
            assert f.attrs[name].dtype == np.float64, f"{name} is {f.attrs[name].dtype}"
        assert sorted(f) == sorted(names), f"datasets {sorted(f)}"
        for name in names:
            assert f[name].dtype == np.float64 and f[name].shape == (6,), f"{name} type, shape"
            assert f[name].attrs["units"] == units[name].encode(), f"{name} units"
    # An overdamped run without the optional series: q absent, None back.
    minimal = os.path.join(work, "minimal.h5")
    t, phi = series()
    jamio().write_run(minimal, phi, np.zeros(6), dim=3, n=2, rate=RATE, phi_init=PHI_INIT,
                      simulator="x", sample=0)
    run = jamio().validate_run(minimal)
    assert run.q is None and run.dim == 3 and "time" not in run and run.source is None, \
        f"minimal run {vars(run)}"
    with h5py.File(minimal, "r") as f:
        assert "q" not in f.attrs and "source" not in f.attrs, "absent attributes written"


# Each malformed input to write_run: (the change to a valid call, words of the refusal).
T, PHI = series()
WRITE_REFUSALS = [
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
    (dict(packing_fraction=PHI[::-1]), ("packing_fraction[1]", "increase")),
    (dict(packing_fraction=PHI.reshape(2, 3)), ("packing_fraction", "(2, 3)")),
    (dict(packing_fraction=np.where(np.arange(6) == 2, 1.5, PHI)),
     ("packing_fraction[2] = 1.5",)),
    (dict(packing_fraction=PHI * 0.99), ("packing_fraction[0]", "below phi_init")),
    (dict(packing_fraction=PHI * (1 + 1e-4)), ("packing_fraction[0]", "rate")),
    (dict(packing_fraction=["a"] * 6), ("packing_fraction", "numbers")),
    (dict(pressure=-np.ones(6)), ("pressure[0] = -1.0",)),
    # A masked array: its raw values behind the mask (here 5.0) must not be written.
    (dict(pressure=np.ma.masked_array(np.full(6, 5.0), mask=[0, 0, 1, 0, 0, 0])),
     ("pressure has a masked value", "index 2")),
    (dict(contacts_per_particle=np.full(6, 1e300)),
     ("contacts_per_particle[0] = 1e+300", "[0, 64]")),
    (dict(sample=1 << 62), ("sample 4611686018427387904", "2^53")),
    (dict(pressure=np.where(np.arange(6) == 4, np.nan, 0.0)), ("pressure[4] = nan",)),
    (dict(pressure=np.zeros(5)), ("pressure has 5 values", "packing_fraction 6")),
    (dict(packing_fraction=PHI[:1], pressure=[0.0], time=T[:1],
          contacts_per_particle=None, energy_per_particle=None), ("at least 2",)),
    (dict(contacts_per_particle=-np.ones(6)), ("contacts_per_particle[0] = -1.0",)),
    (dict(energy_per_particle=np.full(6, np.inf)), ("energy_per_particle[0] = inf",)),
    (dict(time=T * 2), ("packing_fraction[1]", "time", "does not shrink")),
    (dict(time=T - 1), ("time[0] = -1.0",)),
    (dict(time=T[::-1], packing_fraction=PHI), ("time",)),
]


@pytest.mark.parametrize("change, words", WRITE_REFUSALS,
                         ids=[",".join(sorted(c)) for c, _ in WRITE_REFUSALS])


def test_write_refused(work, change, words):
    """Each malformed input: refused, naming the field and the value; nothing written."""
    refused(lambda: write(os.path.join(work, "run.h5"), **change), "run.h5", *words)
    only(work)


def test_write_keeps_what_is_there(work):
    out = os.path.join(work, "run.h5")
    # A file already there is kept; overwrite=True replaces it.
    with open(out, "wb") as f:
        f.write(b"keep me")
    refused(lambda: write(out), "exists", "overwrite")
    only(work, ["run.h5"])
    with open(out, "rb") as f:
        assert f.read() == b"keep me", "the existing file was changed"
    write(out, overwrite=True)
    assert jamio().validate_run(out).sample == 3, "overwritten run"
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


def test_write_fails_midway(work, monkeypatch):
    """A failure after the partial file was written (the check before the rename) leaves
    nothing, also when interrupted; a file that appears under the name meanwhile is kept."""
    module = jamio().write
    out = os.path.join(work, "run.h5")

    def disk_full(path):
        assert os.path.exists(path) and path.endswith(".partial"), f"checked {path}"
        raise OSError(28, "No space left on device")

    def interrupt(path):
        raise KeyboardInterrupt

    def another_writer(path):  # a file appears under the name while the run is written
        with open(out, "wb") as f:
            f.write(b"the other writer's")

    monkeypatch.setattr(module, "validate_run", disk_full)
    refused(lambda: write(out), "run.h5", "cannot be written", "no space left")
    only(work)
    monkeypatch.setattr(module, "validate_run", interrupt)
    with pytest.raises(KeyboardInterrupt):  # not swallowed
        write(out)
    only(work)
    monkeypatch.setattr(module, "validate_run", another_writer)
    refused(lambda: write(out), "run.h5", "exists")
    only(work, ["run.h5"])
    with open(out, "rb") as f:
        assert f.read() == b"the other writer's", "a file that appeared was overwritten"


def test_temporary_name_taken(work, monkeypatch):
    """The temporary name `<path>.<pid>.partial` already taken, by a symbolic link to another
    file or by a file another writer is writing: neither is opened, written or removed (the
    link's target was truncated, and the name unlinked after the write); the run is written
    through a name of its own, also when the write fails midway."""
    out = os.path.join(work, "run.h5")
    taken = f"{out}.{os.getpid()}.partial"
    victim = os.path.join(work, "victim.txt")
    with open(victim, "wb") as f:
        f.write(b"not jamio's")
    os.symlink(victim, taken)
    write(out)
    only(work, ["run.h5", os.path.basename(taken), "victim.txt"])
    assert os.path.islink(taken) and os.readlink(taken) == victim, "the link was removed"
    with open(victim, "rb") as f:
        assert f.read() == b"not jamio's", "the link's target was written"
    assert jamio().validate_run(out).sample == 3, "the run written"
    os.unlink(taken)
    os.unlink(out)
    with open(taken, "wb") as f:
        f.write(b"the other writer's")

    def disk_full(path):
        assert path != taken, "checked the other writer's file"
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(jamio().write, "validate_run", disk_full)
    refused(lambda: write(out), "run.h5", "no space left")
    only(work, [os.path.basename(taken), "victim.txt"])
    with open(taken, "rb") as f:
        assert f.read() == b"the other writer's", "the other writer's file was changed"


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


def outside(work, how):
    """pressure kept outside the run file, in good.h5 beside it (a regular file: what the run
    file names must be refused, not opened, wherever it points): `how` is "external link",
    "soft link" (through an external link elsewhere in the file) or "external storage"."""
    good = os.path.join(work, "good.h5")

    def change(f):
        del f["pressure"]
        if how == "external link":
            f["pressure"] = h5py.ExternalLink(good, "/pressure")
        elif how == "soft link":
            f["elsewhere"] = h5py.ExternalLink(good, "/")
            f["pressure"] = h5py.SoftLink("/elsewhere/pressure")
        else:
            raw = os.path.join(work, "pressure.raw")
            with open(raw, "wb") as out:
                out.write(np.zeros(6).tobytes())
            f.create_dataset("pressure", shape=(6,), dtype=np.float64, external=[(raw, 0, 48)])
    return change


# Hand-made malformed files: (name, the change to a valid run, words of the refusal); a string
# for the change is outside()'s `how`.
MALFORMED = [
    ("phi_2d.h5", replace("packing_fraction", np.vstack([PHI[:3], PHI[3:]])),
     ("packing_fraction", "(2, 3)")),
    # Shape before value: 10^12 x 10^12 declared, refused without reading (8 TB otherwise).
    ("phi_huge_2d.h5", huge("packing_fraction", (10 ** 6, 10 ** 6)),
     ("packing_fraction", "(1000000, 1000000)")),
    ("phi_huge.h5", huge("pressure", (10 ** 11,)), ("pressure", "100000000000")),
    ("dim_array.h5", set_attribute("dim", np.array([2, 2])), ("'dim'", "array")),
    ("dim_one_element.h5", set_attribute("dim", np.array([2])), ("'dim'", "array")),
    ("dim_float.h5", set_attribute("dim", 2.0), ("dim 2.0", "integer")),
    ("phi_decreasing.h5", replace("packing_fraction", PHI[::-1]),
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
    ("time_negative.h5", replace("time", T - 1), ("time[0] = -1.0",)),
    ("z_negative.h5", replace("contacts_per_particle", -np.ones(6)),
     ("contacts_per_particle[0] = -1.0",)),
    ("simulator_empty.h5", set_attribute("simulator", b""), ("simulator ''",)),
    ("sample_bool.h5", set_attribute("sample", np.True_), ("sample True",)),
    # Followed, these were read from good.h5 (and a FIFO there blocked for ever): outside().
    ("external_link.h5", "external link",
     ("'/pressure' is an external link", "good.h5", "not followed")),
    ("soft_link_out.h5", "soft link",
     ("'/elsewhere' is an external link", "not followed")),
    ("external_storage.h5", "external storage",
     ("dataset '/pressure'", "another file", "not read")),
]


@pytest.mark.parametrize("name, change, words", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_validate_malformed(short_work, name, change, words):
    if isinstance(change, str):
        change = outside(short_work, change)
    path = malformed_copy(short_work, name, change)
    refused(lambda: jamio().validate_run(path), path, *words)


def test_validate_refuses_what_is_not_a_run(work):
    write(os.path.join(work, "good.h5"))
    not_hdf5 = os.path.join(work, "text.h5")
    with open(not_hdf5, "w") as f:
        f.write("not HDF5\n")
    refused(lambda: jamio().validate_run(not_hdf5), "text.h5", "not a readable run file")
    e = None
    try:
        jamio().validate_run(os.path.join(work, "absent.h5"))
    except jamio().JamioError as error:
        e = error
    assert e is not None and e.missing, "a missing file is not JamioError(missing=True)"
    refused(lambda: jamio().validate_run(work), "is a directory")
    # The file as written passes.
    assert jamio().validate_run(os.path.join(work, "good.h5")).points == 6, "good.h5"


def test_jam_native(jam, work):
    """A run file of jam's own (`jam sim`): recognised by its checksum, simulator "jam"."""
    out = os.path.join(work, "jam.h5")
    subprocess.run([jam, "sim", "--n", "64", "--phi-init", "0.7", "--phi-stop", "0.72", "--rate",
                    "1e-2", "--phi-step", "0.005", "--quiet", "--out", out],
                   check=True, capture_output=True, timeout=600)
    run = jamio().validate_run(out)
    with h5py.File(out, "r") as f:
        version = f.attrs["version"].decode()
        assert np.array_equal(run["pressure"], f["pressure"][()]), "pressure"
        assert run.phi_init == float(f.attrs["phi_init"]), "phi_init"
    assert run.native and run.simulator == "jam" and run.simulator_version == version, \
        f"native {run.native}, simulator {run.simulator} {run.simulator_version}"
    assert (run.q is None and run.sample is None and run.format is None and run.dim == 2
            and run.n == 64 and run.contact == "harmonic"), f"attributes {vars(run)}"
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


def test_write_frames(work):
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
        assert a == expected, f"attributes {a}"
        shapes = {k: f[k].shape for k in f}
        assert shapes == {"box_length": (4,), "positions": (4, 8, 2), "diameters": (8,),
                          "time": (4,)}, f"datasets {shapes}"
        for k in f:
            assert f[k].dtype == np.float64, f"{k} is {f[k].dtype}"
            assert np.array_equal(f[k][()], kw[k]), f"{k} differs from what was given"
        units = {k: f[k].attrs["units"] for k in f}
        assert units == {"box_length": b"d_s", "positions": b"d_s", "diameters": b"d_s",
                         "time": b"t0"}, "units"
    refused(lambda: jamio().write_frames(path, **kw), "exists")
    # Without time the rate is not checked (there is nothing to check it against).
    out = os.path.join(work, "bad.h5")
    no_time = dict(kw, time=None, box_length=kw["box_length"] * np.exp(-np.arange(4) * 1e-3))
    jamio().write_frames(out, **no_time)
    with h5py.File(out, "r") as f:
        assert "time" not in f, "time written though not given"


# ---- GSD import ----------------------------------------------------------------------------------


def frames_refusals():
    """Each malformed input to write_frames: (the change to frames_input(), words of the
    refusal). A function: frames_input needs jamio, imported once pytest has read --source."""
    kw = frames_input()
    x, box, t = kw["positions"], kw["box_length"], kw["time"]
    return [
        (dict(diameters=np.ones(8)), ("diameters hold 8 of 1 and 0 of 1.4", "4 of each")),
        (dict(diameters=np.full(8, 1.2)), ("diameters[0] = 1.2",)),
        (dict(diameters=np.ones(7)), ("diameters has shape (7,)",)),
        (dict(positions=x[:, :, :1]), ("positions has shape (4, 8, 1)", "(4, 8, 2)")),
        (dict(positions=x[0]), ("positions has shape (8, 2)",)),
        (dict(positions=np.where(np.arange(8)[None, :, None] == 5, np.nan, x)),
         ("positions[0, 5]", "finite")),
        (dict(box_length=box * 1.001), ("packing fraction from box_length[0]", "phi_init")),
        (dict(box_length=box[[0, 0, 1, 2]]), ("packing fraction from box_length[1]", "increase")),
        (dict(box_length=box * np.exp(-np.arange(4) * 1e-3)), ("does not shrink",)),
        (dict(box_length=-box), ("box_length[0]",)),
        (dict(time=t[:3]), ("time has 3 values", "box_length 4")),
        (dict(box_length=box[:1], positions=x[:1], time=t[:1]), ("at least 2",)),
        (dict(n=10), ("positions has shape (4, 8, 2)", "(4, 10, 2)")),
        (dict(diameter_ratio=3.0), ("diameter_ratio 3.0",)),
    ]


@pytest.mark.parametrize("k", range(14))
def test_write_frames_refused(work, k):
    """Refused, naming the field and the value; nothing written."""
    cases = frames_refusals()
    assert len(cases) == 14
    change, words = cases[k]
    jamio().write_frames(os.path.join(work, "frames.h5"), **frames_input())
    out = os.path.join(work, "bad.h5")
    refused(lambda: jamio().write_frames(out, **dict(frames_input(), **change)), "write_frames",
            "bad.h5", *words)
    only(work, ["frames.h5"])
