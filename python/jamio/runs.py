"""Run files (`jam sim --out run.h5`, and a campaign's `runs/<name>.h5`): one at a time with
load_run, all of a campaign as one table with load_runs."""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass

import h5py
import numpy as np

from .errors import JamioError, optional_module, reading
from .hdf5 import array, attrs, read_hdf5, require, units

# The datasets every run file has (one entry per output point) and those only some have.
SERIES = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle", "time")
OPTIONAL_SERIES = ("contacts_per_particle_no_rattlers", "rattler_fraction")
# Root attributes every run file has that the table of load_runs repeats on each row.
PARAMETERS = ("n", "phi_init", "compression_rate", "seed")


@dataclass(repr=False)
class Run:
    """One run file. `attrs`: every root attribute (str, int, float); `data`: every dataset
    (numpy arrays); `units`: each dataset's unit where the file stores one (schema 2).
    `run["pressure"]` is `run.data["pressure"]`."""

    path: str
    attrs: dict
    data: dict
    units: dict

    @property
    def name(self):
        """The file name without `.h5` (a campaign's run name)."""
        base = os.path.basename(self.path)
        return base[:-3] if base.endswith(".h5") else base

    @property
    def schema_version(self):
        """2 for files with the attribute `schema_version`, 1 for older files."""
        return int(self.attrs.get("schema_version", 1))

    def __repr__(self):
        """One line: what the run is, not its arrays."""
        a, phi = self.attrs, self.data.get("packing_fraction")
        where = "" if phi is None or not len(phi) else f" (phi {phi[0]:.6g} to {phi[-1]:.6g})"
        sample = f", sample {a['sample']}" if "sample" in a else ""
        return (f"Run {self.name}: N {a.get('n')}, phi_init {a.get('phi_init', float('nan')):.6g}, "
                f"rate {a.get('compression_rate', float('nan')):.4g}{sample}, "
                f"{0 if phi is None else len(phi)} points{where}")

    def __getitem__(self, key):
        return self.data[key]

    def __contains__(self, key):
        return key in self.data

    def keys(self):
        return self.data.keys()


def _check(run):
    """The datasets and attributes every run file has, of their types (the table of load_runs
    repeats them as numbers), the series one-dimensional arrays of numbers of equal length."""
    for name in SERIES:
        if name not in run.data:
            raise ValueError(f"dataset '{name}' missing")
    for name in SERIES + OPTIONAL_SERIES:
        data = run.data.get(name)
        if data is not None and (data.ndim != 1 or data.dtype.kind not in "biuf"):
            raise ValueError(f"dataset '{name}' is {data.ndim}-dimensional of {data.dtype}, "
                             "expected one dimension of numbers")
    for name in PARAMETERS:
        if name not in run.attrs:
            raise ValueError(f"attribute '{name}' missing")
    require(run.attrs, "/", numbers=("phi_init", "compression_rate", "sample"),
            integers=("n", "seed"))
    lengths = {name: len(run.data[name]) for name in SERIES + OPTIONAL_SERIES if name in run.data}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"datasets of different lengths {lengths}")


def _read_run(path, f):
    datasets = {k: v for k, v in f.items() if isinstance(v, h5py.Dataset)}
    run = Run(path, attrs(f), {k: array(v) for k, v in datasets.items()}, units(datasets))
    _check(run)
    return run


def load_run(path):
    """The run file at `path` as a Run. Raises JamioError naming the file when it is missing,
    not HDF5, or lacks what every run file has."""
    path = os.fspath(path)
    return read_hdf5(path, "run file", lambda f: _read_run(path, f))


def run_files(campaign_dir):
    """The finished run files of a campaign directory, `runs/*.h5` in name order: not the files
    set aside or unfinished beside them (`*.h5.rejected`, `*.h5.<pid>.partial`,
    `*.h5.checkpoint`, reference/schema.md)."""
    runs_dir = os.path.join(os.fspath(campaign_dir), "runs")
    with reading(runs_dir, "campaign's runs directory"):
        try:
            names = sorted(os.listdir(runs_dir))
        except FileNotFoundError:
            raise JamioError(runs_dir, "missing (not a campaign directory)", missing=True) from None
    names = [n for n in names if n.endswith(".h5")]
    return [os.path.join(runs_dir, n) for n in names if os.path.isfile(os.path.join(runs_dir, n))]


def _rows(run, optional):
    """The table's columns for one run: its parameters repeated on each output point."""
    m = len(run.data["packing_fraction"])
    sample = run.attrs.get("sample")
    out = {"run": np.full(m, run.name, dtype=object),
           "n": np.full(m, run.attrs["n"], dtype=np.int64),
           "phi_init": np.full(m, run.attrs["phi_init"], dtype=np.float64),
           "compression_rate": np.full(m, run.attrs["compression_rate"], dtype=np.float64),
           "seed": np.full(m, run.attrs["seed"], dtype=np.int64),
           "sample": np.full(m, np.nan if sample is None else sample, dtype=np.float64)}
    for name in SERIES + optional:
        out[name] = np.asarray(run.data.get(name, np.full(m, np.nan)), dtype=np.float64)
    return out


def _table(runs):
    optional = tuple(n for n in OPTIONAL_SERIES if any(n in r.data for r in runs))
    parts = [_rows(r, optional) for r in runs]
    columns = ["run", *PARAMETERS, "sample", *SERIES, *optional]
    empty = {"run": object, "n": np.int64, "seed": np.int64}
    return {c: (np.concatenate([p[c] for p in parts]) if parts
                else np.empty(0, dtype=empty.get(c, np.float64))) for c in columns}


def _load_each(files, skip_unreadable):
    runs = []
    for path in files:
        try:
            runs.append(load_run(path))
        except JamioError as e:
            if not skip_unreadable:
                raise
            warnings.warn(f"skipped {e}", stacklevel=3)
    return runs


def load_runs(campaign_dir, as_frame=None, skip_unreadable=False):
    """Every finished run of a campaign directory as one table, one row per output point of
    every run: columns `run` (its name), `n`, `phi_init`, `compression_rate`, `seed`, `sample`
    (NaN in files without it) and the series `packing_fraction`, `pressure`,
    `contacts_per_particle`, `energy_per_particle`, `time` (and
    `contacts_per_particle_no_rattlers`, `rattler_fraction` when a run has them, NaN in the
    others). A pandas DataFrame when pandas can be imported (as_frame=None) or as_frame=True,
    else a dict of numpy arrays (the same columns). An unreadable run file is a JamioError, or
    with skip_unreadable=True a warning naming it.

    The values are the run files' own: `phi_init` is the packing each run's box had at t = 0
    (0.5999999999999998 for the campaign's 0.6; a chained run's start), `packing_fraction`
    where each point was taken. To group by the campaign's values and grid, use runs_frame."""
    table = _table(_load_each(run_files(campaign_dir), skip_unreadable))
    if as_frame is False:
        return table
    if as_frame:
        return optional_module("pandas").DataFrame(table)
    try:
        import pandas
    except ImportError:
        return table
    return pandas.DataFrame(table)
