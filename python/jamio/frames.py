"""A campaign as tables for pandas and xarray, on its nominal coordinates.

runs_frame / runs_dataset: one row per output point of every run, coordinates n, phi_init,
log10_rate (the campaign file's values), sample and phi (the grid value of the point,
grid.py). Of an external campaign (external.toml): the ensemble's nominal values external.toml
lists for each run, phi the grid value where a point is one (else where it was taken: open runs
need not lie on a grid), and each run's simulator and simulator_version.

stats_frame / stats_dataset: one row per grid point of every ensemble of stats.h5, averages at
constant phi (coordinate phi) or at constant Z (coordinate z), with their errors, or with
samples=True every sample's value. Units: DataFrame.attrs["units"] and each xarray
variable's attrs["units"] (column -> unit), `units_source` says whether they come from the
files or from jamio's table (files written before they stated units).

pandas and xarray are imported here only, when a table is asked for, so that jamio's readers
need nothing beyond numpy and h5py (xarray brings pandas; both are extras of the package).
"""

from __future__ import annotations

import os

import numpy as np

from .campaign import load_design
from .errors import JamioError, optional_module, shown
from .grid import external_grid, positive_attribute, run_coordinates, run_grid, snap
from .runs import (OPTIONAL_SERIES, PROVENANCE, SERIES, _load_each, load_external_runs,
                   present_series, run_files)
from .stats import Stats, load_stats
from .units import column_units

RUN_COORDINATES = ("n", "phi_init", "log10_rate", "sample", "phi")
ENSEMBLE_COORDINATES = ("n", "phi_init", "log10_rate")
# The averages of stats.h5 and the coordinate of their grids.
AVERAGES = {"constant_phi": "phi", "constant_z": "z"}


def _frame(columns, units, source, campaign):
    frame = optional_module("pandas").DataFrame(columns)
    frame.attrs.update(units=units, units_source=source, campaign=campaign)
    return frame


def _dataset(frame, index):
    """frame as an xarray Dataset on the coordinates `index`, its units on each variable."""
    optional_module("xarray")
    units = frame.attrs["units"]
    ds = frame.set_index(list(index)).to_xarray()
    for name in list(ds.variables):
        if name in units:
            ds[name].attrs["units"] = units[name]
    ds.attrs.update(units_source=frame.attrs["units_source"], campaign=frame.attrs["campaign"])
    return ds


def _unique(keys, names, what):
    """A JamioError naming the first two rows with the same coordinates."""
    seen = {}
    for key, name in zip(keys, names):
        if key in seen:
            raise JamioError(name, f"has the coordinates {key} of {seen[key]} ({what})")
        seen[key] = name


def _run_columns(run, design, optional):
    n, phi_init, log10_rate, sample = run_coordinates(run, design)
    phi = run_grid(run, design, phi_init, log10_rate)
    m = len(phi)
    if m == 0:  # no row would carry the run's coordinates
        raise JamioError(run.path, "dataset 'packing_fraction' is empty: a run has at least "
                                   "one output point")
    out = {"run": np.full(m, run.name, dtype=object), "n": np.full(m, n, dtype=np.int64),
           "phi_init": np.full(m, phi_init), "log10_rate": np.full(m, log10_rate),
           "sample": np.full(m, sample, dtype=np.int64), "phi": phi}
    for name in SERIES + optional:
        out[name] = np.asarray(run.data.get(name, np.full(m, np.nan)), dtype=np.float64)
    return out


def _external_run_columns(entry, run, design, series):
    """One open run's rows: external.toml's nominal coordinates and provenance of the run,
    phi (external_grid), the run's series."""
    phi = external_grid(run.path, run["packing_fraction"], design.phi_step, entry.phi_init)
    m = len(phi)
    out = {"run": np.full(m, entry.name, dtype=object), "n": np.full(m, entry.n, dtype=np.int64),
           "phi_init": np.full(m, entry.phi_init), "log10_rate": np.full(m, entry.log10_rate),
           "sample": np.full(m, entry.sample, dtype=np.int64), "phi": phi}
    for name in PROVENANCE:
        out[name] = np.full(m, getattr(entry, name), dtype=object)
    for name in series:
        out[name] = np.asarray(run.data.get(name, np.full(m, np.nan)), dtype=np.float64)
    return out


