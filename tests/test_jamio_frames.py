#!/usr/bin/python3
"""jamio's tables on a campaign's nominal coordinates, on campaigns run as a user runs them.

Two tiny campaigns (`jam campaign run`, `jam stats`): one with the default (adaptive) integrator,
a phi_init off the output grid (0.7013) and a chained rate, one with fixed Euler steps, whose
points lie past their grid values by up to one step's growth. The run files themselves show
the problem the tables solve: more distinct phi_init and packing values than the campaign has.
Then: runs_frame and stats_frame carry exactly the campaign file's phi_init values (read here
with tomllib) and the grid's values (computed here in decimal); groupby and pivot on (n,
phi_init, log10_rate, phi) give one row per grid point per ensemble; the xarray Datasets have
the documented dimensions; every value equals what h5py reads; every dataset of stats.h5 states
its unit and the tables carry them (an old stats.h5 without units still loads, from jamio's
table, and says so); reprs are short; a run planted off the grid or off the campaign's values
is refused in one line naming it; without pandas or xarray a table asks for the package in one
line while the readers still work.

Usage (ctest runs it): python3 -m pytest tests/test_jamio_frames.py --jam build/jam --source .
"""

import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
from decimal import Decimal

import h5py
import numpy as np
import pytest

import jamio

ADAPTIVE = """name = "frames"
dim = 2
sizes = [32, 64]
phi_init = [0.70, 0.7013]
log10_rates = [-2.5, -3.0]
chain_phi_init = [0, 0.74]
samples = 2
phi_stop = 0.78
phi_step = 0.002
seed = 3
output = "adaptive"
"""
# The same with fixed steps: points land past their grid values.
FIXED = ADAPTIVE.replace('name = "frames"', 'name = "euler"\nintegrator = "euler"\ndt = 0.05') \
                .replace('output = "adaptive"', 'output = "fixed"')
KEYS = ["n", "phi_init", "log10_rate", "phi"]
# An ensemble's constant-phi averages in the adaptive campaign's stats.h5 (2 samples).
GROUP = "ensembles/n64_phi0.7013_r-3.00/constant_phi"


def run(cmd, cwd, expect=(0,), env=None):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=600, env=env)
    assert r.returncode in expect, f"{' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


def expected_grid(design, phi_init, log10_rate):
    """The grid values of one ensemble, from the campaign file alone: its start (phi_init, or
    the chained rate's chain_phi_init), the multiples of phi_step above it, phi_stop."""
    chain = dict(zip(design["log10_rates"], design.get("chain_phi_init", [])))
    start = chain.get(log10_rate) or phi_init
    step, stop = Decimal(str(design["phi_step"])), design["phi_stop"]
    k = int(Decimal(str(start)) / step) + 1
    grid = [start]
    while float(k * step) < stop:
        grid.append(float(k * step))
        k += 1
    return grid + [stop]


def ensembles(design):
    return [(n, p, r) for n in design["sizes"] for p in design["phi_init"]
            for r in design["log10_rates"]]


class Campaigns:
    """The two campaigns run and averaged in `work`, and their campaign files read."""

    def __init__(self, jam, work):
        self.work = work
        self.design = {}
        for name, text in (("adaptive", ADAPTIVE), ("fixed", FIXED)):
            with open(os.path.join(work, f"{name}.toml"), "w") as f:
                f.write(text)
            run([str(jam), "campaign", "run", f"{name}.toml", "--quiet"], work)
            run([str(jam), "stats", name], work)
            self.design[name] = tomllib.loads(text)

    def dir(self, name):
        return os.path.join(self.work, name)

    def run_files(self, name):
        runs = os.path.join(self.dir(name), "runs")
        return sorted(os.path.join(runs, f) for f in os.listdir(runs) if f.endswith(".h5"))


@pytest.fixture(scope="module")
def made(jam):
    """The campaigns, in a directory of a short path (refusals quote the paths)."""
    for module in ("pandas", "xarray"):  # a failure, not a skip: they are test packages
        try:
            __import__(module)
        except ImportError:
            pytest.fail(f"needs {module} (Debian: python3-{module}; scripts/setup.sh --tests "
                        "installs it)")
    work = tempfile.mkdtemp(prefix="jam-jamio-frames-")
    yield Campaigns(jam, work)
    shutil.rmtree(work, ignore_errors=True)


