#!/usr/bin/python3
"""jam and jamio judge every open run the same way.

Each case is a valid open run (written here with h5py, not with either validator's writer) with
one field changed: the hostile values found so far (phi_J inf, 5, -1; q with overdamped
dynamics; an integer pressure; a NUL inside `source`; n and sample 2^62, 2^63 + 2 as unsigned;
Z 1e300 and the flipped exponent bit 4 -> 5.4e154; ...) and their valid neighbours (phi_J NaN,
sample 2^53, float32 series, a 32-bit n). `jam validate` and jamio.validate_run read every file;
each must give the expected answer (accept or refuse), and they must agree. Both read their
limits from reference/schema/open_run.toml (written by `jam schema open-run`); the last case
checks that jamio's limits are that file's.

Usage (ctest runs it): python3 -m pytest tests/test_open_run_agreement.py --jam build/jam --source .
"""

import tomllib
import os
import subprocess

import h5py
import numpy as np
import pytest

import jamio
from jamio import open_run

M = 40
PHI_INIT, RATE, DIM, N = 0.80, 1e-4, 2, 64


def base(f):
    """A valid open run: every required attribute and all five series."""
    a = f.attrs
    a["format"], a["format_version"], a["protocol"], a["units"] = (
        "jam-open-run", np.int64(1), "isotropic-compression", "jam")
    a["dim"], a["n"], a["diameter_ratio"] = np.int64(DIM), np.int64(N), 1.4
    a["contact"], a["dynamics"] = "harmonic", "overdamped"
    a["compression_rate"], a["phi_init"] = RATE, PHI_INIT
    a["simulator"], a["simulator_version"], a["sample"] = "my-code", "1.0", np.int64(3)
    t = np.linspace(0.0, 50.0, M)
    phi = PHI_INIT * np.exp(DIM * RATE * t)
    f["packing_fraction"] = phi
    f["pressure"] = np.linspace(0.0, 1e-3, M)
    f["contacts_per_particle"] = np.linspace(0.0, 4.2, M)
    f["energy_per_particle"] = np.linspace(0.0, 1e-6, M)
    f["time"] = t


def attr(name, value):
    def edit(f):
        f.attrs[name] = value
    return edit


def series(name, values):
    def edit(f):
        del f[name]
        f[name] = values
    return edit


def at(name, k, value):
    def edit(f):
        v = f[name][()].copy()
        v[k] = value
        del f[name]
        f[name] = v
    return edit


def fixed_string(name, raw):
    """A fixed-length string attribute holding exactly these bytes (h5py's str is
    variable-length and cannot hold a NUL)."""
    def edit(f):
        if name in f.attrs:
            del f.attrs[name]
        f.attrs.create(name, np.array(raw, dtype=f"S{len(raw)}"))
    return edit


def without(name):
    def edit(f):
        del f.attrs[name]
    return edit


def inertial(q):
    def edit(f):
        f.attrs["dynamics"] = "inertial"
        if q is not None:
            f.attrs["q"] = q
    return edit


z = np.linspace(0.0, 4.2, M)
z_flipped = z.copy()
z_flipped[M - 1] = np.frombuffer((np.float64(4.0).view(np.uint64) ^ np.uint64(1 << 61))
                                 .tobytes(), dtype=np.float64)[0]