def _external_runs_frame(campaign_dir, design, as_frame, skip_unreadable):
    _, loaded = load_external_runs(campaign_dir, skip_unreadable)
    series = present_series([r for _, r in loaded])
    parts = [_external_run_columns(entry, run, design, series) for entry, run in loaded]
    _unique([tuple(p[c][0] for c in RUN_COORDINATES[:4]) for p in parts],
            [run.path for _, run in loaded], "one run per n, phi_init, log10_rate and sample")
    names = ("run",) + RUN_COORDINATES + PROVENANCE + series
    kinds = {"run": object, "n": np.int64, "sample": np.int64,
             **{name: object for name in PROVENANCE}}
    columns = {c: (np.concatenate([p[c] for p in parts]) if parts
                   else np.empty(0, dtype=kinds.get(c, np.float64))) for c in names}
    stated = {k: u for _, r in loaded for k, u in r.series_units.items()}
    units, source = column_units([c for c in names if c not in PROVENANCE], stated)
    if not as_frame:
        return columns, units, source
    return _frame(columns, units, source, design.name)


def runs_frame(campaign_dir, as_frame=True, skip_unreadable=False):
    """Every output point of every finished run of a campaign as one row: `run` (its name),
    n, phi_init, log10_rate (the campaign file's values), sample, phi (the point's grid
    value), then the run file's series (packing_fraction where the point was taken, pressure,
    contacts_per_particle, energy_per_particle, time, and those only some runs have). A pandas
    DataFrame (units in .attrs["units"]), or with as_frame=False (columns, units, source). A
    point off the campaign's grid, or a run of values the campaign file lacks, is a JamioError
    naming the run and the value.

    An external campaign (external.toml): the runs it lists (a file in runs/ it does not list
    is not read), each read with validate_run and checked to be the run imported under its
    name (runs.load_external_runs: a run that is not is a JamioError of one line naming it,
    or with skip_unreadable=True a warning); n, phi_init, log10_rate and sample as
    external.toml lists them (its ensembles' nominal values); phi the grid value k * phi_step
    where a point is one to round-off, the nominal phi_init where it is that, else the
    packing_fraction as written (open runs need not lie on a grid); `simulator` and
    `simulator_version` (external.toml's, per run); packing_fraction, pressure and the open
    run series that some run has."""
    design = load_design(campaign_dir)
    if design.external is not None:
        return _external_runs_frame(campaign_dir, design, as_frame, skip_unreadable)
    runs = _load_each(run_files(campaign_dir), skip_unreadable)
    optional = tuple(n for n in OPTIONAL_SERIES if any(n in r.data for r in runs))
    parts = [_run_columns(r, design, optional) for r in runs]
    _unique([tuple(p[c][0] for c in RUN_COORDINATES[:4]) for p in parts],
            [r.path for r in runs], "one run per n, phi_init, log10_rate and sample")
    names = ("run",) + RUN_COORDINATES + SERIES + optional
    columns = {c: (np.concatenate([p[c] for p in parts]) if parts else np.empty(0))
               for c in names}
    stated = {k: u for r in runs for k, u in r.units.items()}
    units, source = column_units(names, stated)
    if not as_frame:
        return columns, units, source
    return _frame(columns, units, source, design.name)


def runs_dataset(campaign_dir, skip_unreadable=False):
    """runs_frame as an xarray Dataset: dimensions n, phi_init, log10_rate, sample, phi (NaN
    where a run has no point at that grid value, e.g. below a chained rate's start)."""
    frame = runs_frame(campaign_dir, skip_unreadable=skip_unreadable)
    return _dataset(frame.drop(columns="run"), RUN_COORDINATES)


