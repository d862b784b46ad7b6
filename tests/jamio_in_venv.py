"""jamio against h5py, in the venv tests/test_jamio.py made (run there by it, with pytest and
without tests/conftest.py, so that jamio is the installed copy and not the source tree's).

Every value jamio returns must equal what h5py and json read (strings decoded, numbers as int
and float), nothing in a file may be left out, and every broken file must raise JamioError naming
it. The files are in $JAMIO_TEST_DATA (made by test_jamio.py with jam); the source tree is
$JAMIO_TEST_SOURCE. Not a suite of its own: its name is not test_*.py.
"""

import json
import math
import os
import sys

import h5py
import numpy as np
import pytest

from jamio_hostile import HOSTILE_CASES

SERIES = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle", "time",
          "contacts_per_particle_no_rattlers", "rattler_fraction")
DECOYS = ("n64_phi0.7000_r-2.50_s009.h5.rejected", "n64_phi0.7000_r-2.50_s010.h5.4242.partial",
          "n64_phi0.7000_r-2.50_s011.h5.checkpoint")


@pytest.fixture(scope="module")
def data():
    return os.environ["JAMIO_TEST_DATA"]


@pytest.fixture(scope="module")
def source():
    return os.environ["JAMIO_TEST_SOURCE"]


def expected(v):
    """A value as jamio must return it: bytes decoded, numpy scalars as Python numbers."""
    if isinstance(v, (bytes, np.bytes_)):
        return bytes(v).decode()
    if isinstance(v, np.generic):
        return v.item()
    return v


def same(got, want, where):
    want = expected(want)
    if isinstance(want, np.ndarray):
        if not isinstance(got, np.ndarray) or got.shape != want.shape:
            raise AssertionError(f"{where}: {got!r} is not an array shaped {want.shape}")
        if want.dtype.kind == "f":
            ok = np.array_equal(got, want, equal_nan=True)
        else:
            ok = got.tolist() == want.tolist()
        if not ok:
            raise AssertionError(f"{where}: values differ")
        return
    if type(got) is not type(want):
        raise AssertionError(f"{where}: {type(got).__name__} {got!r}, h5py/json: "
                             f"{type(want).__name__} {want!r}")
    if not (got == want or (isinstance(want, float) and math.isnan(want) and math.isnan(got))):
        raise AssertionError(f"{where}: {got!r} != {want!r}")


