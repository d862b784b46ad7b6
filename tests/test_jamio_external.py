#!/usr/bin/python3
"""jamio on an external campaign: runs jam did not plan, imported with `jam campaign import`.

The test writes its own open runs with jamio.write_run under another simulator's name (N 64,
2D, rates 1e-3 and 1e-4, 3 samples each) on output grids of their own: the rate 1e-3 runs at
the packings k * 0.002 as another code computes them in binary (within round-off of the grid),
the rate 1e-4 runs at times of their own, a different count per sample (off any grid). Their
phi_init differ in the last digits, as a code's box arithmetic makes them, so that the
ensembles' nominal values (the first imported run's, kept in external.toml) are not every
file's. A run of another model is imported too and set aside. Then `jam campaign import`
(phi_step 0.002) and `jam stats`, and:

- load_design reads external.toml: sizes, phi_init, log10_rates, phi_step, the model, the runs
  and the file set aside;
- load_runs gives the files' own values (phi_init as written), the series bitwise as written,
  simulator and simulator_version per run, NaN where a run lacks a series, no seed;
- runs_frame and runs_dataset: n, phi_init, log10_rate, sample exactly external.toml's
  nominal values, phi the grid values (computed here in decimal) where the points are on the
  grid and the written packings where not, the series bitwise as written, units from the files;
- load_stats, stats_frame, stats_dataset: the same nominal coordinates, the grid of phi_step
  between the samples' common range, each mean equal to the mean of the written pressures
  interpolated here, no constant-Z averages (the runs carry no contacts_per_particle);
- a stray file in runs/ (a valid open run external.toml does not list, and a file that is not
  HDF5) is not read: the tables are unchanged;
- a tampered run (a negative pressure; another n in a run that still validates; a deleted
  file) is refused in one line naming it, and with skip_unreadable=True left out with a warning
  naming it;
- a damaged external.toml is refused naming the file, the run table and the key.

Usage (ctest runs it): python3 -m pytest tests/test_jamio_external.py --jam build/jam --source .
"""

import json
import math
import os
import shutil
import subprocess
import tempfile
import tomllib
import warnings
from decimal import Decimal

import h5py
import numpy as np
import pytest

import jamio

N, DIM, STEP = 64, 2, 0.002
RATES = {-3.0: 1e-3, -4.0: 1e-4}
SAMPLES = (0, 1, 2)
# Each run's phi_init as its code wrote it; the first imported run of an ensemble (sample 0)
# gives the ensemble's nominal value: 0.8 at rate 1e-3, 0.7999999999999997 at 1e-4.
PHI_INIT = {(-3.0, 0): 0.8, (-3.0, 1): 0.8000000000000003, (-3.0, 2): 0.8,
            (-4.0, 0): 0.7999999999999997, (-4.0, 1): 0.8, (-4.0, 2): 0.8000000000000003}
NOMINAL_PHI_INIT = {-3.0: 0.8, -4.0: 0.7999999999999997}
SIMULATOR = "toy-md"
VERSION = {-3.0: "1.0", -4.0: "1.1-rc2"}
COORDINATES = ["n", "phi_init", "log10_rate", "sample"]


def run(cmd, cwd, expect=(0,)):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=600)
    if r.returncode not in expect:
        raise AssertionError(f"{' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}")
    return r


def decimal_grid(k):
    """k * STEP in decimal, rounded once: the grid value jamio must give."""
    return float(Decimal(k) * Decimal(str(STEP)))


def series(log10_rate, sample):
    """One run's output points: (time, packing_fraction, pressure, energy or None)."""
    rate, phi_init = RATES[log10_rate], PHI_INIT[(log10_rate, sample)]
    if log10_rate == -3.0:
        # At the packings 0.800, 0.802, ..., 0.860, from the times that reach them.
        targets = np.array([k * STEP for k in range(400, 431)])
        t = np.maximum(np.log(targets / phi_init) / (DIM * rate), 0.0)
        t[0] = 0.0
    else:
        t = np.linspace(0.0, math.log(0.8593 / 0.8) / (DIM * rate), 23 + 6 * sample)
    phi = phi_init * np.exp(DIM * rate * t)
    pressure = np.maximum(phi - 0.842, 0.0) * (1.0 + 0.05 * sample) + 1e-3 * rate ** 0.5 * phi
    energy = 0.5 * pressure ** 2 if log10_rate == -3.0 else None
    return t, phi, pressure, energy


