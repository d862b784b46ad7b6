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

Usage (ctest runs it): test_jamio_external.py --jam build/jam --source .
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
import unittest
import warnings
from decimal import Decimal

import h5py
import numpy as np

ARGS = None
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


class External(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        sys.path.insert(0, os.path.join(ARGS.source, "python"))
        import jamio
        cls.jamio = jamio
        cls.work = tempfile.mkdtemp(prefix="jam-jamio-external-")
        made = os.path.join(cls.work, "made")
        os.makedirs(made)
        cls.written = {}
        files = []
        for log10_rate in RATES:
            for sample in SAMPLES:
                t, phi, p, energy = series(log10_rate, sample)
                path = os.path.join(made, f"r{log10_rate:g}_s{sample}.h5")
                jamio.write_run(path, phi, p, time=t, energy_per_particle=energy, dim=DIM, n=N,
                                rate=RATES[log10_rate], phi_init=PHI_INIT[(log10_rate, sample)],
                                simulator=SIMULATOR, simulator_version=VERSION[log10_rate],
                                sample=sample)
                cls.written[(log10_rate, sample)] = {"time": t, "packing_fraction": phi,
                                                     "pressure": p, "energy_per_particle": energy}
                files.append(path)
        other = os.path.join(made, "other-model.h5")
        t, phi, p, _ = series(-3.0, 0)
        jamio.write_run(other, phi, p, time=t, dim=DIM, n=N, rate=1e-3, phi_init=0.8,
                        simulator=SIMULATOR, sample=5, diameter_ratio=1.3)
        cls.other = other
        cls.dir = os.path.join(cls.work, "toy")
        run([ARGS.jam, "campaign", "import", cls.dir, *files, "--phi-step", str(STEP)], cls.work)
        run([ARGS.jam, "campaign", "import", cls.dir, other], cls.work, expect=(1,))
        run([ARGS.jam, "stats", cls.dir], cls.work)
        with open(os.path.join(cls.dir, "external.toml"), "rb") as f:
            cls.toml = tomllib.load(f)

    @classmethod
    def tearDownClass(cls):
        if not ARGS.keep:
            shutil.rmtree(cls.work, ignore_errors=True)

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

    # ---- the setup itself ------------------------------------------------------------------

    def test_the_import_and_external_toml(self):
        """What the checks below rely on: six runs imported under their names, the ensembles'
        nominal phi_init the first imported run's (not every file's), the other model set aside,
        the rate 1e-4 points off the grid but for the first."""
        runs = {(r["log10_rate"], r["sample"]): r for r in self.toml["run"]}
        self.assertEqual(sorted(runs), sorted(self.written))
        for (log10_rate, sample), r in runs.items():
            self.assertEqual(r["name"], run_name(log10_rate, sample))
            self.assertEqual(r["phi_init"], NOMINAL_PHI_INIT[log10_rate])
        self.assertEqual([a["file"] for a in self.toml["set_aside"]], [self.other])
        self.assertNotEqual(PHI_INIT[(-3.0, 1)], NOMINAL_PHI_INIT[-3.0])
        for sample in SAMPLES:
            phi = self.written[(-4.0, sample)]["packing_fraction"]
            k = np.round(phi / STEP)
            self.assertTrue(np.all(np.abs(phi - k * STEP)[1:] > 1e-9), sample)
        status = json.loads(run([ARGS.jam, "campaign", "status", self.dir, "--json"],
                                self.work).stdout)
        self.assertEqual({r["status"] for r in status["runs"]}, {"done"})

    # ---- the design ------------------------------------------------------------------------

    def test_design_from_external_toml(self):
        design = self.jamio.load_design(self.dir)
        self.assertEqual(design.path, os.path.join(self.dir, "external.toml"))
        self.assertEqual(design.name, "toy")
        self.assertEqual(design.dim, DIM)
        self.assertEqual(design.sizes, (N,))
        self.assertEqual(design.phi_init, tuple(sorted(NOMINAL_PHI_INIT.values())))
        self.assertEqual(design.log10_rates, (-4.0, -3.0))
        self.assertEqual(design.phi_step, STEP)
        self.assertIsNone(design.phi_stop)
        self.assertEqual(design.chain_phi_init, {})
        e = design.external
        self.assertIsInstance(e, self.jamio.ExternalCampaign)
        self.assertEqual((e.dim, e.diameter_ratio, e.contact, e.dynamics, e.q),
                         (DIM, 1.4, "harmonic", "overdamped", 0.0))
        self.assertEqual(len(e.runs), 6)
        r = next(r for r in e.runs if r.name == run_name(-4.0, 2))
        self.assertEqual((r.n, r.phi_init, r.log10_rate, r.sample), (N, 0.7999999999999997,
                                                                    -4.0, 2))
        self.assertEqual((r.simulator, r.simulator_version), (SIMULATOR, "1.1-rc2"))
        self.assertTrue(r.source.endswith("r-4_s2.h5"), r.source)
        self.assertEqual(len(r.source_checksum), 16)
        self.assertEqual([f for f, _ in e.set_aside], [self.other])
        self.assertIn("diameter_ratio", e.set_aside[0][1])
        self.assertTrue(self.jamio.is_external(self.dir))

    def test_a_damaged_external_toml_is_refused_naming_the_key(self):
        copy = self.copy()
        path = os.path.join(copy, "external.toml")
        with open(path) as f:
            text = f.read()
        with open(path, "w") as f:
            f.write(text.replace(f"n = {N}\n", 'n = "sixty-four"\n', 1))
        for call in (self.jamio.load_design, self.jamio.load_runs, self.jamio.runs_frame):
            with self.assertRaises(self.jamio.JamioError) as e:
                call(copy)
            text = str(e.exception)
            self.assertEqual(len(text.splitlines()), 1)
            for w in (path, "run[0]", "key 'n'", "sixty-four", "whole number"):
                self.assertIn(w, text)

    # ---- the runs --------------------------------------------------------------------------

    def test_load_run_of_an_open_run_names_its_reader(self):
        # An imported open run has no seed or dt: load_run says which reader it needs, rather
        # than "attribute 'seed' missing".
        path = self.jamio.run_files(self.dir)[0]
        with self.assertRaises(self.jamio.JamioError) as e:
            self.jamio.load_run(path)
        self.assertIn("validate_run", str(e.exception))
        self.assertNotIn("'seed' missing", str(e.exception))
        self.assertEqual(self.jamio.validate_run(path).n, N)

    def test_load_runs_has_the_files_values(self):
        table = self.jamio.load_runs(self.dir)
        self.assertEqual(list(table.columns),
                         ["run", "n", "phi_init", "compression_rate", "sample", "simulator",
                          "simulator_version", "packing_fraction", "pressure",
                          "energy_per_particle", "time"])
        self.assertEqual(table["run"].nunique(), 6)
        for (log10_rate, sample), w in self.written.items():
            rows = table[table["run"] == run_name(log10_rate, sample)]
            self.assertEqual(len(rows), len(w["pressure"]))
            self.assertEqual(set(rows["phi_init"]), {PHI_INIT[(log10_rate, sample)]})
            self.assertEqual(set(rows["compression_rate"]), {RATES[log10_rate]})
            self.assertEqual(set(rows["n"]), {N})
            self.assertEqual(set(rows["sample"]), {sample})
            self.assertEqual(set(rows["simulator"]), {SIMULATOR})
            self.assertEqual(set(rows["simulator_version"]), {VERSION[log10_rate]})
            for name in ("packing_fraction", "pressure", "time"):
                self.assertTrue(np.array_equal(rows[name].to_numpy(), w[name]), name)
            energy = rows["energy_per_particle"].to_numpy()
            if w["energy_per_particle"] is None:
                self.assertTrue(np.all(np.isnan(energy)))
            else:
                self.assertTrue(np.array_equal(energy, w["energy_per_particle"]))
        plain = self.jamio.load_runs(self.dir, as_frame=False)
        self.assertEqual(sorted(plain), sorted(table.columns))
        self.assertEqual(len(self.jamio.run_files(self.dir)), 6)

    def test_runs_frame_has_the_nominal_values_and_the_written_points(self):
        df = self.jamio.runs_frame(self.dir)
        self.assertEqual(list(df.columns),
                         ["run", "n", "phi_init", "log10_rate", "sample", "phi", "simulator",
                          "simulator_version", "packing_fraction", "pressure",
                          "energy_per_particle", "time"])
        self.assertEqual(df.attrs["campaign"], "toy")
        self.assertEqual(df.attrs["units_source"], "the files")
        self.assertEqual(df.attrs["units"]["pressure"], "k_e/d_s^D")
        self.assertEqual(df.attrs["units"]["log10_rate"], "log10(1/t0)")
        self.assertNotIn("simulator", df.attrs["units"])
        listed = {r["name"]: r for r in self.toml["run"]}
        for (log10_rate, sample), w in self.written.items():
            name = run_name(log10_rate, sample)
            rows = df[df["run"] == name]
            want = listed[name]
            for c in COORDINATES:
                self.assertEqual(set(rows[c]), {want[c]}, f"{name} {c}")
            self.assertEqual(set(rows["phi_init"]), {NOMINAL_PHI_INIT[log10_rate]})
            self.assertEqual(set(rows["log10_rate"]), {log10_rate})
            self.assertEqual(rows["phi"].tolist(), self.expected_phi(log10_rate, sample), name)
            self.assertEqual(set(rows["simulator_version"]), {VERSION[log10_rate]})
            for c in ("packing_fraction", "pressure", "time"):
                self.assertTrue(np.array_equal(rows[c].to_numpy(), w[c]), f"{name} {c}")
        # The rate 1e-3 samples share their grid values: one row per sample at each.
        on_grid = df[df["log10_rate"] == -3.0].groupby(["n", "phi_init", "log10_rate", "phi"])
        self.assertEqual(set(on_grid.size()), {3})
        self.assertEqual(len(on_grid), 31)

    def test_runs_dataset(self):
        ds = self.jamio.runs_dataset(self.dir)
        self.assertEqual(list(ds["pressure"].dims), COORDINATES + ["phi"])
        self.assertEqual(ds["n"].values.tolist(), [N])
        self.assertEqual(ds["phi_init"].values.tolist(), sorted(NOMINAL_PHI_INIT.values()))
        self.assertEqual(ds["sample"].values.tolist(), list(SAMPLES))
        self.assertEqual(ds["pressure"].attrs["units"], "k_e/d_s^D")
        for (log10_rate, sample), w in self.written.items():
            p = ds["pressure"].sel(n=N, phi_init=NOMINAL_PHI_INIT[log10_rate],
                                   log10_rate=log10_rate, sample=sample).dropna("phi")
            self.assertTrue(np.array_equal(p.values, w["pressure"]))
            self.assertEqual(p["phi"].values.tolist(), self.expected_phi(log10_rate, sample))

    # ---- the statistics --------------------------------------------------------------------

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

    def test_stats_frame_nominal_values_and_means(self):
        stats = self.jamio.load_stats(self.dir)
        self.assertEqual(stats.attrs["campaign"], "toy")
        self.assertEqual(len(stats.ensembles), 2)
        for e in stats.ensembles.values():
            self.assertIsNone(e.constant_z)  # no contacts_per_particle in the runs
        df = self.jamio.stats_frame(self.dir)
        self.assertEqual(sorted(df["phi_init"].unique()), sorted(NOMINAL_PHI_INIT.values()))
        self.assertEqual(df.attrs["units"]["pressure_mean"], "k_e/d_s^D")
        samples = self.jamio.stats_frame(self.dir, samples=True)
        for log10_rate, phi_init in NOMINAL_PHI_INIT.items():
            rows = df[(df["n"] == N) & (df["phi_init"] == phi_init)
                      & (df["log10_rate"] == log10_rate)]
            grid, mean, each = self.expected_means(log10_rate)
            self.assertEqual(rows["phi"].tolist(), grid, log10_rate)
            self.assertEqual(set(rows["samples"]), {3})
            self.assertTrue(np.allclose(rows["pressure_mean"].to_numpy(), mean, rtol=1e-12,
                                        atol=1e-300), log10_rate)
            self.assertEqual(stats.ensemble(N, phi_init, log10_rate).key.phi_init, phi_init)
            for sample in SAMPLES:
                got = samples[(samples["log10_rate"] == log10_rate)
                              & (samples["sample"] == sample)]
                self.assertTrue(np.allclose(got["pressure"].to_numpy(), each[sample],
                                            rtol=1e-12, atol=1e-300))
        z = self.jamio.stats_frame(self.dir, "constant_z")
        self.assertEqual(len(z), 0)
        self.assertIn("z", z.columns)

    def test_stats_dataset(self):
        ds = self.jamio.stats_dataset(self.dir)
        self.assertEqual(list(ds["pressure_mean"].dims), ["n", "phi_init", "log10_rate", "phi"])
        self.assertEqual(list(ds["pressure_samples"].dims),
                         ["n", "phi_init", "log10_rate", "sample", "phi"])
        self.assertEqual(ds["phi_init"].values.tolist(), sorted(NOMINAL_PHI_INIT.values()))
        grid, mean, _ = self.expected_means(-4.0)
        got = ds["pressure_mean"].sel(n=N, phi_init=NOMINAL_PHI_INIT[-4.0],
                                      log10_rate=-4.0).dropna("phi")
        self.assertEqual(got["phi"].values.tolist(), grid)
        self.assertTrue(np.allclose(got.values, mean, rtol=1e-12, atol=1e-300))

    # ---- files that are not the campaign's -------------------------------------------------

    def test_a_stray_file_in_runs_is_not_read(self):
        copy = self.copy()
        runs = os.path.join(copy, "runs")
        # A valid open run of this model under a run's name, and a file that is not HDF5.
        t, phi, p, _ = series(-3.0, 0)
        self.jamio.write_run(os.path.join(runs, f"n{N}_phi0.8000_r-3.00_s007.h5"), phi, p * 9,
                             time=t, dim=DIM, n=N, rate=1e-3, phi_init=0.8,
                             simulator="stray", sample=7)
        with open(os.path.join(runs, "junk.h5"), "w") as f:
            f.write("not HDF5\n")
        self.assertEqual(self.jamio.run_files(copy),
                         [os.path.join(runs, os.path.basename(f))
                          for f in self.jamio.run_files(self.dir)])
        for call in (self.jamio.load_runs, self.jamio.runs_frame):
            got, want = call(copy), call(self.dir)
            self.assertTrue(got.equals(want), call.__name__)
            self.assertNotIn(7, set(got["sample"]))
        self.assertTrue(self.jamio.runs_dataset(copy).equals(self.jamio.runs_dataset(self.dir)))

    def assert_refused(self, campaign, words):
        for call in (self.jamio.load_runs, self.jamio.runs_frame, self.jamio.runs_dataset):
            with self.assertRaises(self.jamio.JamioError) as e:
                call(campaign)
            text = str(e.exception)
            self.assertEqual(len(text.splitlines()), 1, text)
            for w in words:
                self.assertIn(w, text, call.__name__)
        for call in (self.jamio.load_runs, self.jamio.runs_frame):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                df = call(campaign, skip_unreadable=True)
            self.assertEqual(df["run"].nunique(), 5, call.__name__)
            self.assertEqual(len(caught), 1)
            self.assertIn(words[0], str(caught[0].message))
            self.assertIn("skipped", str(caught[0].message))

    def tampered(self, edit):
        copy = self.copy()
        path = os.path.join(copy, "runs", run_name(-4.0, 1) + ".h5")
        with h5py.File(path, "r+") as f:
            edit(f)
        return copy, path

    def test_a_run_that_no_longer_validates_is_refused_naming_it(self):
        def negative(f):
            p = f["pressure"][()]
            p[4] = -0.5
            f["pressure"][...] = p
        copy, path = self.tampered(negative)
        self.assert_refused(copy, [path, "pressure[4]"])

    def test_a_run_that_is_another_run_is_refused_naming_it(self):
        """Still a valid open run, but of another N than the run imported under its name."""
        def other_n(f):
            f.attrs["n"] = np.int64(128)
        copy, path = self.tampered(other_n)
        self.jamio.validate_run(path)  # the format alone takes it
        self.assert_refused(copy, [path, "n 128", "external.toml has 64"])

    def test_a_missing_run_is_refused_naming_it(self):
        copy = self.copy()
        path = os.path.join(copy, "runs", run_name(-3.0, 2) + ".h5")
        os.unlink(path)
        self.assert_refused(copy, [path, "missing"])

    def test_run_files_of_jam_sim_read_under_the_sample_ids_the_import_gave(self):
        # `jam sim` writes no sample id; the import gives the second file sample 1 in
        # external.toml (the file itself unchanged), and jamio reads it under that id.
        made = tempfile.mkdtemp(dir=self.work, prefix="sim-")
        files = []
        for seed in (1, 2):
            path = os.path.join(made, f"seed{seed}.h5")
            run([ARGS.jam, "sim", "--quiet", "--n", "64", "--phi-init", "0.7", "--phi-stop",
                 "0.72", "--rate", "1e-2", "--phi-step", "0.005", "--seed", str(seed), "--out",
                 path], made)
            files.append(path)
        campaign = os.path.join(made, "c")
        run([ARGS.jam, "campaign", "import", campaign, *files], made)
        _, loaded = self.jamio.load_external_runs(campaign)
        self.assertEqual([(e.sample, r.sample) for e, r in loaded], [(0, None), (1, None)])


def main():
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jam", required=True, help="the jam binary (build/jam)")
    parser.add_argument("--source", required=True, help="the source tree (holds python/)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    ARGS, rest = parser.parse_known_args()
    ARGS.jam, ARGS.source = os.path.abspath(ARGS.jam), os.path.abspath(ARGS.source)
    for module in ("pandas", "xarray"):
        try:
            __import__(module)
        except ImportError:
            print(f"test_jamio_external: needs {module} (Debian: python3-{module}; "
                  "scripts/setup.sh --tests installs it)")
            return 1
    program = unittest.main(argv=[sys.argv[0], *rest], exit=False, verbosity=2)
    return 0 if program.result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