# name -> (edit, accepted)
CASES = {
    "valid": (lambda f: None, True),
    "phi_J NaN": (attr("jamming_packing_fraction", float("nan")), True),
    "phi_J 0.84": (attr("jamming_packing_fraction", 0.84), True),
    "phi_J inf": (attr("jamming_packing_fraction", float("inf")), False),
    "phi_J 5": (attr("jamming_packing_fraction", 5.0), False),
    "phi_J -1": (attr("jamming_packing_fraction", -1.0), False),
    "q with overdamped": (attr("q", 2.0), False),
    "q 0 with overdamped": (attr("q", 0.0), False),
    "inertial with q": (inertial(2.0), True),
    "inertial without q": (inertial(None), False),
    "inertial q inf": (inertial(float("inf")), False),
    "integer pressure": (series("pressure", np.arange(M, dtype=np.int64)), False),
    "float32 pressure": (series("pressure", np.linspace(0, 1e-3, M).astype(np.float32)), True),
    "NUL inside source": (fixed_string("source", b"/data/a\0evil"), False),
    "NUL-padded source": (fixed_string("source", b"/data/a\0\0\0"), True),
    "NUL inside simulator": (fixed_string("simulator", b"my\0code"), False),
    "blank simulator": (attr("simulator", "   "), False),
    "source_checksum not hex": (attr("source_checksum", "xyz"), False),
    "source_checksum hex": (attr("source_checksum", "0123456789abcdef"), True),
    "n int32": (attr("n", np.int32(N)), True),
    "n 2^62": (attr("n", np.int64(1 << 62)), False),
    "n 2^63+2 unsigned": (attr("n", np.uint64((1 << 63) + 2)), False),
    "n float": (attr("n", float(N)), False),
    "n odd": (attr("n", np.int64(N + 1)), False),
    "sample 2^53": (attr("sample", np.int64(1 << 53)), True),
    "sample 2^62": (attr("sample", np.int64(1 << 62)), False),
    "sample -1": (attr("sample", np.int64(-1)), False),
    "sample missing": (without("sample"), False),
    "diameter_ratio 2.5": (attr("diameter_ratio", 2.5), False),
    "dim 4": (attr("dim", np.int64(4)), False),
    "Z 1e300": (at("contacts_per_particle", 0, 1e300), False),
    "Z flipped exponent bit": (series("contacts_per_particle", z_flipped), False),
    "Z 64": (at("contacts_per_particle", 0, 64.0), True),
    "Z 65": (at("contacts_per_particle", 0, 65.0), False),
    "Z negative": (at("contacts_per_particle", 3, -0.5), False),
    "pressure NaN": (at("pressure", 3, float("nan")), False),
    "phi not increasing": (at("packing_fraction", 5, PHI_INIT), False),
    "phi off the rate": (at("packing_fraction", M - 1, 0.9), False),
    "compression_rate 0": (attr("compression_rate", 0.0), False),
    "phi_init 1": (attr("phi_init", 1.0), False),
    "units wrong": (attr("units", "lj"), False),
}


def write_cases(directory):
    paths = {}
    for k, (name, (edit, _)) in enumerate(CASES.items()):
        path = os.path.join(directory, f"case{k:02d}.h5")
        with h5py.File(path, "w") as f:
            base(f)
            edit(f)
        paths[name] = path
    return paths


def jam_answers(jam, paths):
    """name -> (accepted, line) from one `jam validate` over every file."""
    r = subprocess.run([jam, "validate", *paths.values()], capture_output=True, text=True,
                       timeout=120)
    lines = {}
    for line in r.stdout.splitlines():
        path, _, rest = line.partition(": ")
        lines[path] = rest
    out = {}
    for name, path in paths.items():
        line = lines.get(path)
        if line is None:
            raise AssertionError(f"jam validate printed no line for {name}: {r.stdout}{r.stderr}")
        out[name] = (line.startswith("ok:"), line)
    return out


def jamio_answers(paths):
    out = {}
    for name, path in paths.items():
        try:
            jamio.validate_run(path)
            out[name] = (True, "ok")
        except jamio.JamioError as e:
            out[name] = (False, str(e))
    return out


@pytest.fixture(scope="module")
def answers(jam, tmp_path_factory):
    """(jam's, jamio's) answers for every case, each validator run once over all the files."""
    paths = write_cases(tmp_path_factory.mktemp("cases"))
    return jam_answers(jam, paths), jamio_answers(paths)


@pytest.mark.parametrize("name", CASES)
def test_both_validators_give_the_expected_answer(answers, name):
    jam, py = answers
    accepted = CASES[name][1]
    assert jam[name][0] == accepted, f"jam: {jam[name][1]}"
    assert py[name][0] == accepted, f"jamio: {py[name][1]}"


@pytest.mark.parametrize("name, word", [
    ("phi_J inf", "jamming_packing_fraction"), ("q with overdamped", "q"),
    ("integer pressure", "pressure"), ("NUL inside source", "source"), ("n 2^62", "n"),
    ("sample 2^62", "sample"), ("Z 1e300", "contacts_per_particle"),
    ("n 2^63+2 unsigned", "9223372036854775810"),
])
def test_refusals_name_the_field(answers, name, word):
    jam, py = answers
    assert word in jam[name][1]
    assert word in py[name][1]
    assert len(jam[name][1].splitlines()) == 1


def test_the_limits_come_from_the_shared_table(source):
    with open(source / "reference" / "schema" / "open_run.toml", "rb") as f:
        limits = tomllib.load(f)["limits"]
    # The Z bound the cases above straddle is the table's, not a number of this test's.
    assert limits["max_contacts_per_particle"]["value"] == 64.0
    assert open_run.MAX_CONTACTS == limits["max_contacts_per_particle"]["value"]
    assert open_run.MAX_WHOLE == 1 << 53
    assert open_run.RATE_TOLERANCE == limits["rate_tolerance"]["value"]