def run_name(log10_rate, sample):
    return f"n{N}_phi0.8000_r{log10_rate:.2f}_s{sample:03d}"


class Imported:
    """The open runs written and imported (`jam campaign import`, `jam stats`) in `work`."""

    def __init__(self, jam, work):
        self.work = work
        made = os.path.join(self.work, "made")
        os.makedirs(made)
        self.written = {}
        files = []
        for log10_rate in RATES:
            for sample in SAMPLES:
                t, phi, p, energy = series(log10_rate, sample)
                path = os.path.join(made, f"r{log10_rate:g}_s{sample}.h5")
                jamio.write_run(path, phi, p, time=t, energy_per_particle=energy, dim=DIM, n=N,
                                rate=RATES[log10_rate], phi_init=PHI_INIT[(log10_rate, sample)],
                                simulator=SIMULATOR, simulator_version=VERSION[log10_rate],
                                sample=sample)
                self.written[(log10_rate, sample)] = {"time": t, "packing_fraction": phi,
                                                     "pressure": p, "energy_per_particle": energy}
                files.append(path)
        other = os.path.join(made, "other-model.h5")
        t, phi, p, _ = series(-3.0, 0)
        jamio.write_run(other, phi, p, time=t, dim=DIM, n=N, rate=1e-3, phi_init=0.8,
                        simulator=SIMULATOR, sample=5, diameter_ratio=1.3)
        self.other = other
        self.dir = os.path.join(self.work, "toy")
        run([jam, "campaign", "import", self.dir, *files, "--phi-step", str(STEP)], work)
        run([jam, "campaign", "import", self.dir, other], work, expect=(1,))
        run([jam, "stats", self.dir], work)
        with open(os.path.join(self.dir, "external.toml"), "rb") as f:
            self.toml = tomllib.load(f)

    def copy(self):
        """A copy of the campaign to spoil."""
        copy = tempfile.mkdtemp(dir=self.work, prefix="copy-")
        shutil.copytree(self.dir, copy, dirs_exist_ok=True)
        return copy

    def expected_phi(self, log10_rate, sample):
        """phi of each point: the decimal grid value at rate 1e-3 (every point within
        round-off of k * 0.002), the written packing at 1e-4 but for the start (0.8 = 400 *
        0.002 to round-off)."""
        phi = self.written[(log10_rate, sample)]["packing_fraction"]
        if log10_rate == -3.0:
            return [decimal_grid(k) for k in range(400, 431)]
        return [decimal_grid(400)] + phi[1:].tolist()

    def expected_means(self, log10_rate):
        """The grid jam's statistics average on (k * 0.002 within every sample's range) and
        the mean over samples of the written pressures interpolated linearly onto it."""
        runs = [self.written[(log10_rate, s)] for s in SAMPLES]
        lo = max(r["packing_fraction"][0] for r in runs)
        hi = min(r["packing_fraction"][-1] for r in runs)
        ks = range(math.ceil(lo / STEP - 1e-9), math.floor(hi / STEP + 1e-9) + 1)
        at = np.array([k * STEP for k in ks])
        each = [np.interp(at, r["packing_fraction"], r["pressure"]) for r in runs]
        return [decimal_grid(k) for k in ks], np.mean(each, axis=0), each

    def assert_refused(self, campaign, words):
        for call in (jamio.load_runs, jamio.runs_frame, jamio.runs_dataset):
            with pytest.raises(jamio.JamioError) as e:
                call(campaign)
            text = str(e.value)
            assert len(text.splitlines()) == 1, text
            for w in words:
                assert w in text, call.__name__
        for call in (jamio.load_runs, jamio.runs_frame):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                df = call(campaign, skip_unreadable=True)
            assert df["run"].nunique() == 5, call.__name__
            assert len(caught) == 1
            assert words[0] in str(caught[0].message)
            assert "skipped" in str(caught[0].message)

    def tampered(self, edit):
        copy = self.copy()
        path = os.path.join(copy, "runs", run_name(-4.0, 1) + ".h5")
        with h5py.File(path, "r+") as f:
            edit(f)
        return copy, path


@pytest.fixture(scope="module")
def ext(jam):
    """The imported campaign, in a directory of a short path (refusals quote the paths)."""
    for module in ("pandas", "xarray"):  # a failure, not a skip: they are test packages
        try:
            __import__(module)
        except ImportError:
            pytest.fail(f"needs {module} (Debian: python3-{module}; scripts/setup.sh --tests "
                        "installs it)")
    work = tempfile.mkdtemp(prefix="jam-jamio-external-")
    yield Imported(jam, work)
    shutil.rmtree(work, ignore_errors=True)