@pytest.mark.parametrize("name", ["adaptive", "fixed"])
def test_the_run_files_have_more_values_than_the_campaign(made, name):
    """The problem, as the run files have it: the raw table's phi_init and packing_fraction
    have more distinct values than the campaign's phi_init and grid (so the checks below
    would fail on them)."""
    raw = jamio.load_runs(made.dir(name))
    design = made.design[name]
    grid = {g for e in ensembles(design) for g in expected_grid(design, *e[1:])}
    assert raw["phi_init"].nunique() > len(design["phi_init"]), name
    if name == "fixed":
        assert raw["packing_fraction"].nunique() > 2 * len(grid)


@pytest.mark.parametrize("name", ["adaptive", "fixed"])
def test_runs_frame_has_the_nominal_values_and_the_grid(made, name):
    design = made.design[name]
    df = jamio.runs_frame(made.dir(name))
    assert sorted(df["phi_init"].unique()) == sorted(design["phi_init"])
    assert sorted(df["log10_rate"].unique()) == sorted(design["log10_rates"])
    assert sorted(df["n"].unique()) == design["sizes"]
    assert sorted(df["sample"].unique()) == list(range(design["samples"]))
    grids = {e: expected_grid(design, *e[1:]) for e in ensembles(design)}
    assert set(df["phi"]) == {g for grid in grids.values() for g in grid}
    groups = df.groupby(KEYS).size()
    assert len(groups) == sum(len(g) for g in grids.values()), name
    assert set(groups) == {design["samples"]}
    for e, grid in grids.items():
        got = groups.loc[e].index.tolist()
        assert got == grid, f"{name} {e}"
    pivot = df.pivot_table(index=KEYS, columns="sample", values="pressure")
    assert len(pivot) == len(groups)
    assert not pivot.isna().any().any()
    assert df.attrs["units"]["pressure"] == "k_e/d_s^D"
    assert df.attrs["units"]["time"] == "t0"
    assert df.attrs["units_source"] == "the files"


@pytest.mark.parametrize("name", ["adaptive", "fixed"])
def test_runs_frame_values_are_the_run_files(made, name):
    """Every series equals h5py's array bitwise; coordinates are the files' n and sample,
    and phi is within the integrator's allowance below each packing_fraction."""
    df = jamio.runs_frame(made.dir(name))
    for path in made.run_files(name):
        rows = df[df["run"] == os.path.basename(path)[:-3]]
        with h5py.File(path, "r") as f:
            for series in ("packing_fraction", "pressure", "contacts_per_particle",
                           "energy_per_particle", "time"):
                assert np.array_equal(rows[series].to_numpy(), f[series][()]), \
                    f"{path} {series}"
            assert set(rows["n"]) == {f.attrs["n"]}
            assert set(rows["sample"]) == {f.attrs["sample"]}
            past = (f["packing_fraction"][()] - rows["phi"].to_numpy()) / rows["phi"]
            assert np.all(past >= -1e-12), path
            limit = 1e-12 if name == "adaptive" else 2 * 10 ** -2.5 * 0.05 * 1.01
            assert np.all(past <= limit), f"{path}: {past.max()}"


def test_runs_dataset_dimensions_and_values(made):
    design = made.design["adaptive"]
    ds = jamio.runs_dataset(made.dir("adaptive"))
    assert list(ds["pressure"].dims) == ["n", "phi_init", "log10_rate", "sample", "phi"]
    assert ds["n"].values.tolist() == design["sizes"]
    assert sorted(ds["phi_init"].values.tolist()) == sorted(design["phi_init"])
    assert ds.sizes["phi"] == len({g for e in ensembles(design)
                                   for g in expected_grid(design, *e[1:])})
    assert ds["pressure"].attrs["units"] == "k_e/d_s^D"
    path = made.run_files("adaptive")[-1]
    with h5py.File(path, "r") as f:
        a = f.attrs
        point = ds["pressure"].sel(n=a["n"], phi_init=0.7013, log10_rate=-3.0,
                                   sample=a["sample"]).dropna("phi")
        assert np.array_equal(point.values, f["pressure"][()]), path
        assert point["phi"].values[0] == 0.74  # the chained rate's start