def _phi_step(stats):
    """The constant-phi grid's step: stats.h5's `phi_step`, else the campaign file beside it
    (or an external campaign's external.toml), else the grids' smallest spacing rounded to 10
    significant digits (files written before `phi_step`, apart from their campaign)."""
    if "phi_step" in stats.attrs:
        return positive_attribute(stats.path, stats.attrs, "phi_step", "the step of its grid")
    directory = os.path.dirname(os.path.abspath(stats.path))
    if any(os.path.exists(os.path.join(directory, f))
           for f in ("campaign.toml", "manifest.toml", "external.toml")):
        step = load_design(directory).phi_step
        if step:
            return step
    grids = [_values(stats, f"ensembles/{name}/constant_phi", e.constant_phi, "packing_fraction")
             for name, e in stats.ensembles.items()
             if e.constant_phi is not None and "packing_fraction" in e.constant_phi]
    gaps = [np.diff(g) for g in grids if len(g) > 1]
    if not gaps:
        raise JamioError(stats.path, "has no phi_step and no grid of two points to take it from")
    step = float(f"{np.min(np.concatenate(gaps)):.10g}")
    if not step > 0:
        raise JamioError(stats.path, f"has no phi_step, and its grids' smallest spacing {step!r} "
                                     "is not above 0 to take it from")
    return step


def _values(stats, where, group, key, shape=None):
    """group[key], the dataset `where`/key of stats.h5, as float64: numbers of exactly `shape`
    (of one dimension when shape is None); a JamioError naming the dataset otherwise (a table
    built from values of another shape would put them on other rows)."""
    if key not in group:
        raise JamioError(stats.path, f"{where}/{key} missing")
    v = group[key]
    if v.dtype.kind not in "biuf" or (v.ndim != 1 if shape is None else v.shape != shape):
        expected = "one dimension" if shape is None else f"shape {shape}"
        raise JamioError(stats.path, f"{where}/{key} has shape {v.shape} of {v.dtype}, expected "
                                     f"{expected} of numbers")
    return np.asarray(v, dtype=np.float64)


def _sample_ids(stats, where, group):
    """The ensemble's sample ids as int64 (stats.h5 stores them as floats): each a whole number
    of int64's range; a JamioError naming the first that is not (1.5 would become 1)."""
    ids = _values(stats, where, group, "sample_ids")
    bad = np.flatnonzero(~(np.isfinite(ids) & (ids == np.round(ids)) & (np.abs(ids) < 2.0 ** 63)))
    if bad.size:
        k = int(bad[0])
        raise JamioError(stats.path, f"{where}/sample_ids[{k}] = {shown(float(ids[k]))} is not "
                                     "a whole number")
    return ids.astype(np.int64)


def _grid(stats, average, name, group, step):
    """Exact grid values of one ensemble's `average` group (its grid dataset snapped to the
    multiples of `step`)."""
    key = "packing_fraction"
    if average == "constant_z":
        key = next((k for k in ("contacts_per_particle_no_rattlers", "contacts_per_particle")
                    if k in group), "contacts_per_particle")
    if key not in group:
        raise JamioError(stats.path, f"ensembles/{name}/{average} has no grid '{key}'")
    where = f"ensembles/{name}/{average}"
    return snap(_values(stats, where, group, key), step, stats.path, f"{where}/{key}")


def _observables(group):
    return [k[: -len("_mean")] for k in group if k.endswith("_mean")]


def _coordinates(stats, name, e, m, coordinate, grid):
    missing = [c for c in ENSEMBLE_COORDINATES if c not in e.attrs]
    if missing:
        raise JamioError(stats.path, f"ensembles/{name} has no attribute '{missing[0]}'")
    out = {c: np.full(m, e.attrs[c]) for c in ENSEMBLE_COORDINATES}
    out[coordinate] = grid
    return out


def _means(stats, name, e, average, step):
    """One ensemble's rows: a row per grid point, each observable's mean and errors."""
    group = getattr(e, average)
    where = f"ensembles/{name}/{average}"
    grid = _grid(stats, average, name, group, step)
    m = len(grid)
    out = _coordinates(stats, name, e, m, AVERAGES[average], grid)
    out["samples"] = np.full(m, len(_sample_ids(stats, where, group)))
    for obs in _observables(group):
        for suffix in ("_mean", "_error", "_relative_error"):
            out[obs + suffix] = _values(stats, where, group, obs + suffix, (m,))
    return out


