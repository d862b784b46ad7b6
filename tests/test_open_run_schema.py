"""The open run format is defined once, by jam.

reference/schema/open_run.toml is what `jam schema open-run` writes (regenerate it with
JAM_REGENERATE_SCHEMA=1 in the environment, as LAMMPS's unit tests regenerate their
references); jamio validates with it. A contact law compiled into a test-only executable alone
(tests/open_run_registry_tool.cpp: the registry's list with one more law) is validated,
imported and, with that executable's schema, accepted by jamio, with no edit but the list;
jam itself and jamio's own schema refuse it, naming the laws they know.
"""

import dataclasses
import os
import pathlib
import subprocess

import h5py
import numpy as np
import pytest

import jamio
from jamio import open_run

SCHEMA = pathlib.Path("reference", "schema", "open_run.toml")


def run(*args):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def tool(jam):
    """The test-only executable, built beside jam (build/tests/)."""
    path = pathlib.Path(jam).parent / "tests" / "open_run_registry_tool"
    if not path.exists():
        pytest.fail(f"{path} is not built: cmake --build build --target open_run_registry_tool")
    return path


def test_committed_schema_is_what_jam_writes(jam, source):
    r = run(jam, "schema", "open-run")
    assert r.returncode == 0, r.stderr
    committed = source / SCHEMA
    if os.environ.get("JAM_REGENERATE_SCHEMA") == "1":
        committed.write_text(r.stdout, encoding="utf-8")
    assert committed.read_text(encoding="utf-8") == r.stdout, (
        f"{SCHEMA} is stale: regenerate it (jam schema open-run > {SCHEMA}, or run this test "
        "with JAM_REGENERATE_SCHEMA=1)")


def test_jamio_reads_the_committed_schema(source):
    schema = open_run.load_schema(source / SCHEMA)
    assert dataclasses.replace(open_run.SCHEMA, path=schema.path) == schema
    assert "harmonic" in schema.contacts and "hertzian" in schema.contacts
    assert schema.limits["max_frame_particles"]["value"] == 1 << 24
    assert jamio.grid.ENDS_STEPS_ON_GRID == tuple(
        name for name, i in schema.integrators.items() if i["adaptive"])


def test_jam_refuses_an_unknown_format_naming_the_known(jam):
    r = run(jam, "schema", "stats-file")
    assert r.returncode != 0
    assert "open-run" in r.stderr


def frames(path, contact):
    """A valid frames file of 32 particles in 2D, three frames of a compression, the contact
    law named (written with h5py: jamio's writer knows only jam's own laws)."""
    rng = np.random.default_rng(7)
    n, ratio = 32, 1.4
    volume = n / 2 * np.pi / 4 * (1 + ratio ** 2)
    phi = np.array([0.60, 0.70, 0.80])
    lengths = np.sqrt(volume / phi)
    with h5py.File(path, "w") as f:
        a = f.attrs
        a["format"], a["format_version"], a["protocol"], a["units"] = (
            "jam-open-run", np.int64(1), "isotropic-compression", "jam")
        a["dim"], a["n"], a["diameter_ratio"] = np.int64(2), np.int64(n), ratio
        a["contact"], a["dynamics"] = contact, "overdamped"
        a["compression_rate"], a["phi_init"] = 1e-3, phi[0]
        a["simulator"], a["simulator_version"], a["sample"] = "my-code", "1.0", np.int64(0)
        f["box_length"] = lengths
        f["positions"] = rng.uniform(-0.5, 0.5, (3, n, 2)) * lengths[:, None, None]
        f["diameters"] = np.repeat([1.0, ratio], n // 2)


def test_a_test_only_contact_law_needs_no_edit_but_the_list(jam, tool, tmp_path):
    test_only, hertzian = tmp_path / "test-only.h5", tmp_path / "hertzian.h5"
    frames(test_only, "test-only")
    frames(hertzian, "hertzian")
    # jam does not know the law: refused, naming the field and the laws it knows.
    r = run(jam, "import", "frames", test_only, "--out", tmp_path / "refused.h5")
    assert r.returncode != 0
    assert "contact 'test-only' must be harmonic or hertzian" in r.stderr
    assert not (tmp_path / "refused.h5").exists()
    # The executable whose list has it imports and validates it, measured with that law.
    r = run(tool, "import", test_only, tmp_path / "run.h5")
    assert r.returncode == 0, r.stdout + r.stderr
    r = run(tool, "validate", tmp_path / "run.h5")
    assert r.returncode == 0 and "ok: contact test-only" in r.stdout, r.stdout
    r = run(jam, "import", "frames", hertzian, "--out", tmp_path / "hertzian-run.h5")
    assert r.returncode == 0, r.stderr
    with h5py.File(tmp_path / "run.h5") as a, h5py.File(tmp_path / "hertzian-run.h5") as b:
        assert jamio.hdf5.value(a.attrs["contact"]) == "test-only"
        assert np.array_equal(a["pressure"][()], b["pressure"][()])
        assert a["pressure"][-1] > 0
    # jam validate and jamio's own schema refuse it; jamio with that executable's schema
    # (written by it as jam writes reference/schema/open_run.toml) accepts it.
    r = run(jam, "validate", tmp_path / "run.h5")
    assert r.returncode == 1 and "contact 'test-only' must be harmonic or hertzian" in r.stdout
    with pytest.raises(jamio.JamioError, match="contact 'test-only' must be 'harmonic' or "
                                               "'hertzian'"):
        jamio.validate_run(tmp_path / "run.h5")
    schema_file = tmp_path / "open_run.toml"
    r = run(tool, "schema")
    assert r.returncode == 0
    schema_file.write_text(r.stdout, encoding="utf-8")
    schema = open_run.load_schema(schema_file)
    assert schema.contacts == ("harmonic", "hertzian", "test-only")
    assert jamio.validate_run(tmp_path / "run.h5", schema=schema).contact == "test-only"
