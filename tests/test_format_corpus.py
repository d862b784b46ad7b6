"""jam and jamio judge one corpus of open runs the same way.

The corpus is written here at test time with h5py (neither validator's writer): a valid open
run and, for each rule of the schema (reference/schema/open_run.toml, written by jam), files
on both sides of it, with the edges taken from the schema itself (every contact law and
dynamics of jam's registry and one it does not have; n, sample, diameter_ratio, Z, phi_J at and
beyond their limits; phi_init slack and rate tolerance at half and twice their value).
`jam validate` reads every file at once, jamio.validate_run each; the test fails on any file
where they disagree, or where both give what the schema does not say.
"""

import subprocess

import h5py
import numpy as np
import pytest

import jamio
from jamio import open_run

LIM = open_run.SCHEMA.limits
M, PHI_INIT, RATE, DIM, N = 24, 0.80, 1e-4, 2, 64
WHOLE = LIM["max_whole"]["value"]


def base(f):
    a = f.attrs
    a["format"], a["format_version"], a["protocol"], a["units"] = (
        "jam-open-run", np.int64(1), "isotropic-compression", "jam")
    a["dim"], a["n"], a["diameter_ratio"] = np.int64(DIM), np.int64(N), 1.4
    a["contact"], a["dynamics"] = open_run.SCHEMA.contacts[0], "overdamped"
    a["compression_rate"], a["phi_init"] = RATE, PHI_INIT
    a["simulator"], a["simulator_version"], a["sample"] = "my-code", "1.0", np.int64(3)
    t = np.linspace(0.0, 50.0, M)
    f["packing_fraction"] = PHI_INIT * np.exp(DIM * RATE * t)
    f["pressure"] = np.linspace(0.0, 1e-3, M)
    f["contacts_per_particle"] = np.linspace(0.0, 4.2, M)
    f["energy_per_particle"] = np.linspace(0.0, 1e-6, M)
    f["time"] = t


def attr(**values):
    def edit(f):
        for k, v in values.items():
            f.attrs[k] = v
    return edit


def scale(name, k, factor):
    def edit(f):
        v = f[name][()].copy()
        v[k] *= factor
        del f[name]
        f[name] = v
    return edit


def put(name, k, value):
    return lambda f: (scale(name, k, 0.0)(f), f[name].__setitem__(k, value))


def cases():
    """name -> (edit, accepted), the edges from the schema."""
    out = {"valid": (lambda f: None, True)}
    for c in open_run.SCHEMA.contacts:
        out[f"contact {c}"] = (attr(contact=c), True)
    out["contact not in the registry"] = (attr(contact="lennard-jones"), False)
    out["dynamics inertial with q"] = (attr(dynamics="inertial", q=2.0), True)
    out["dynamics unknown"] = (attr(dynamics="brownian"), False)
    out["n 2"] = (attr(n=np.int64(2)), True)
    out["n max_whole"] = (attr(n=np.int64(WHOLE)), True)
    out["n beyond max_whole"] = (attr(n=np.int64(WHOLE + 2)), False)
    # An open run holds no positions: a frames file's bound on n is not an open run's.
    out["n beyond a frames file's"] = (
        attr(n=np.int64(LIM["max_frame_particles"]["value"] * 2)), True)
    out["n odd"] = (attr(n=np.int64(N + 1)), False)
    out["sample max_whole"] = (attr(sample=np.int64(WHOLE)), True)
    out["sample beyond max_whole"] = (attr(sample=np.int64(WHOLE + 1)), False)
    out["sample -1"] = (attr(sample=np.int64(-1)), False)
    low, high = LIM["diameter_ratio"]["min"], LIM["diameter_ratio"]["max"]
    out["diameter_ratio min"] = (attr(diameter_ratio=low), True)
    out["diameter_ratio max"] = (attr(diameter_ratio=high), True)
    out["diameter_ratio below min"] = (attr(diameter_ratio=np.nextafter(low, 0)), False)
    out["diameter_ratio above max"] = (attr(diameter_ratio=np.nextafter(high, 3)), False)
    j = LIM["jamming_packing_fraction"]
    out["phi_J NaN"] = (attr(jamming_packing_fraction=float("nan")), True)
    out["phi_J at its upper bound"] = (attr(jamming_packing_fraction=j["below"]), False)
    out["phi_J at its lower bound"] = (attr(jamming_packing_fraction=j["above"]), False)
    out["phi_J inside"] = (attr(jamming_packing_fraction=(j["above"] + j["below"]) / 2), True)
    z = LIM["max_contacts_per_particle"]["value"]
    out["Z at the limit"] = (put("contacts_per_particle", 0, z), True)
    out["Z beyond the limit"] = (put("contacts_per_particle", 0, z * (1 + 1e-12)), False)
    slack = LIM["phi_init_slack"]["value"]
    out["phi_init within the slack"] = (attr(phi_init=PHI_INIT * (1 + slack / 2)), True)
    out["phi_init beyond the slack"] = (attr(phi_init=PHI_INIT * (1 + 2 * slack)), False)
    tol = LIM["rate_tolerance"]["value"]
    out["phi within the rate tolerance"] = (scale("packing_fraction", M - 1, 1 + tol / 2), True)
    out["phi beyond the rate tolerance"] = (scale("packing_fraction", M - 1, 1 + 2 * tol), False)
    out["format_version 2"] = (attr(format_version=np.int64(2)), False)
    out["units not jam"] = (attr(units="lj"), False)
    out["protocol other"] = (attr(protocol="shear"), False)
    out["dim 1"] = (attr(dim=np.int64(1)), False)
    out["blank simulator"] = (attr(simulator=" "), False)
    out["compression_rate inf"] = (attr(compression_rate=float("inf")), False)
    return out