def _samples(stats, name, e, average, step):
    """One ensemble's rows: a row per sample and grid point, each observable's value."""
    group = getattr(e, average)
    where = f"ensembles/{name}/{average}"
    grid = _grid(stats, average, name, group, step)
    ids = _sample_ids(stats, where, group)
    m, s = len(grid), len(ids)
    out = {c: np.tile(v, s) for c, v in
           _coordinates(stats, name, e, m, AVERAGES[average], grid).items()}
    out["sample"] = np.repeat(ids, m)
    for obs in _observables(group):
        # (samples, points) exactly: a transposed or flattened table has as many values, and
        # reshaped it would put them on other rows.
        out[obs] = _values(stats, where, group, f"{obs}_samples", (s, m)).reshape(s * m)
    return out


def _stats_table(stats, average, samples):
    if average not in AVERAGES:
        raise ValueError(f"average {average!r}: expected one of {list(AVERAGES)}")
    stats = stats if isinstance(stats, Stats) else load_stats(stats)
    chosen = [(name, e) for name, e in stats.ensembles.items() if getattr(e, average) is not None]
    rows = _samples if samples else _means
    step = 0.0
    if chosen:
        step = _phi_step(stats) if average == "constant_phi" else positive_attribute(
            stats.path, stats.attrs, "z_step", "the step of its grid")
    parts = [rows(stats, name, e, average, step) for name, e in chosen]
    # Without any such average (constant Z of runs that carry no Z: an external campaign's),
    # the coordinates alone, so that the table is empty rather than without columns.
    names = list(dict.fromkeys(k for p in parts for k in p)) or [
        *ENSEMBLE_COORDINATES, AVERAGES[average], "sample" if samples else "samples"]
    columns = {c: np.concatenate([p[c] for p in parts]) if parts else np.empty(0) for c in names}
    for c in ("n", "sample", "samples"):
        if c in columns:
            columns[c] = columns[c].astype(np.int64)
    stated = {}
    for _, e in chosen:
        for k, u in getattr(e, average).units.items():
            stated[k[: -len("_samples")] if samples and k.endswith("_samples") else k] = u
    units, source = column_units(names, stated)
    return stats, columns, units, source


def stats_frame(stats, average="constant_phi", samples=False):
    """The averages of every ensemble of stats.h5 (a Stats, or its path or directory) as one
    row per grid point: n, phi_init, log10_rate (n 0 when sizes were pooled), phi (average
    "constant_phi") or z ("constant_z") as exact grid values, samples, and each observable's
    `_mean`, `_error`, `_relative_error`. samples=True: one row per sample and grid point, a
    column `sample` and each observable's value in that sample."""
    stats, columns, units, source = _stats_table(stats, average, samples)
    return _frame(columns, units, source, stats.attrs.get("campaign", ""))


def stats_dataset(stats, average="constant_phi"):
    """stats_frame as an xarray Dataset: the means and errors on dimensions n, phi_init,
    log10_rate and phi (or z), every sample's values as `<observable>_samples` with the
    dimension sample too (NaN where an ensemble has no such point or sample)."""
    xr = optional_module("xarray")
    stats = stats if isinstance(stats, Stats) else load_stats(stats)
    means = stats_frame(stats, average)
    coordinate = AVERAGES[average]
    per_sample = stats_frame(stats, average, samples=True)
    ds = _dataset(means, ENSEMBLE_COORDINATES + (coordinate,))
    observables = [c for c in per_sample.columns
                   if c not in ENSEMBLE_COORDINATES + ("sample", coordinate)]
    attrs = dict(per_sample.attrs)
    per_sample = per_sample.rename(columns={c: f"{c}_samples" for c in observables})
    per_sample.attrs.update(attrs, units={f"{c}_samples" if c in observables else c: u
                                          for c, u in attrs["units"].items()})
    return xr.merge([ds, _dataset(per_sample, ENSEMBLE_COORDINATES + ("sample", coordinate))],
                    combine_attrs="override")


__all__ = ["runs_dataset", "runs_frame", "stats_dataset", "stats_frame"]
