#!/usr/bin/python3
"""jamio (python/) installed the documented way and read back against h5py.

In a temporary directory: a venv with --system-site-packages, `pip install --no-index
--no-build-isolation` of a copy of python/ (offline: nothing is fetched), then the files jam
writes: a run file (`jam sim`), a small campaign run, averaged (`jam stats`) and checked (`jam
check all --no-lmp`), a schema 1 checks.json (the bare array), a run file without the schema 2
attributes, files set aside in runs/, and broken files. The venv's Python then runs this file
with --inside: every value jamio returns must equal what h5py and json read (strings decoded,
numbers as int and float), nothing in a file may be left out, and every broken file must raise
JamioError naming it.

Usage (ctest runs it): test_jamio.py --jam build/jam --source .
Prints one line per case and a last line `N passed, M failed`; exit status 1 if any failed.
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from jamio_hostile import HOSTILE_CASES, make_broken

CAMPAIGN = """name = "jamio"
dim = 2
sizes = [64, 128]
phi_init = [0.70]
log10_rates = [-2.5, -3.0]
samples = 3
phi_stop = 0.8
phi_step = 0.002
dt = 0.02
seed = 5
output = "campaign"
jamming_point = true
rattlers = true
stress = true
"""
SERIES = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle", "time",
          "contacts_per_particle_no_rattlers", "rattler_fraction")
DECOYS = ("n64_phi0.7000_r-2.50_s009.h5.rejected", "n64_phi0.7000_r-2.50_s010.h5.4242.partial",
          "n64_phi0.7000_r-2.50_s011.h5.checkpoint")
TIMEOUT = 600


def run(cmd, cwd=None, expect=(0,), env=None):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT, env=env)
    if r.returncode not in expect:
        raise AssertionError(f"{' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}")
    return r


# ---- outside the venv: install jamio, make the files ------------------------------------------

def install(work, source):
    """A venv with the system's packages and jamio installed offline; its python."""
    venv = os.path.join(work, "venv")
    run([sys.executable, "-m", "venv", "--system-site-packages", venv])
    copy = os.path.join(work, "jamio-source")  # pip builds in the tree: not in the source's
    shutil.copytree(os.path.join(source, "python"), copy,
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    python = os.path.join(venv, "bin", "python")
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    run([python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-cache-dir",
         "--root-user-action=ignore", copy], env=env)
    return python


def strip_schema_2(path):
    """The run file as schema 1 wrote it: no units, campaign, sample or schema_version."""
    with h5py.File(path, "r+") as f:
        for name in ("units", "campaign", "sample", "schema_version"):
            if name in f.attrs:
                del f.attrs[name]
        for d in f.values():
            if "units" in d.attrs:
                del d.attrs["units"]


def make_old_campaign(data, runs):
    """data/old/runs: a run file stripped to schema 1, an intact one and files set aside."""
    old = os.path.join(data, "old", "runs")
    os.makedirs(old)
    names = sorted(n for n in os.listdir(runs) if n.endswith(".h5"))
    shutil.copy(os.path.join(runs, names[0]), os.path.join(old, names[0]))
    strip_schema_2(os.path.join(old, names[0]))
    shutil.copy(os.path.join(data, "old", "runs", names[0]), os.path.join(data, "old.h5"))
    shutil.copy(os.path.join(runs, names[-1]), old)
    for decoy in DECOYS:
        with open(os.path.join(old, decoy), "wb") as f:
            f.write(b"not a run file\n")


def make_schema_1(data):
    """data/schema1: checks.json as the bare array of verdicts, with the campaign's checks.h5."""
    out = os.path.join(data, "schema1")
    os.mkdir(out)
    with open(os.path.join(data, "campaign", "checks.json")) as f:
        verdicts = json.load(f)["verdicts"]
    with open(os.path.join(out, "checks.json"), "w") as f:
        json.dump(verdicts, f, indent=2)
    shutil.copy(os.path.join(data, "campaign", "checks.h5"), out)


def make_data(work, jam, source):
    data = os.path.join(work, "data")
    os.mkdir(data)
    run([jam, "sim", "--n", "64", "--phi-init", "0.7", "--phi-stop", "0.72", "--rate", "1e-2",
         "--phi-step", "0.005", "--quiet", "--out", os.path.join(data, "run.h5")])
    with open(os.path.join(data, "campaign.toml"), "w") as f:
        f.write(CAMPAIGN)
    run([jam, "campaign", "run", "campaign.toml", "--quiet"], cwd=data)
    run([jam, "stats", "campaign"], cwd=data)
    run([jam, "check", "all", "campaign", "--no-lmp", "--reference-dir",
         os.path.join(source, "reference")], cwd=data, expect=(0, 1, 3))
    make_old_campaign(data, os.path.join(data, "campaign", "runs"))
    make_schema_1(data)
    make_broken(data)
    return data


def outside(a):
    """Installs, makes the files, runs the checks in the venv; (passed, failed)."""
    work = tempfile.mkdtemp(prefix="jam-jamio-test-")
    passed = failed = 0
    try:
        for name, step in (("install", lambda: install(work, a.source)),
                           ("data", lambda: make_data(work, a.jam, a.source))):
            try:
                result = step()
                print(f"passed  {name}", flush=True)
                passed += 1
            except (AssertionError, OSError, subprocess.SubprocessError) as e:
                print(f"FAILED  {name}: {e}", flush=True)
                return passed, failed + 1
            if name == "install":
                python = result
        r = subprocess.run([python, os.path.abspath(__file__), "--inside", result,
                            "--source", a.source], capture_output=True, text=True,
                           timeout=TIMEOUT, cwd=work)
        m = re.search(r"^inside the venv: (\d+) passed, (\d+) failed$", r.stdout, re.M)
        sys.stdout.write(r.stdout.replace(m[0] + "\n", "") if m else r.stdout + r.stderr)
        if not m or (r.returncode != 0 and m[2] == "0"):
            print(f"FAILED  venv: exit status {r.returncode}")
            return passed + (int(m[1]) if m else 0), failed + 1 + (int(m[2]) if m else 0)
        return passed + int(m[1]), failed + int(m[2])
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)


