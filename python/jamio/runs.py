"""Run files (`jam sim --out run.h5`, and a campaign's `runs/<name>.h5`): one at a time with
load_run, all of a campaign as one table with load_runs.

An external campaign (external.toml, campaign.py) holds open runs of any simulator, or jam's
own run files, imported by `jam campaign import`: its runs are those external.toml lists (a
file in runs/ it does not list is not read), each read through validate_run (open_run.py) and
checked to be still the run imported under its name."""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass

import math

import h5py
import numpy as np

from .campaign import is_external, load_external
from .errors import JamioError, optional_module, reading, shown
from .hdf5 import array, attrs, members, read_hdf5, require, units, value
from .open_run import REQUIRED_SERIES, SERIES_UNITS, validate_run

# The datasets every run file has (one entry per output point) and those only some have.
SERIES = ("packing_fraction", "pressure", "contacts_per_particle", "energy_per_particle", "time")
OPTIONAL_SERIES = ("contacts_per_particle_no_rattlers", "rattler_fraction")
# Root attributes every run file has that the table of load_runs repeats on each row.
PARAMETERS = ("n", "phi_init", "compression_rate", "seed")
# An external campaign's runs: the series of an open run (packing_fraction and pressure in
# every run, the others where a run has them), and the columns of external.toml's per-run
# metadata the tables repeat on each row (strings, without a unit).
OPEN_SERIES = tuple(SERIES_UNITS)
PROVENANCE = ("simulator", "simulator_version")
# How far a run's own phi_init and log10 rate may lie from its ensemble's nominal values in
# external.toml: what `jam campaign import` allows when it puts a run in an ensemble
# (campaign/external_campaign.cpp), and what a run name tells.
IMPORT_PHI_INIT = 1e-6
IMPORT_LOG10_RATE = 1e-9
# The model's numbers must equal external.toml's to this (as jam compares them).
IMPORT_MODEL = 1e-12


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
    require(run.attrs, "/", numbers=("phi_init", "compression_rate", "phi_step", "phi_stop",
                                     "dt"), integers=("n", "seed", "sample", "dim"))
    lengths = {name: len(run.data[name]) for name in SERIES + OPTIONAL_SERIES if name in run.data}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"datasets of different lengths {lengths}")