CASES = cases()


@pytest.fixture(scope="module")
def answers(jam, tmp_path_factory):
    """name -> (jam accepted, jam's line, jamio accepted, jamio's line)."""
    directory = tmp_path_factory.mktemp("corpus")
    paths = {}
    for k, (name, (edit, _)) in enumerate(CASES.items()):
        paths[name] = directory / f"case{k:02d}.h5"
        with h5py.File(paths[name], "w") as f:
            base(f)
            edit(f)
    r = subprocess.run([str(jam), "validate", *map(str, paths.values())], capture_output=True,
                       text=True, timeout=120)
    lines = dict(line.partition(": ")[::2] for line in r.stdout.splitlines())
    out = {}
    for name, path in paths.items():
        line = lines[str(path)]
        try:
            jamio.validate_run(path)
            py = (True, "ok")
        except jamio.JamioError as e:
            py = (False, str(e))
        out[name] = (line.startswith("ok:"), line, *py)
    return out


@pytest.mark.parametrize("name", CASES)
def test_jam_and_jamio_agree(answers, name):
    jam_ok, jam_line, py_ok, py_line = answers[name]
    assert jam_ok == py_ok, f"jam: {jam_line}; jamio: {py_line}"
    assert jam_ok == CASES[name][1], f"jam: {jam_line}; jamio: {py_line}"


def test_frames_files_have_one_bound_on_n(jam, tmp_path):
    """jam import frames and jamio.write_frames refuse the same n (the schema's
    max_frame_particles), before reading or allocating any positions."""
    n = LIM["max_frame_particles"]["value"] + 2
    path = tmp_path / "frames.h5"
    with h5py.File(path, "w") as f:
        base(f)
        for name in list(f):
            del f[name]
        f.attrs["n"] = np.int64(n)
        f["box_length"] = np.array([400.0, 399.0])
        f["diameters"] = np.ones(2)
        f["positions"] = np.zeros((2, 2, 2))
    r = subprocess.run([str(jam), "import", "frames", str(path), "--out", str(tmp_path / "r.h5")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode != 0 and f"n {n} is more than a frames file holds" in r.stderr
    with pytest.raises(jamio.JamioError, match=f"n {n} is more than a frames file holds"):
        jamio.write_frames(tmp_path / "w.h5", [400.0, 399.0], np.zeros((2, 2, 2)), np.ones(2),
                           dim=2, n=n, rate=RATE, phi_init=1e-9, simulator="my-code", sample=0)
    assert not (tmp_path / "r.h5").exists() and not (tmp_path / "w.h5").exists()
