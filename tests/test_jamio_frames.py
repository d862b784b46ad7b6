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

Usage (ctest runs it): test_jamio_frames.py --jam build/jam --source .
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
import unittest
from decimal import Decimal

import h5py
import numpy as np

ARGS = None
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
    if r.returncode not in expect:
        raise AssertionError(f"{' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}")
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


class Frames(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="jam-jamio-frames-")
        cls.design = {}
        for name, text in (("adaptive", ADAPTIVE), ("fixed", FIXED)):
            with open(os.path.join(cls.work, f"{name}.toml"), "w") as f:
                f.write(text)
            run([ARGS.jam, "campaign", "run", f"{name}.toml", "--quiet"], cls.work)
            run([ARGS.jam, "stats", name], cls.work)
            cls.design[name] = tomllib.loads(text)
        sys.path.insert(0, os.path.join(ARGS.source, "python"))
        import jamio
        cls.jamio = jamio

    @classmethod
    def tearDownClass(cls):
        if not ARGS.keep:
            shutil.rmtree(cls.work, ignore_errors=True)

    def dir(self, name):
        return os.path.join(self.work, name)

    def run_files(self, name):
        runs = os.path.join(self.dir(name), "runs")
        return sorted(os.path.join(runs, f) for f in os.listdir(runs) if f.endswith(".h5"))

    def test_the_run_files_have_more_values_than_the_campaign(self):
        """The problem, as the run files have it: the raw table's phi_init and packing_fraction
        have more distinct values than the campaign's phi_init and grid (so the checks below
        would fail on them)."""
        for name in ("adaptive", "fixed"):
            raw = self.jamio.load_runs(self.dir(name))
            design = self.design[name]
            grid = {g for e in ensembles(design) for g in expected_grid(design, *e[1:])}
            self.assertGreater(raw["phi_init"].nunique(), len(design["phi_init"]), name)
            if name == "fixed":
                self.assertGreater(raw["packing_fraction"].nunique(), 2 * len(grid))

    def test_runs_frame_has_the_nominal_values_and_the_grid(self):
        for name in ("adaptive", "fixed"):
            design = self.design[name]
            df = self.jamio.runs_frame(self.dir(name))
            self.assertEqual(sorted(df["phi_init"].unique()), sorted(design["phi_init"]))
            self.assertEqual(sorted(df["log10_rate"].unique()), sorted(design["log10_rates"]))
            self.assertEqual(sorted(df["n"].unique()), design["sizes"])
            self.assertEqual(sorted(df["sample"].unique()), list(range(design["samples"])))
            grids = {e: expected_grid(design, *e[1:]) for e in ensembles(design)}
            self.assertEqual(set(df["phi"]), {g for grid in grids.values() for g in grid})
            groups = df.groupby(KEYS).size()
            self.assertEqual(len(groups), sum(len(g) for g in grids.values()), name)
            self.assertEqual(set(groups), {design["samples"]})
            for e, grid in grids.items():
                got = groups.loc[e].index.tolist()
                self.assertEqual(got, grid, f"{name} {e}")
            pivot = df.pivot_table(index=KEYS, columns="sample", values="pressure")
            self.assertEqual(len(pivot), len(groups))
            self.assertFalse(pivot.isna().any().any())
            self.assertEqual(df.attrs["units"]["pressure"], "k_e/d_s^D")
            self.assertEqual(df.attrs["units"]["time"], "t0")
            self.assertEqual(df.attrs["units_source"], "the files")

    def test_runs_frame_values_are_the_run_files(self):
        """Every series equals h5py's array bitwise; coordinates are the files' n and sample,
        and phi is within the integrator's allowance below each packing_fraction."""
        for name in ("adaptive", "fixed"):
            df = self.jamio.runs_frame(self.dir(name))
            for path in self.run_files(name):
                rows = df[df["run"] == os.path.basename(path)[:-3]]
                with h5py.File(path, "r") as f:
                    for series in ("packing_fraction", "pressure", "contacts_per_particle",
                                   "energy_per_particle", "time"):
                        self.assertTrue(np.array_equal(rows[series].to_numpy(), f[series][()]),
                                        f"{path} {series}")
                    self.assertEqual(set(rows["n"]), {f.attrs["n"]})
                    self.assertEqual(set(rows["sample"]), {f.attrs["sample"]})
                    past = (f["packing_fraction"][()] - rows["phi"].to_numpy()) / rows["phi"]
                    self.assertTrue(np.all(past >= -1e-12), path)
                    limit = 1e-12 if name == "adaptive" else 2 * 10 ** -2.5 * 0.05 * 1.01
                    self.assertTrue(np.all(past <= limit), f"{path}: {past.max()}")

    def test_runs_dataset_dimensions_and_values(self):
        design = self.design["adaptive"]
        ds = self.jamio.runs_dataset(self.dir("adaptive"))
        self.assertEqual(list(ds["pressure"].dims), ["n", "phi_init", "log10_rate", "sample",
                                                     "phi"])
        self.assertEqual(ds["n"].values.tolist(), design["sizes"])
        self.assertEqual(sorted(ds["phi_init"].values.tolist()), sorted(design["phi_init"]))
        self.assertEqual(ds.sizes["phi"], len({g for e in ensembles(design)
                                               for g in expected_grid(design, *e[1:])}))
        self.assertEqual(ds["pressure"].attrs["units"], "k_e/d_s^D")
        path = self.run_files("adaptive")[-1]
        with h5py.File(path, "r") as f:
            a = f.attrs
            point = ds["pressure"].sel(n=a["n"], phi_init=0.7013, log10_rate=-3.0,
                                       sample=a["sample"]).dropna("phi")
            self.assertTrue(np.array_equal(point.values, f["pressure"][()]), path)
            self.assertEqual(point["phi"].values[0], 0.74)  # the chained rate's start

    def test_stats_frames_and_units(self):
        stats_path = os.path.join(self.dir("adaptive"), "stats.h5")
        with h5py.File(stats_path, "r") as f:
            lacking = []
            f.visititems(lambda k, v: lacking.append(k) if isinstance(v, h5py.Dataset)
                         and "units" not in v.attrs else None)
            self.assertEqual(lacking, [])
            self.assertEqual(f.attrs["phi_step"], 0.002)
            stats = self.jamio.load_stats(stats_path)
            for average, coordinate, grid in (("constant_phi", "phi", "packing_fraction"),
                                              ("constant_z", "z", "contacts_per_particle")):
                df = stats.frame(average)
                self.assertEqual(df.attrs["units"]["pressure_mean"], "k_e/d_s^D")
                self.assertEqual(df.attrs["units_source"], "the files")
                self.assertEqual(df.groupby(KEYS[:3] + [coordinate]).size().max(), 1)
                for name, g in f["ensembles"].items():
                    key = tuple(g.attrs[k] for k in KEYS[:3])
                    rows = df[(df[KEYS[:3]] == key).all(axis=1)]
                    want = g[f"{average}/pressure_mean"][()]
                    self.assertTrue(np.array_equal(rows["pressure_mean"].to_numpy(), want), name)
                    stored = g[f"{average}/{grid}"][()]
                    step = Decimal(str(0.002 if average == "constant_phi" else f.attrs["z_step"]))
                    exact = [float(round(Decimal(v) / step) * step) for v in stored]
                    self.assertEqual(rows[coordinate].tolist(), exact, name)
            self.assertEqual(sorted(stats.frame()["phi_init"].unique()), [0.7, 0.7013])
            per_sample = stats.frame(samples=True)
            g = f["ensembles/n64_phi0.7013_r-3.00/constant_phi"]
            rows = per_sample[(per_sample["n"] == 64) & (per_sample["phi_init"] == 0.7013)
                              & (per_sample["log10_rate"] == -3.0) & (per_sample["sample"] == 1)]
            self.assertTrue(np.array_equal(rows["pressure"].to_numpy(), g["pressure_samples"][1]))

    def test_stats_dataset(self):
        stats = self.jamio.load_stats(self.dir("adaptive"))
        ds = stats.dataset()
        self.assertEqual(list(ds["pressure_mean"].dims), ["n", "phi_init", "log10_rate", "phi"])
        self.assertEqual(list(ds["pressure_samples"].dims),
                         ["n", "phi_init", "log10_rate", "sample", "phi"])
        self.assertEqual(ds["pressure_error"].attrs["units"], "k_e/d_s^D")
        e = stats.ensemble(32, 0.7, -2.5)
        got = ds["pressure_mean"].sel(n=32, phi_init=0.7, log10_rate=-2.5).dropna("phi")
        self.assertTrue(np.array_equal(got.values, e.constant_phi["pressure_mean"]))
        z = stats.dataset("constant_z")
        self.assertIn("z", z.dims)
        self.assertEqual(z["packing_fraction_mean"].attrs["units"], "1")

    def test_ensembles_by_coordinates_and_the_old_keys(self):
        stats = self.jamio.load_stats(self.dir("adaptive"))
        old = stats.ensembles["n32_phi0.7013_r-3.00"]
        self.assertIs(stats.by_coordinates[(32, 0.7013, -3.0)], old)
        self.assertIs(stats.ensemble(32, 0.7013, -3), old)
        self.assertEqual(old.key, (32, 0.7013, -3.0))
        with self.assertRaises(KeyError) as e:
            stats.ensemble(32, 0.71, -3)
        self.assertIn("(32, 0.7013, -3.0)", str(e.exception))

    def test_old_stats_without_units_load_with_jamio_units(self):
        old = os.path.join(self.work, "old-stats")
        os.makedirs(old, exist_ok=True)
        path = os.path.join(old, "stats.h5")
        shutil.copy(os.path.join(self.dir("adaptive"), "stats.h5"), path)
        with h5py.File(path, "r+") as f:
            for k in ("phi_step", "units"):
                del f.attrs[k]
            f.visititems(lambda k, v: v.attrs.__delitem__("units") if "units" in v.attrs
                         else None)
        new = self.jamio.stats_frame(os.path.join(self.dir("adaptive"), "stats.h5"))
        got = self.jamio.stats_frame(path)  # no phi_step, no campaign beside: the spacing
        self.assertIn("jamio's table", got.attrs["units_source"])
        self.assertEqual(got.attrs["units"], new.attrs["units"])
        self.assertTrue(got.equals(new))

    def test_reprs_are_short(self):
        run = self.jamio.load_run(self.run_files("adaptive")[0])
        stats = self.jamio.load_stats(self.dir("adaptive"))
        ensemble = next(iter(stats.ensembles.values()))
        for obj, lines in ((run, 1), (ensemble, 1), (stats, 3), (stats.fit, 1)):
            text = repr(obj)
            self.assertLessEqual(len(text.splitlines()), lines, text)
            self.assertLess(len(text), 300, text)
            self.assertNotIn("array(", text)
        self.assertIn("N 32", repr(run))
        self.assertIn("41 points", repr(run))
        self.assertIn("sample 0", repr(run))

    def planted(self, name, edit):
        """A copy of the adaptive campaign with `edit` applied to its run `name`."""
        copy = tempfile.mkdtemp(dir=self.work, prefix="planted-")
        shutil.copytree(self.dir("adaptive"), copy, dirs_exist_ok=True)
        path = os.path.join(copy, "runs", name)
        with h5py.File(path, "r+") as f:
            edit(f)
        return copy, path

    def assert_refused(self, campaign, words):
        self.assert_one_line(lambda: self.jamio.runs_frame(campaign), words)

    def assert_one_line(self, call, words):
        """call() raises one line of JamioError holding every word."""
        with self.assertRaises(self.jamio.JamioError) as e:
            call()
        text = str(e.exception)
        self.assertEqual(len(text.splitlines()), 1, text)
        for w in words:
            self.assertIn(w, text)

    def planted_stats(self, edit):
        """A copy of the adaptive campaign's stats.h5, alone in a directory, changed by
        edit(h5py file)."""
        path = os.path.join(tempfile.mkdtemp(dir=self.work, prefix="stats-"), "stats.h5")
        shutil.copy(os.path.join(self.dir("adaptive"), "stats.h5"), path)
        with h5py.File(path, "r+") as f:
            edit(f)
        return path

    def test_a_point_off_the_grid_is_refused(self):
        def shift(f):
            phi = f["packing_fraction"][()]
            phi[5] += 0.002 / 3
            f["packing_fraction"][...] = phi
        campaign, path = self.planted("n64_phi0.7000_r-2.50_s001.h5", shift)
        with h5py.File(path, "r") as f:
            value = f["packing_fraction"][5]
        self.assert_refused(campaign, [path, "packing_fraction[5]", repr(float(value)),
                                       "0.71"])

    def test_a_run_off_the_campaign_values_is_refused(self):
        def retarget(f):
            f.attrs["fingerprint"] = f.attrs["fingerprint"].replace(
                b"phi_init=0.69999999999999996", b"phi_init=0.71")
        campaign, path = self.planted("n32_phi0.7000_r-3.00_s000.h5", retarget)
        self.assert_refused(campaign, [path, "phi_init 0.71", "[0.7, 0.7013]"])

    def test_a_samples_table_of_another_shape_is_refused(self):
        """pressure_samples transposed (points x samples) or flattened has as many values as
        (samples, points): reshaped, they went to other rows without a word. Refused, naming
        the dataset and its shape."""
        name = f"{GROUP}/pressure_samples"
        with h5py.File(os.path.join(self.dir("adaptive"), "stats.h5"), "r") as f:
            s, m = f[name].shape
        self.assertGreater(m, s)
        for shape in ((m, s), (s * m,)):
            def edit(f):
                v = f[name][()]
                del f[name]
                f[name] = v.T if len(shape) == 2 else v.reshape(-1)
            path = self.planted_stats(edit)
            self.assert_one_line(lambda: self.jamio.stats_frame(path, samples=True),
                                 [path, name, f"has shape {shape}", f"expected shape {(s, m)}"])

    def test_sample_ids_and_sizes_that_are_not_whole_numbers_are_refused(self):
        """A sample id of 1.5 (read as 1) or NaN (as -2^63), an ensemble's n of 64.5 and a
        run's sample of 2.7 (cut to 64 and 2): each refused, naming the field and the value."""
        for ids, words in (([0.0, 1.5], ["sample_ids[1] = 1.5"]),
                           ([np.nan, 1.0], ["sample_ids[0] = nan"])):
            def edit(f):
                f[f"{GROUP}/sample_ids"][...] = ids
            path = self.planted_stats(edit)
            for samples in (False, True):
                self.assert_one_line(lambda: self.jamio.stats_frame(path, samples=samples),
                                     [path, *words, "not a whole number"])

        def half_size(f):
            f[os.path.dirname(GROUP)].attrs["n"] = 64.5
        path = self.planted_stats(half_size)
        self.assert_one_line(lambda: self.jamio.load_stats(path),
                             [path, "attribute 'n'", "64.5", "not a whole number"])
        campaign, path = self.planted("n64_phi0.7000_r-2.50_s001.h5",
                                      lambda f: f.attrs.__setitem__("sample", 2.7))
        self.assert_refused(campaign, [path, "attribute 'sample'", "2.7", "not a whole number"])

    def test_missing_or_mismatched_datasets_are_one_line(self):
        """What raised IndexError, KeyError, ZeroDivisionError or a pandas ValueError: a run of
        no points, a missing `_error`, sample_ids or z_step, a mean shorter than its grid, a
        run's phi_step missing or 0 where the campaign file gives none. Each a JamioError
        naming the file and the field."""
        def empty(f):
            for k in [k for k, v in f.items() if isinstance(v, h5py.Dataset)]:
                del f[k]
                f[k] = np.zeros(0)
        campaign, path = self.planted("n64_phi0.7000_r-2.50_s001.h5", empty)
        self.assert_refused(campaign, [path, "'packing_fraction' is empty"])

        def shorten(f):
            mean = f[f"{GROUP}/pressure_mean"][()]
            del f[f"{GROUP}/pressure_mean"]
            f[f"{GROUP}/pressure_mean"] = mean[1:]
        # (edit, words, average, the tables that read it: of means, of samples)
        for edit, words, average, tables in (
                (lambda f: f[GROUP].__delitem__("pressure_error"),
                 ["pressure_error missing"], "constant_phi", (False,)),
                (lambda f: f[GROUP].__delitem__("sample_ids"), ["sample_ids missing"],
                 "constant_phi", (False, True)),
                (lambda f: f.attrs.__delitem__("z_step"), ["'z_step'"], "constant_z",
                 (False, True)),
                (shorten, ["pressure_mean has shape", "expected shape"], "constant_phi",
                 (False,))):
            path = self.planted_stats(edit)
            for samples in tables:
                self.assert_one_line(lambda: self.jamio.stats_frame(path, average, samples),
                                     [path, *words])
        for edit, words in ((lambda f: f.attrs.__delitem__("phi_step"),
                             ["has no attribute 'phi_step'"]),
                            (lambda f: f.attrs.__setitem__("phi_step", 0.0),
                             ["attribute 'phi_step' is 0.0"])):
            campaign, path = self.planted("n64_phi0.7000_r-2.50_s001.h5", edit)
            toml = os.path.join(campaign, "campaign.toml")
            with open(toml) as f:
                text = f.read()
            with open(toml, "w") as f:  # the campaign file gives no phi_step: the run's is used
                f.write("".join(line for line in text.splitlines(True)
                                if not line.startswith("phi_step")))
            self.assert_refused(campaign, [path, *words])

    def test_without_pandas_or_xarray_one_line_names_the_package(self):
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
            r = run([sys.executable, "-c", code, self.dir("adaptive"), blocked,
                     os.path.join(ARGS.source, "python"), call], self.work, expect=(1,))
            last = r.stderr.strip().splitlines()[-1]
            self.assertEqual(last.split(": ", 1)[0], "ImportError", r.stderr)
            self.assertIn(f"needs {package}", last)
            self.assertIn(f"python3-{package}", last)
            self.assertNotIn("During handling", r.stderr)  # the one line, no chained traceback
            expected = "dict" if "pandas" in blocked else "DataFrame"
            self.assertEqual(r.stdout.split(), ["8", expected], r.stdout)


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
            print(f"test_jamio_frames: needs {module} (Debian: python3-{module}; "
                  "scripts/setup.sh --tests installs it)")
            return 1
    program = unittest.main(argv=[sys.argv[0], *rest], exit=False, verbosity=2)
    return 0 if program.result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