# ---- the setup itself ----------------------------------------------------------------------------


def test_the_import_and_external_toml(ext, jam):
    """What the checks below rely on: six runs imported under their names, the ensembles'
    nominal phi_init the first imported run's (not every file's), the other model set aside,
    the rate 1e-4 points off the grid but for the first."""
    runs = {(r["log10_rate"], r["sample"]): r for r in ext.toml["run"]}
    assert sorted(runs) == sorted(ext.written)
    for (log10_rate, sample), r in runs.items():
        assert r["name"] == run_name(log10_rate, sample)
        assert r["phi_init"] == NOMINAL_PHI_INIT[log10_rate]
    assert [a["file"] for a in ext.toml["set_aside"]] == [ext.other]
    assert PHI_INIT[(-3.0, 1)] != NOMINAL_PHI_INIT[-3.0]
    for sample in SAMPLES:
        phi = ext.written[(-4.0, sample)]["packing_fraction"]
        k = np.round(phi / STEP)
        assert np.all(np.abs(phi - k * STEP)[1:] > 1e-9), sample
    status = json.loads(run([jam, "campaign", "status", ext.dir, "--json"],
                            ext.work).stdout)
    assert {r["status"] for r in status["runs"]} == {"done"}


# ---- the design ----------------------------------------------------------------------------------


def test_design_from_external_toml(ext):
    design = jamio.load_design(ext.dir)
    assert design.path == os.path.join(ext.dir, "external.toml")
    assert design.name == "toy"
    assert design.dim == DIM
    assert design.sizes == (N,)
    assert design.phi_init == tuple(sorted(NOMINAL_PHI_INIT.values()))
    assert design.log10_rates == (-4.0, -3.0)
    assert design.phi_step == STEP
    assert design.phi_stop is None
    assert design.chain_phi_init == {}
    e = design.external
    assert isinstance(e, jamio.ExternalCampaign)
    assert (e.dim, e.diameter_ratio, e.contact, e.dynamics, e.q) == \
        (DIM, 1.4, "harmonic", "overdamped", 0.0)
    assert len(e.runs) == 6
    r = next(r for r in e.runs if r.name == run_name(-4.0, 2))
    assert (r.n, r.phi_init, r.log10_rate, r.sample) == (N, 0.7999999999999997, -4.0, 2)
    assert (r.simulator, r.simulator_version) == (SIMULATOR, "1.1-rc2")
    assert r.source.endswith("r-4_s2.h5"), r.source
    assert len(r.source_checksum) == 16
    assert [f for f, _ in e.set_aside] == [ext.other]
    assert "diameter_ratio" in e.set_aside[0][1]
    assert jamio.is_external(ext.dir)


def test_a_damaged_external_toml_is_refused_naming_the_key(ext):
    copy = ext.copy()
    path = os.path.join(copy, "external.toml")
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text.replace(f"n = {N}\n", 'n = "sixty-four"\n', 1))
    for call in (jamio.load_design, jamio.load_runs, jamio.runs_frame):
        with pytest.raises(jamio.JamioError) as e:
            call(copy)
        text = str(e.value)
        assert len(text.splitlines()) == 1
        for w in (path, "run[0]", "key 'n'", "sixty-four", "whole number"):
            assert w in text

# ---- the runs ------------------------------------------------------------------------------------


def test_load_run_of_an_open_run_names_its_reader(ext):
    # An imported open run has no seed or dt: load_run says which reader it needs, rather
    # than "attribute 'seed' missing".
    path = jamio.run_files(ext.dir)[0]
    with pytest.raises(jamio.JamioError) as e:
        jamio.load_run(path)
    assert "validate_run" in str(e.value)
    assert "'seed' missing" not in str(e.value)
    assert jamio.validate_run(path).n == N