def test_stats_frames_and_units(made):
    stats_path = os.path.join(made.dir("adaptive"), "stats.h5")
    with h5py.File(stats_path, "r") as f:
        lacking = []
        f.visititems(lambda k, v: lacking.append(k) if isinstance(v, h5py.Dataset)
                     and "units" not in v.attrs else None)
        assert lacking == []
        assert f.attrs["phi_step"] == 0.002
        stats = jamio.load_stats(stats_path)
        for average, coordinate, grid in (("constant_phi", "phi", "packing_fraction"),
                                          ("constant_z", "z", "contacts_per_particle")):
            df = stats.frame(average)
            assert df.attrs["units"]["pressure_mean"] == "k_e/d_s^D"
            assert df.attrs["units_source"] == "the files"
            assert df.groupby(KEYS[:3] + [coordinate]).size().max() == 1
            for name, g in f["ensembles"].items():
                key = tuple(g.attrs[k] for k in KEYS[:3])
                rows = df[(df[KEYS[:3]] == key).all(axis=1)]
                want = g[f"{average}/pressure_mean"][()]
                assert np.array_equal(rows["pressure_mean"].to_numpy(), want), name
                stored = g[f"{average}/{grid}"][()]
                step = Decimal(str(0.002 if average == "constant_phi" else f.attrs["z_step"]))
                exact = [float(round(Decimal(v) / step) * step) for v in stored]
                assert rows[coordinate].tolist() == exact, name
        assert sorted(stats.frame()["phi_init"].unique()) == [0.7, 0.7013]
        per_sample = stats.frame(samples=True)
        g = f["ensembles/n64_phi0.7013_r-3.00/constant_phi"]
        rows = per_sample[(per_sample["n"] == 64) & (per_sample["phi_init"] == 0.7013)
                          & (per_sample["log10_rate"] == -3.0) & (per_sample["sample"] == 1)]
        assert np.array_equal(rows["pressure"].to_numpy(), g["pressure_samples"][1])


def test_stats_dataset(made):
    stats = jamio.load_stats(made.dir("adaptive"))
    ds = stats.dataset()
    assert list(ds["pressure_mean"].dims) == ["n", "phi_init", "log10_rate", "phi"]
    assert list(ds["pressure_samples"].dims) == ["n", "phi_init", "log10_rate", "sample", "phi"]
    assert ds["pressure_error"].attrs["units"] == "k_e/d_s^D"
    e = stats.ensemble(32, 0.7, -2.5)
    got = ds["pressure_mean"].sel(n=32, phi_init=0.7, log10_rate=-2.5).dropna("phi")
    assert np.array_equal(got.values, e.constant_phi["pressure_mean"])
    z = stats.dataset("constant_z")
    assert "z" in z.dims
    assert z["packing_fraction_mean"].attrs["units"] == "1"


def test_ensembles_by_coordinates_and_the_old_keys(made):
    stats = jamio.load_stats(made.dir("adaptive"))
    old = stats.ensembles["n32_phi0.7013_r-3.00"]
    assert stats.by_coordinates[(32, 0.7013, -3.0)] is old
    assert stats.ensemble(32, 0.7013, -3) is old
    assert old.key == (32, 0.7013, -3.0)
    with pytest.raises(KeyError) as e:
        stats.ensemble(32, 0.71, -3)
    assert "(32, 0.7013, -3.0)" in str(e.value)


def test_old_stats_without_units_load_with_jamio_units(made):
    old = os.path.join(made.work, "old-stats")
    os.makedirs(old, exist_ok=True)
    path = os.path.join(old, "stats.h5")
    shutil.copy(os.path.join(made.dir("adaptive"), "stats.h5"), path)
    with h5py.File(path, "r+") as f:
        for k in ("phi_step", "units", "checksum"):  # as written before all three were kept
            del f.attrs[k]
        f.visititems(lambda k, v: v.attrs.__delitem__("units") if "units" in v.attrs
                     else None)
    new = jamio.stats_frame(os.path.join(made.dir("adaptive"), "stats.h5"))
    got = jamio.stats_frame(path)  # no phi_step, no campaign beside: the spacing
    assert "jamio's table" in got.attrs["units_source"]
    assert got.attrs["units"] == new.attrs["units"]
    assert got.equals(new)