# ---- inside the venv: jamio against h5py ------------------------------------------------------

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


def case_installed(data, source):
    import jamio
    where = os.path.realpath(jamio.__file__)
    if not where.startswith(os.path.realpath(sys.prefix) + os.sep):
        raise AssertionError(f"jamio imported from {where}, not from the venv {sys.prefix}")
    if sys.prefix == sys.base_prefix:
        raise AssertionError("not running in a venv")


def case_run_file(data, source):
    import jamio
    for path in (os.path.join(data, "run.h5"),
                 os.path.join(data, "campaign", "runs", "n64_phi0.7000_r-2.50_s001.h5")):
        r = jamio.load_run(path)
        compare(run_flat(r), path)
        if r.schema_version != 2 or r["pressure"] is not r.data["pressure"]:
            raise AssertionError(f"{path}: schema_version {r.schema_version}")
        if r.units.get("pressure") != "k_e/d_s^D":
            raise AssertionError(f"{path}: units {r.units}")


def case_old_run_file(data, source):
    import jamio
    path = os.path.join(data, "old.h5")
    r = jamio.load_run(path)
    compare(run_flat(r), path)
    if r.schema_version != 1 or r.units or "sample" in r.attrs:
        raise AssertionError(f"schema {r.schema_version}, units {r.units}")


def case_campaign_runs(data, source):
    import jamio
    campaign = os.path.join(data, "campaign")
    compare_table(jamio.load_runs(campaign, as_frame=False), os.path.join(campaign, "runs"))
    table = jamio.load_runs(campaign)
    try:
        import pandas
    except ImportError:
        pandas = None
    if pandas is not None and not isinstance(table, pandas.DataFrame):
        raise AssertionError("pandas is installed but load_runs gave no DataFrame")
    compare_table(as_columns(table), os.path.join(campaign, "runs"))


def case_runs_set_aside_and_schema_1(data, source):
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
    if not np.isnan(table["sample"]).any() or np.isnan(table["sample"]).all():
        raise AssertionError("expected NaN samples for the schema 1 file only")


def case_stats(data, source):
    import jamio
    for path in (os.path.join(data, "campaign", "stats.h5"),
                 os.path.join(source, "reference", "results", "reduced-2d", "stats.h5"),
                 os.path.join(source, "reference", "results", "reduced-3d", "stats.h5")):
        s = jamio.load_stats(path)
        compare(stats_flat(s), path)
    s = jamio.load_stats(os.path.join(data, "campaign"))  # a directory: its stats.h5
    # Its 2 rates give no scaling fit, and `jam stats` writes none (the stored results above
    # carry fits).
    if s.attrs["campaign"] != "jamio" or not s.ensembles or s.fit is not None:
        raise AssertionError(f"campaign stats: {s.attrs}, {list(s.ensembles)}, fit {s.fit}")


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


def case_checks(data, source):
    import jamio
    campaign = os.path.join(data, "campaign")
    c = jamio.load_checks(campaign)
    compare_checks(c, os.path.join(campaign, "checks.json"), os.path.join(campaign, "checks.h5"))
    if (c.campaign, c.schema_version) != ("jamio", 2) or not c.code_version or not c.created:
        raise AssertionError(f"metadata {c.metadata}")


def case_checks_schema_1(data, source):
    import jamio
    schema1 = os.path.join(data, "schema1")
    c = jamio.load_checks(os.path.join(schema1, "checks.json"))
    compare_checks(c, os.path.join(schema1, "checks.json"), os.path.join(schema1, "checks.h5"))
    if c.campaign is not None or c.schema_version != 1:
        raise AssertionError(f"schema 1: {c.schema_version}, {c.metadata}")
    stored = os.path.join(source, "reference", "results", "reduced-2d")
    compare_checks(jamio.load_checks(stored), os.path.join(stored, "checks.json"), None)


CASES = [case_installed, case_run_file, case_old_run_file, case_campaign_runs,
         case_runs_set_aside_and_schema_1, case_stats, case_checks, case_checks_schema_1,
         *HOSTILE_CASES]


def inside(a):
    """Every case in this (the venv's) Python; (passed, failed)."""
    passed = failed = 0
    for case in CASES:
        name = case.__name__.removeprefix("case_")
        try:
            case(a.inside, a.source)
            print(f"passed  {name}")
            passed += 1
        except Exception as e:  # a case that crashes fails, the others still run
            print(f"FAILED  {name}: {type(e).__name__}: {e}")
            failed += 1
    return passed, failed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jam", help="the jam binary (build/jam)")
    parser.add_argument("--source", required=True, help="the source tree (holds python/)")
    parser.add_argument("--inside", metavar="DATA", help=argparse.SUPPRESS)
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    a = parser.parse_args()
    a.source = os.path.abspath(a.source)
    if not a.inside and not a.jam:
        parser.error("--jam is required")
    if a.jam and os.sep in a.jam:  # the runs are made in the temporary directory
        a.jam = os.path.abspath(a.jam)
    passed, failed = inside(a) if a.inside else outside(a)
    print(f"{'inside the venv: ' if a.inside else ''}{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