def test_load_runs_has_the_files_values(ext):
    table = jamio.load_runs(ext.dir)
    assert list(table.columns) == ["run", "n", "phi_init", "compression_rate", "sample",
                                   "simulator", "simulator_version", "packing_fraction",
                                   "pressure", "energy_per_particle", "time"]
    assert table["run"].nunique() == 6
    for (log10_rate, sample), w in ext.written.items():
        rows = table[table["run"] == run_name(log10_rate, sample)]
        assert len(rows) == len(w["pressure"])
        assert set(rows["phi_init"]) == {PHI_INIT[(log10_rate, sample)]}
        assert set(rows["compression_rate"]) == {RATES[log10_rate]}
        assert set(rows["n"]) == {N}
        assert set(rows["sample"]) == {sample}
        assert set(rows["simulator"]) == {SIMULATOR}
        assert set(rows["simulator_version"]) == {VERSION[log10_rate]}
        for name in ("packing_fraction", "pressure", "time"):
            assert np.array_equal(rows[name].to_numpy(), w[name]), name
        energy = rows["energy_per_particle"].to_numpy()
        if w["energy_per_particle"] is None:
            assert np.all(np.isnan(energy))
        else:
            assert np.array_equal(energy, w["energy_per_particle"])
    plain = jamio.load_runs(ext.dir, as_frame=False)
    assert sorted(plain) == sorted(table.columns)
    assert len(jamio.run_files(ext.dir)) == 6


def test_runs_frame_has_the_nominal_values_and_the_written_points(ext):
    df = jamio.runs_frame(ext.dir)
    assert list(df.columns) == ["run", "n", "phi_init", "log10_rate", "sample", "phi",
                                "simulator", "simulator_version", "packing_fraction", "pressure",
                                "energy_per_particle", "time"]
    assert df.attrs["campaign"] == "toy"
    assert df.attrs["units_source"] == "the files"
    assert df.attrs["units"]["pressure"] == "k_e/d_s^D"
    assert df.attrs["units"]["log10_rate"] == "log10(1/t0)"
    assert "simulator" not in df.attrs["units"]
    listed = {r["name"]: r for r in ext.toml["run"]}
    for (log10_rate, sample), w in ext.written.items():
        name = run_name(log10_rate, sample)
        rows = df[df["run"] == name]
        want = listed[name]
        for c in COORDINATES:
            assert set(rows[c]) == {want[c]}, f"{name} {c}"
        assert set(rows["phi_init"]) == {NOMINAL_PHI_INIT[log10_rate]}
        assert set(rows["log10_rate"]) == {log10_rate}
        assert rows["phi"].tolist() == ext.expected_phi(log10_rate, sample), name
        assert set(rows["simulator_version"]) == {VERSION[log10_rate]}
        for c in ("packing_fraction", "pressure", "time"):
            assert np.array_equal(rows[c].to_numpy(), w[c]), f"{name} {c}"
    # The rate 1e-3 samples share their grid values: one row per sample at each.
    on_grid = df[df["log10_rate"] == -3.0].groupby(["n", "phi_init", "log10_rate", "phi"])
    assert set(on_grid.size()) == {3}
    assert len(on_grid) == 31


def test_runs_dataset(ext):
    ds = jamio.runs_dataset(ext.dir)
    assert list(ds["pressure"].dims) == COORDINATES + ["phi"]
    assert ds["n"].values.tolist() == [N]
    assert ds["phi_init"].values.tolist() == sorted(NOMINAL_PHI_INIT.values())
    assert ds["sample"].values.tolist() == list(SAMPLES)
    assert ds["pressure"].attrs["units"] == "k_e/d_s^D"
    for (log10_rate, sample), w in ext.written.items():
        p = ds["pressure"].sel(n=N, phi_init=NOMINAL_PHI_INIT[log10_rate],
                               log10_rate=log10_rate, sample=sample).dropna("phi")
        assert np.array_equal(p.values, w["pressure"])
        assert p["phi"].values.tolist() == ext.expected_phi(log10_rate, sample)

# ---- the statistics ------------------------------------------------------------------------------


def test_stats_frame_nominal_values_and_means(ext):
    stats = jamio.load_stats(ext.dir)
    assert stats.attrs["campaign"] == "toy"
    assert len(stats.ensembles) == 2
    for e in stats.ensembles.values():
        assert e.constant_z is None  # no contacts_per_particle in the runs
    df = jamio.stats_frame(ext.dir)
    assert sorted(df["phi_init"].unique()) == sorted(NOMINAL_PHI_INIT.values())
    assert df.attrs["units"]["pressure_mean"] == "k_e/d_s^D"
    samples = jamio.stats_frame(ext.dir, samples=True)
    for log10_rate, phi_init in NOMINAL_PHI_INIT.items():
        rows = df[(df["n"] == N) & (df["phi_init"] == phi_init)
                  & (df["log10_rate"] == log10_rate)]
        grid, mean, each = ext.expected_means(log10_rate)
        assert rows["phi"].tolist() == grid, log10_rate
        assert set(rows["samples"]) == {3}
        assert np.allclose(rows["pressure_mean"].to_numpy(), mean, rtol=1e-12, atol=1e-300), \
            log10_rate
        assert stats.ensemble(N, phi_init, log10_rate).key.phi_init == phi_init
        for sample in SAMPLES:
            got = samples[(samples["log10_rate"] == log10_rate)
                          & (samples["sample"] == sample)]
            assert np.allclose(got["pressure"].to_numpy(), each[sample], rtol=1e-12,
                               atol=1e-300)
    z = jamio.stats_frame(ext.dir, "constant_z")
    assert len(z) == 0
    assert "z" in z.columns