def test_reprs_are_short(made):
    run = jamio.load_run(made.run_files("adaptive")[0])
    stats = jamio.load_stats(made.dir("adaptive"))
    ensemble = next(iter(stats.ensembles.values()))
    for obj, lines in ((run, 1), (ensemble, 1), (stats, 3), (stats.fit, 1)):
        text = repr(obj)
        assert len(text.splitlines()) <= lines, text
        assert len(text) < 300, text
        assert "array(" not in text
    assert "N 32" in repr(run)
    assert "41 points" in repr(run)
    assert "sample 0" in repr(run)


def planted(made, name, edit):
    """A copy of the adaptive campaign with `edit` applied to its run `name`."""
    copy = tempfile.mkdtemp(dir=made.work, prefix="planted-")
    shutil.copytree(made.dir("adaptive"), copy, dirs_exist_ok=True)
    path = os.path.join(copy, "runs", name)
    with h5py.File(path, "r+") as f:
        edit(f)
    return copy, path


def assert_refused(campaign, words):
    assert_one_line(lambda: jamio.runs_frame(campaign), words)


def assert_one_line(call, words):
    """call() raises one line of JamioError holding every word."""
    with pytest.raises(jamio.JamioError) as e:
        call()
    text = str(e.value)
    assert len(text.splitlines()) == 1, text
    for w in words:
        assert w in text


def planted_stats(made, edit):
    """A copy of the adaptive campaign's stats.h5, alone in a directory, changed by
    edit(h5py file), its seal taken out (the edit is the case, not the seal it breaks)."""
    path = os.path.join(tempfile.mkdtemp(dir=made.work, prefix="stats-"), "stats.h5")
    shutil.copy(os.path.join(made.dir("adaptive"), "stats.h5"), path)
    with h5py.File(path, "r+") as f:
        del f.attrs["checksum"]
        edit(f)
    return path


def test_a_point_off_the_grid_is_refused(made):
    def shift(f):
        phi = f["packing_fraction"][()]
        phi[5] += 0.002 / 3
        f["packing_fraction"][...] = phi
    campaign, path = planted(made, "n64_phi0.7000_r-2.50_s001.h5", shift)
    with h5py.File(path, "r") as f:
        value = f["packing_fraction"][5]
    assert_refused(campaign, [path, "packing_fraction[5]", repr(float(value)),
                                   "0.71"])


def test_a_run_off_the_campaign_values_is_refused(made):
    def retarget(f):
        f.attrs["fingerprint"] = f.attrs["fingerprint"].replace(
            b"phi_init=0.69999999999999996", b"phi_init=0.71")
    campaign, path = planted(made, "n32_phi0.7000_r-3.00_s000.h5", retarget)
    assert_refused(campaign, [path, "phi_init 0.71", "[0.7, 0.7013]"])


def test_a_samples_table_of_another_shape_is_refused(made):
    """pressure_samples transposed (points x samples) or flattened has as many values as
    (samples, points): reshaped, they went to other rows without a word. Refused, naming
    the dataset and its shape."""
    name = f"{GROUP}/pressure_samples"
    with h5py.File(os.path.join(made.dir("adaptive"), "stats.h5"), "r") as f:
        s, m = f[name].shape
    assert m > s
    for shape in ((m, s), (s * m,)):
        def edit(f):
            v = f[name][()]
            del f[name]
            f[name] = v.T if len(shape) == 2 else v.reshape(-1)
        path = planted_stats(made, edit)
        assert_one_line(lambda: jamio.stats_frame(path, samples=True),
                             [path, name, f"has shape {' x '.join(map(str, shape))}",
                              f"expected S x M = {s} x {m}"])