def h5_flat(path):
    """Every attribute and dataset of an HDF5 file, as h5py reads them."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            where = obj.name
            out.update({("attr", where, k): v for k, v in obj.attrs.items()})
            if isinstance(obj, h5py.Dataset):
                out[("data", where)] = obj[()]
        visit("/", f)
        f.visititems(visit)
    return out


def compare(got, path):
    """jamio's flattened view `got` against the whole file: nothing left out, nothing added,
    every value equal."""
    want = h5_flat(path)
    missing, extra = set(want) - set(got), set(got) - set(want)
    if missing or extra:
        raise AssertionError(f"{path}: jamio lacks {sorted(missing)[:5]}, adds {sorted(extra)[:5]}")
    for key in want:
        same(got[key], want[key], f"{path} {key}")


def put_attrs(out, where, attrs, units=()):
    out.update({("attr", where, k): v for k, v in attrs.items()})
    out.update({("attr", f"{where.rstrip('/')}/{k}", "units"): u for k, u in dict(units).items()})


def put_group(out, where, group):
    if group is not None:
        put_attrs(out, where, group.attrs, group.units)
        out.update({("data", f"{where}/{k}"): v for k, v in group.items()})


def run_flat(r):
    out = {("data", f"/{k}"): v for k, v in r.data.items()}
    put_attrs(out, "/", r.attrs, r.units)
    return out


def stats_flat(s):
    out = {}
    put_attrs(out, "/", s.attrs)
    put_attrs(out, "/paper", s.paper)
    for name, e in s.ensembles.items():
        put_attrs(out, f"/ensembles/{name}", e.attrs)
        for sub in ("constant_phi", "constant_z", "jamming", "coverage"):
            put_group(out, f"/ensembles/{name}/{sub}", getattr(e, sub))
        for sub in ("constant_phi", "constant_z"):
            put_group(out, f"/ensembles/{name}/coverage/{sub}", getattr(e, "coverage_" + sub))
    for key, fit in (("fit", s.fit), ("fit_z", s.fit_z)):
        if fit is not None:
            put_attrs(out, f"/{key}", fit.attrs)
            put_group(out, f"/{key}/scan", fit.scan)
            fitted = [(f"/{key}/families/{name}", family)
                      for name, family in fit.families.items()]
            if fit.papers_protocol is not None:
                fitted.append((f"/{key}/papers_protocol", fit.papers_protocol))
            for where, family in fitted:
                put_attrs(out, where, family.attrs, family.units)
                if family.coefficients is not None:
                    out[("data", where + "/coefficients")] = family.coefficients
                put_group(out, where + "/collapse", family.collapse)
        if fit is not None and fit.representative is not None:
            put_attrs(out, f"/{key}/representative", fit.representative, fit.units)
            out[("data", f"/{key}/representative/coefficients")] = fit.coefficients
            put_group(out, f"/{key}/representative/collapse", fit.collapse)
    return out


def checks_flat(c):
    out = {}
    put_attrs(out, "/", c.curves_attrs)
    for name, g in c.curves.items():
        put_group(out, f"/verdicts/{name}", g)
    return out


def expected_table(runs_dir):
    """The table load_runs must return, read with h5py from every runs/*.h5."""
    names = sorted(n for n in os.listdir(runs_dir) if n.endswith(".h5"))
    columns = {c: [] for c in ("run", "n", "phi_init", "compression_rate", "seed", "sample",
                               *SERIES)}
    for name in names:
        with h5py.File(os.path.join(runs_dir, name), "r") as f:
            m = len(f["packing_fraction"])
            for key in ("n", "phi_init", "compression_rate", "seed"):
                columns[key] += [f.attrs[key].item()] * m
            columns["sample"] += [f.attrs["sample"].item() if "sample" in f.attrs else np.nan] * m
            columns["run"] += [name[:-3]] * m
            for key in SERIES:
                columns[key] += f[key][()].tolist() if key in f else [None] * m
    # The optional series are columns only when a run has them; NaN in the others.
    return {k: [np.nan if x is None else x for x in v] for k, v in columns.items()
            if k not in SERIES[5:] or any(x is not None for x in v)}


def compare_table(table, runs_dir):
    want = expected_table(runs_dir)
    if list(table) != list(want):
        raise AssertionError(f"columns {list(table)}, expected {list(want)}")
    for key, values in want.items():
        got = table[key].tolist()
        if key in ("sample", *SERIES):
            got, values = [repr(x) for x in got], [repr(float(x)) for x in values]
        if got != values:
            raise AssertionError(f"{runs_dir}: column {key} differs")
        if key in ("n", "seed") and table[key].dtype.kind != "i":
            raise AssertionError(f"column {key} is {table[key].dtype}, not integers")


def as_columns(table):
    """A DataFrame (pandas installed) or the dict of arrays, as a dict of numpy arrays."""
    if isinstance(table, dict):
        return table
    return {c: table[c].to_numpy() for c in table.columns}


def test_installed(data, source):
    import jamio
    where = os.path.realpath(jamio.__file__)
    assert where.startswith(os.path.realpath(sys.prefix) + os.sep), \
        f"jamio imported from {where}, not from the venv {sys.prefix}"
    assert sys.prefix != sys.base_prefix, "not running in a venv"


def test_run_file(data, source):
    import jamio
    for path in (os.path.join(data, "run.h5"),
                 os.path.join(data, "campaign", "runs", "n64_phi0.7000_r-2.50_s001.h5")):
        r = jamio.load_run(path)
        compare(run_flat(r), path)
        assert r.schema_version == 2 and r["pressure"] is r.data["pressure"], \
            f"{path}: schema_version {r.schema_version}"
        assert r.units.get("pressure") == "k_e/d_s^D", f"{path}: units {r.units}"


def test_old_run_file(data, source):
    import jamio
    path = os.path.join(data, "old.h5")
    r = jamio.load_run(path)
    compare(run_flat(r), path)
    assert r.schema_version == 1 and not r.units and "sample" not in r.attrs, \
        f"schema {r.schema_version}, units {r.units}"


def test_campaign_runs(data, source):
    import jamio
    campaign = os.path.join(data, "campaign")
    compare_table(jamio.load_runs(campaign, as_frame=False), os.path.join(campaign, "runs"))
    table = jamio.load_runs(campaign)
    try:
        import pandas
    except ImportError:
        pandas = None
    assert pandas is None or isinstance(table, pandas.DataFrame), \
        "pandas is installed but load_runs gave no DataFrame"
    compare_table(as_columns(table), os.path.join(campaign, "runs"))


def test_runs_set_aside_and_schema_1(data, source):
    import jamio
    runs = os.path.join(data, "old", "runs")
    table = jamio.load_runs(os.path.join(data, "old"), as_frame=False)
    for decoy in DECOYS:  # garbage: read, they would fail the comparison or raise
        os.rename(os.path.join(runs, decoy), os.path.join(data, decoy))
    try:
        compare_table(table, runs)
    finally:
        for decoy in DECOYS:
            os.rename(os.path.join(data, decoy), os.path.join(runs, decoy))
    assert np.isnan(table["sample"]).any() and not np.isnan(table["sample"]).all(), \
        "expected NaN samples for the schema 1 file only"


def test_stats(data, source):
    import jamio
    for path in (os.path.join(data, "campaign", "stats.h5"),
                 os.path.join(source, "reference", "results", "reduced-2d", "stats.h5"),
                 os.path.join(source, "reference", "results", "reduced-3d", "stats.h5")):
        s = jamio.load_stats(path)
        compare(stats_flat(s), path)
    s = jamio.load_stats(os.path.join(data, "campaign"))  # a directory: its stats.h5
    # Its 2 rates give no scaling fit, and `jam stats` writes none (the stored results above
    # carry fits).
    assert (s.attrs["campaign"] == "jamio" and s.ensembles and s.fit is None), \
        f"campaign stats: {s.attrs}, {list(s.ensembles)}, fit {s.fit}"


def expected_checks(path):
    with open(path) as f:
        content = json.load(f)
    if isinstance(content, list):
        return 1, {}, content
    return 2, {k: v for k, v in content.items() if k != "verdicts"}, content["verdicts"]


def compare_checks(c, json_path, h5_path):
    schema, metadata, verdicts = expected_checks(json_path)
    if (c.schema_version, c.metadata, c.verdicts) != (schema, metadata, verdicts):
        raise AssertionError(f"{json_path}: verdicts or metadata differ")
    if h5_path is None:
        if c.curves or c.curves_attrs or c.curves_path is not None:
            raise AssertionError(f"{json_path}: curves without checks.h5")
        return
    compare(checks_flat(c), h5_path)
    for k, v in enumerate(c.verdicts):
        if c.curves_of(k) is None or c.curves_of(k).attrs["check"] != v["check"]:
            raise AssertionError(f"{h5_path}: no curves group for verdict {k}")


def test_checks(data, source):
    import jamio
    campaign = os.path.join(data, "campaign")
    c = jamio.load_checks(campaign)
    compare_checks(c, os.path.join(campaign, "checks.json"), os.path.join(campaign, "checks.h5"))
    assert (c.campaign, c.schema_version) == ("jamio", 2) and c.code_version and c.created, \
        f"metadata {c.metadata}"


def test_checks_schema_1(data, source):
    import jamio
    schema1 = os.path.join(data, "schema1")
    c = jamio.load_checks(os.path.join(schema1, "checks.json"))
    compare_checks(c, os.path.join(schema1, "checks.json"), os.path.join(schema1, "checks.h5"))
    assert c.campaign is None and c.schema_version == 1, \
        f"schema 1: {c.schema_version}, {c.metadata}"
    stored = os.path.join(source, "reference", "results", "reduced-2d")
    compare_checks(jamio.load_checks(stored), os.path.join(stored, "checks.json"), None)


@pytest.mark.parametrize("case", HOSTILE_CASES,
                         ids=[c.__name__.removeprefix("case_") for c in HOSTILE_CASES])


def test_hostile(data, source, case):
    case(data, source)