def test_stats_dataset(ext):
    ds = jamio.stats_dataset(ext.dir)
    assert list(ds["pressure_mean"].dims) == ["n", "phi_init", "log10_rate", "phi"]
    assert list(ds["pressure_samples"].dims) == ["n", "phi_init", "log10_rate", "sample", "phi"]
    assert ds["phi_init"].values.tolist() == sorted(NOMINAL_PHI_INIT.values())
    grid, mean, _ = ext.expected_means(-4.0)
    got = ds["pressure_mean"].sel(n=N, phi_init=NOMINAL_PHI_INIT[-4.0],
                                  log10_rate=-4.0).dropna("phi")
    assert got["phi"].values.tolist() == grid
    assert np.allclose(got.values, mean, rtol=1e-12, atol=1e-300)

# ---- files that are not the campaign's -----------------------------------------------------------


def test_a_stray_file_in_runs_is_not_read(ext):
    copy = ext.copy()
    runs = os.path.join(copy, "runs")
    # A valid open run of this model under a run's name, and a file that is not HDF5.
    t, phi, p, _ = series(-3.0, 0)
    jamio.write_run(os.path.join(runs, f"n{N}_phi0.8000_r-3.00_s007.h5"), phi, p * 9,
                         time=t, dim=DIM, n=N, rate=1e-3, phi_init=0.8,
                         simulator="stray", sample=7)
    with open(os.path.join(runs, "junk.h5"), "w") as f:
        f.write("not HDF5\n")
    assert jamio.run_files(copy) == [os.path.join(runs, os.path.basename(f))
                                     for f in jamio.run_files(ext.dir)]
    for call in (jamio.load_runs, jamio.runs_frame):
        got, want = call(copy), call(ext.dir)
        assert got.equals(want), call.__name__
        assert 7 not in set(got["sample"])
    assert jamio.runs_dataset(copy).equals(jamio.runs_dataset(ext.dir))


def test_a_run_that_no_longer_validates_is_refused_naming_it(ext):
    def negative(f):
        p = f["pressure"][()]
        p[4] = -0.5
        f["pressure"][...] = p
    copy, path = ext.tampered(negative)
    ext.assert_refused(copy, [path, "pressure[4]"])


def test_a_run_that_is_another_run_is_refused_naming_it(ext):
    """Still a valid open run, but of another N than the run imported under its name."""
    def other_n(f):
        f.attrs["n"] = np.int64(128)
    copy, path = ext.tampered(other_n)
    jamio.validate_run(path)  # the format alone takes it
    ext.assert_refused(copy, [path, "n 128", "external.toml has 64"])


def test_a_missing_run_is_refused_naming_it(ext):
    copy = ext.copy()
    path = os.path.join(copy, "runs", run_name(-3.0, 2) + ".h5")
    os.unlink(path)
    ext.assert_refused(copy, [path, "missing"])


def test_run_files_of_jam_sim_read_under_the_sample_ids_the_import_gave(ext, jam):
    # `jam sim` writes no sample id; the import gives the second file sample 1 in
    # external.toml (the file itself unchanged), and jamio reads it under that id.
    made = tempfile.mkdtemp(dir=ext.work, prefix="sim-")
    files = []
    for seed in (1, 2):
        path = os.path.join(made, f"seed{seed}.h5")
        run([jam, "sim", "--quiet", "--n", "64", "--phi-init", "0.7", "--phi-stop",
             "0.72", "--rate", "1e-2", "--phi-step", "0.005", "--seed", str(seed), "--out",
             path], made)
        files.append(path)
    campaign = os.path.join(made, "c")
    run([jam, "campaign", "import", campaign, *files], made)
    _, loaded = jamio.load_external_runs(campaign)
    assert [(e.sample, r.sample) for e, r in loaded] == [(0, None), (1, None)]