def test_sample_ids_and_sizes_that_are_not_whole_numbers_are_refused(made):
    """A sample id of 1.5 (read as 1) or NaN (as -2^63), an ensemble's n of 64.5 and a
    run's sample of 2.7 (cut to 64 and 2): each refused, naming the field and the value."""
    for ids, words in (([0.0, 1.5], ["sample_ids' holds 1.5"]),
                       ([np.nan, 1.0], ["sample_ids' holds nan"])):
        def edit(f):
            f[f"{GROUP}/sample_ids"][...] = ids
        path = planted_stats(made, edit)
        for samples in (False, True):
            assert_one_line(lambda: jamio.stats_frame(path, samples=samples),
                                 [path, *words, "not a whole number"])

    def half_size(f):
        f[os.path.dirname(GROUP)].attrs["n"] = 64.5
    path = planted_stats(made, half_size)
    assert_one_line(lambda: jamio.load_stats(path),
                         [path, "attribute 'n'", "64.5", "not a whole number"])
    campaign, path = planted(made, "n64_phi0.7000_r-2.50_s001.h5",
                                  lambda f: f.attrs.__setitem__("sample", 2.7))
    assert_refused(campaign, [path, "attribute 'sample'", "2.7", "not a whole number"])


def test_missing_or_mismatched_datasets_are_one_line(made):
    """What raised IndexError, KeyError, ZeroDivisionError or a pandas ValueError: a run of
    no points, a missing `_error`, sample_ids or z_step, a mean shorter than its grid, a
    run's phi_step missing or 0 where the campaign file gives none. Each a JamioError
    naming the file and the field."""
    def empty(f):
        for k in [k for k, v in f.items() if isinstance(v, h5py.Dataset)]:
            del f[k]
            f[k] = np.zeros(0)
    campaign, path = planted(made, "n64_phi0.7000_r-2.50_s001.h5", empty)
    assert_refused(campaign, [path, "'packing_fraction' is empty"])

    def shorten(f):
        mean = f[f"{GROUP}/pressure_mean"][()]
        del f[f"{GROUP}/pressure_mean"]
        f[f"{GROUP}/pressure_mean"] = mean[1:]
    # (edit, words, average, the tables that read it: of means, of samples)
    for edit, words, average, tables in (
            (lambda f: f[GROUP].__delitem__("pressure_error"),
             ["pressure_error missing"], "constant_phi", (False,)),
            (lambda f: f[GROUP].__delitem__("sample_ids"), ["sample_ids' missing"],
             "constant_phi", (False, True)),
            (lambda f: f.attrs.__delitem__("z_step"), ["'z_step'"], "constant_z",
             (False, True)),
            (shorten, ["pressure_mean' has", "values, expected"], "constant_phi",
             (False,))):
        path = planted_stats(made, edit)
        for samples in tables:
            assert_one_line(lambda: jamio.stats_frame(path, average, samples),
                                 [path, *words])
    for edit, words in ((lambda f: f.attrs.__delitem__("phi_step"),
                         ["has no attribute 'phi_step'"]),
                        (lambda f: f.attrs.__setitem__("phi_step", 0.0),
                         ["attribute 'phi_step' is 0.0"])):
        campaign, path = planted(made, "n64_phi0.7000_r-2.50_s001.h5", edit)
        toml = os.path.join(campaign, "campaign.toml")
        with open(toml) as f:
            text = f.read()
        with open(toml, "w") as f:  # the campaign file gives no phi_step: the run's is used
            f.write("".join(line for line in text.splitlines(True)
                            if not line.startswith("phi_step")))
        assert_refused(campaign, [path, *words])


def test_without_pandas_or_xarray_one_line_names_the_package(made, source):
    code = ("import sys\n"
            "for m in sys.argv[2].split(','): sys.modules[m] = None\n"
            "sys.path.insert(0, sys.argv[3])\n"
            "import jamio\n"
            "print(len(jamio.load_stats(sys.argv[1]).ensembles))\n"
            "print(type(jamio.load_runs(sys.argv[1])).__name__)\n"
            "getattr(jamio, sys.argv[4])(sys.argv[1])\n")
    for blocked, call, package in (("pandas,xarray", "runs_frame", "pandas"),
                                   ("xarray", "runs_dataset", "xarray"),
                                   ("xarray", "stats_dataset", "xarray")):
        r = run([sys.executable, "-c", code, made.dir("adaptive"), blocked,
                 os.path.join(source, "python"), call], made.work, expect=(1,))
        last = r.stderr.strip().splitlines()[-1]
        assert last.split(": ", 1)[0] == "ImportError", r.stderr
        assert f"needs {package}" in last
        assert f"python3-{package}" in last
        assert "During handling" not in r.stderr  # the one line, no chained traceback
        expected = "dict" if "pandas" in blocked else "DataFrame"
        assert r.stdout.split() == ["8", expected], r.stdout