def _read_run(path, f):
    if "format" in f.attrs:
        # An open run (another simulator's, or an import's copy) has no seed, dt or phi_step:
        # its reader is validate_run, not this one.
        raise ValueError(f"an open run (format {shown(value(f.attrs['format']))}), not a run file "
                         "of jam's own: read it with jamio.validate_run")
    datasets = {k: v for k, v in members(f).items() if isinstance(v, h5py.Dataset)}
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
    set aside or unfinished beside them (`*.h5.rejected`, `*.h5.<pid>-<tid>.partial`,
    `*.h5.checkpoint`, reference/schema.md). Of an external campaign: `runs/<name>.h5` of
    each run external.toml lists, in name order (whether or not the file is still there),
    and no other file."""
    if is_external(campaign_dir):
        runs_dir = os.path.join(os.fspath(campaign_dir), "runs")
        names = sorted(r.name for r in load_external(campaign_dir).runs)
        return [os.path.join(runs_dir, f"{name}.h5") for name in names]
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


def _imported_as(campaign, entry, run):
    """Why `run` (an OpenRun, validate_run of runs/<entry.name>.h5) is not the run external.toml
    lists under that name, or None: the model external.toml states, the entry's n, sample,
    simulator and version, and its phi_init and rate within what the import allows."""
    # A run file of jam's own without one (`jam sim`): the import gave it its id in
    # external.toml (its checksum covers its attributes, so the file itself is not changed).
    sample = entry.sample if run.sample is None else run.sample
    log10_rate = math.log10(run.compression_rate)
    checks = (("dim", run.dim, campaign.dim, run.dim == campaign.dim),
              ("diameter_ratio", run.diameter_ratio, campaign.diameter_ratio,
               abs(run.diameter_ratio - campaign.diameter_ratio) <= IMPORT_MODEL),
              ("contact", run.contact, campaign.contact, run.contact == campaign.contact),
              ("dynamics", run.dynamics, campaign.dynamics, run.dynamics == campaign.dynamics),
              ("q", run.q or 0.0, campaign.q, abs((run.q or 0.0) - campaign.q) <= IMPORT_MODEL),
              ("n", run.n, entry.n, run.n == entry.n),
              ("sample", sample, entry.sample, sample == entry.sample),
              ("phi_init", run.phi_init, entry.phi_init,
               abs(run.phi_init - entry.phi_init) <= IMPORT_PHI_INIT),
              ("log10 rate", log10_rate, entry.log10_rate,
               abs(log10_rate - entry.log10_rate) <= IMPORT_LOG10_RATE),
              ("simulator", run.simulator, entry.simulator, run.simulator == entry.simulator),
              ("simulator_version", run.simulator_version, entry.simulator_version,
               run.simulator_version == entry.simulator_version))
    for name, got, listed, same in checks:
        if not same:
            return (f"{name} {got!r}, where external.toml has {listed!r} for this run (not the "
                    "run imported under this name)")
    return None


def load_external_runs(campaign_dir, skip_unreadable=False):
    """(ExternalCampaign, [(ExternalRun, OpenRun)]): every run external.toml lists, in name
    order, read with validate_run and checked to be the run imported under its name (model,
    n, sample, simulator as listed; phi_init and rate within what the import allows). A run
    whose file is missing, no longer validates or is another run is a JamioError of one line
    naming its file, or with skip_unreadable=True left out with a warning naming it. The
    checksum jam recorded at import is not verified here (`jam campaign status` does)."""
    campaign = load_external(campaign_dir)
    runs_dir = os.path.join(os.fspath(campaign_dir), "runs")
    loaded = []
    for entry in sorted(campaign.runs, key=lambda r: r.name):
        path = os.path.join(runs_dir, f"{entry.name}.h5")
        try:
            run = validate_run(path)
            why = _imported_as(campaign, entry, run)
            if why is not None:
                raise JamioError(path, why)
        except JamioError as e:
            if not skip_unreadable:
                raise
            warnings.warn(f"skipped {e}", stacklevel=3)
            continue
        loaded.append((entry, run))
    return campaign, loaded


def present_series(runs):
    """The open run series of a table: packing_fraction and pressure, then those of the
    optional ones that at least one of `runs` (OpenRuns) has."""
    return REQUIRED_SERIES + tuple(n for n in OPEN_SERIES if n not in REQUIRED_SERIES
                                   and any(n in r.data for r in runs))


def _external_table(loaded):
    """load_runs's table of an external campaign: the files' own values, and each run's
    simulator and version from external.toml."""
    series = present_series([r for _, r in loaded])
    columns = ["run", "n", "phi_init", "compression_rate", "sample", *PROVENANCE, *series]
    parts = []
    for entry, run in loaded:
        m = run.points
        part = {"run": np.full(m, entry.name, dtype=object),
                "n": np.full(m, run.n, dtype=np.int64),
                "phi_init": np.full(m, run.phi_init, dtype=np.float64),
                "compression_rate": np.full(m, run.compression_rate, dtype=np.float64),
                "sample": np.full(m, entry.sample, dtype=np.int64)}
        for name in PROVENANCE:
            part[name] = np.full(m, getattr(entry, name), dtype=object)
        for name in series:
            part[name] = np.asarray(run.data.get(name, np.full(m, np.nan)), dtype=np.float64)
        parts.append(part)
    kinds = {"run": object, "n": np.int64, "sample": np.int64,
             **{name: object for name in PROVENANCE}}
    return {c: (np.concatenate([p[c] for p in parts]) if parts
                else np.empty(0, dtype=kinds.get(c, np.float64))) for c in columns}


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
    where each point was taken. To group by the campaign's values and grid, use runs_frame.

    An external campaign (external.toml): the runs it lists, read as open runs
    (load_external_runs; a file it does not list is not read); columns `run`, `n`,
    `phi_init`, `compression_rate`, `sample` (the files' values), `simulator`,
    `simulator_version` (external.toml's, per run), `packing_fraction`, `pressure`, and
    `contacts_per_particle`, `energy_per_particle`, `time` where a run has them (NaN in the
    others); no `seed` (an open run has none)."""
    if is_external(campaign_dir):
        table = _external_table(load_external_runs(campaign_dir, skip_unreadable)[1])
    else:
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
