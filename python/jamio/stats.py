"""A campaign's statistics (`<campaign>/stats.h5`, written by `jam stats DIR`)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import NamedTuple

import h5py

from .hdf5 import (Group, array, attrs, group, member, members, optional_group, read_hdf5,
                   require, units)
from .content_checksum import seal_problem
from .stats_schema import check_stats

# The root attributes every stats.h5 has.
REQUIRED = ("campaign", "dim", "version")


class EnsembleKey(NamedTuple):
    """An ensemble's nominal coordinates, as the campaign file gives them (n 0: sizes pooled).
    A tuple: (128, 0.7, -3.0) finds the same ensemble."""

    n: int
    phi_init: float
    log10_rate: float


# Two keys name the same ensemble when they agree to this (relative) round-off: the file's
# values are the campaign file's, and a key may be typed as -3 for -3.0.
_SAME = 1e-12


@dataclass(repr=False)
class Ensemble:
    """`ensembles/<name>/`: one (size, phi_init, rate) average. `attrs`: `n`, `phi_init`,
    `log10_rate`, `compression_rate`, `samples`; `constant_phi`, `constant_z`, `jamming`: Groups
    (dicts of arrays with `.attrs` and `.units`), None where the file has no such group.
    `coverage` (what each run covers: `sample_ids`, `packing_fraction_last`,
    `packing_fraction_step`) and `coverage_constant_phi`, `coverage_constant_z` (the tables over
    the grid any run reaches, NaN beyond a run's end; only when some run reaches past the
    others): the groups `jam check compare` reads, None where absent (reference/schema.md)."""

    name: str
    attrs: dict
    constant_phi: Group | None
    constant_z: Group | None
    jamming: Group | None
    coverage: Group | None = None
    coverage_constant_phi: Group | None = None
    coverage_constant_z: Group | None = None

    @property
    def key(self):
        """(n, phi_init, log10_rate) as the file stores them: the campaign file's values."""
        a = self.attrs
        return EnsembleKey(int(a["n"]), float(a["phi_init"]), float(a["log10_rate"]))

    def __repr__(self):
        """One line: the ensemble's coordinates and sizes, not its arrays."""
        a = self.attrs
        points = [f"{len(g['pressure_mean'])} points at constant {what}"
                  for g, what in ((self.constant_phi, "phi"), (self.constant_z, "Z"))
                  if g is not None and "pressure_mean" in g]
        return (f"Ensemble {self.name}: N {a.get('n') or 'pooled'}, phi_init "
                f"{_number(a.get('phi_init'))}, log10_rate {_number(a.get('log10_rate'))}, "
                f"{a.get('samples')} samples, {', '.join(points) or 'no averages'}")


def _number(v, spec="g"):
    """A number for a repr; anything else (from a damaged file) as its repr."""
    return format(v, spec) if isinstance(v, (int, float)) else repr(v)


def _fitted(a):
    """phi_J, beta, y of a fit's attributes with their errors, or why there is no fit: a line
    of at most about 100 characters."""
    if "phi_j" not in a:
        why = str(a.get("failure", "no failure stated"))
        return f"none ({why if len(why) <= 80 else why[:77] + '...'})"
    return ", ".join(f"{name} {_number(a[key], '.5g')} +- {_number(a.get(key + '_error'), '.2g')}"
                     for name, key in (("phi_J", "phi_j"), ("beta", "beta"), ("y", "y"))
                     if key in a)


@dataclass(repr=False)
class FamilyFit:
    """`fit/families/<name>/`: one (N, phi_init) fitted at the representative's window.
    `attrs`: `n`, `family_phi_init`, and the representative's attributes (`phi_j`, `beta`,
    `y` with `_error` ...) or only `failure`; `coefficients` and `collapse` None on failure;
    `units`: the unit of `coefficients` where the file states one."""

    attrs: dict
    coefficients: object
    collapse: Group | None
    units: dict = field(default_factory=dict)

    def __repr__(self):
        a = self.attrs
        return f"FamilyFit N {a.get('n')}, phi_init {a.get('family_phi_init')}: {_fitted(a)}"


@dataclass(repr=False)
class Fit:
    """`fit/` (at constant phi) or `fit_z/` (at constant Z). `attrs`: of the group itself
    (`phi_init`, `n`, `rates_note`, `failure`); `representative`: the attributes of
    `representative/` (None without a representative fit); `coefficients`: its c_0..c_K;
    `collapse`, `scan`: Groups (`scan.attrs["failures"]` says why rows failed);
    `families`: `families/` (each (N, phi_init) fitted as the representative), name ->
    FamilyFit; `units`: the unit of `coefficients` where the file states one;
    `papers_protocol`: `papers_protocol/` (the paper's protocol fitted whole: its attributes,
    with `how`, or `how` and `failure`), a FamilyFit, None where the file has none."""

    attrs: dict
    representative: dict | None
    coefficients: object
    collapse: Group | None
    scan: Group | None
    families: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    papers_protocol: "FamilyFit | None" = None

    def __repr__(self):
        rows = 0 if self.scan is None else len(next(iter(self.scan.values()), []))
        return (f"Fit: {_fitted(self.representative or self.attrs)}; {rows} scan rows, "
                f"{len(self.families)} families")


@dataclass(repr=False)
class Stats:
    """stats.h5: root `attrs`, `paper` (the paper's published values, attributes of `paper/`),
    `ensembles` (name -> Ensemble, in the file's order), `fit` and `fit_z` (None when absent).
    `ensemble(n, phi_init, log10_rate)` and `by_coordinates` find ensembles by their nominal
    coordinates; `frame()` and `dataset()` give the averages as pandas and xarray tables."""

    path: str
    attrs: dict
    paper: dict
    ensembles: dict
    fit: Fit | None
    fit_z: Fit | None

    def __repr__(self):
        """Two lines: what the file holds, not its arrays."""
        a, fit = self.attrs, ""
        if self.fit is not None:
            fit = f"\n  fit at constant phi: {_fitted(self.fit.representative or self.fit.attrs)}"
        return (f"Stats {self.path}: campaign {a.get('campaign')!r}, {a.get('dim')}D, "
                f"{len(self.ensembles)} ensembles of {a.get('runs')} runs{fit}")

    @property
    def by_coordinates(self):
        """The ensembles keyed by EnsembleKey (n, phi_init, log10_rate), a plain tuple."""
        return {e.key: e for e in self.ensembles.values()}

    def ensemble(self, n, phi_init, log10_rate):
        """The ensemble of these nominal coordinates (n 0: sizes pooled), matched to round-off
        (log10_rate -3 finds -3.0); a KeyError of one line naming those there are."""
        want = (float(n), float(phi_init), float(log10_rate))
        for key, e in self.by_coordinates.items():
            if all(abs(a - b) <= _SAME * max(1.0, abs(b)) for a, b in zip(want, key)):
                return e
        have = ", ".join(str(tuple(k)) for k in self.by_coordinates)
        raise KeyError(f"no ensemble (n, phi_init, log10_rate) = {tuple(want)} in "
                       f"{self.path}; there are {have}"[:1000])

    def frame(self, average="constant_phi", samples=False):
        """jamio.stats_frame of this file: a pandas DataFrame."""
        from .frames import stats_frame
        return stats_frame(self, average, samples)

    def dataset(self, average="constant_phi"):
        """jamio.stats_dataset of this file: an xarray Dataset."""
        from .frames import stats_dataset
        return stats_dataset(self, average)


def _ensemble(name, g):
    # n and samples whole numbers, the coordinates numbers, as Ensemble.key and the tables
    # (frames.py) take them: an n of 64.5 is refused here, not cut to 64 there.
    a = require(attrs(g), g.name, numbers=("phi_init", "log10_rate", "compression_rate"),
                integers=("n", "samples"))
    coverage = member(g, "coverage")
    coverage = coverage if isinstance(coverage, h5py.Group) else None
    return Ensemble(name, a, optional_group(g, "constant_phi"),
                    optional_group(g, "constant_z"), optional_group(g, "jamming"),
                    None if coverage is None else group(coverage),
                    None if coverage is None else optional_group(coverage, "constant_phi"),
                    None if coverage is None else optional_group(coverage, "constant_z"))


def _coefficients(g):
    c = member(g, "coefficients")
    return None if c is None else array(c)


def _fit(f, name):
    g = member(f, name)
    if not isinstance(g, h5py.Group):
        return None
    families = member(g, "families")
    families = {} if not isinstance(families, h5py.Group) else {
        k: FamilyFit(attrs(v), _coefficients(v), optional_group(v, "collapse"),
                     _coefficient_units(v))
        for k, v in members(families).items() if isinstance(v, h5py.Group)}
    papers = member(g, "papers_protocol")
    papers = None if not isinstance(papers, h5py.Group) else FamilyFit(
        attrs(papers), _coefficients(papers), optional_group(papers, "collapse"),
        _coefficient_units(papers))
    rep = member(g, "representative")
    if not isinstance(rep, h5py.Group):
        return Fit(attrs(g), None, None, None, optional_group(g, "scan"), families,
                   papers_protocol=papers)
    coefficients = _coefficients(rep)
    return Fit(attrs(g), attrs(rep), coefficients, optional_group(rep, "collapse"),
               optional_group(g, "scan"), families, _coefficient_units(rep), papers)


def _coefficient_units(g):
    """{"coefficients": unit} when the fit's coefficients state one."""
    c = member(g, "coefficients")
    return units({"coefficients": c}) if isinstance(c, h5py.Dataset) else {}


def _read_stats(path, f):
    # The seal first, then reference/schema/stats.toml: jam's order, so both name one problem.
    problem = seal_problem(f)
    if problem:
        raise ValueError(f"{problem}: changed since `jam stats` wrote it")
    check_stats(f)
    root = attrs(f)
    for key in REQUIRED:
        if key not in root:
            raise ValueError(f"root attribute '{key}' missing")
    require(root, "/", integers=("dim",), strings=("campaign", "version"))
    groups = member(f, "ensembles")
    ensembles = {} if groups is None else {
        name: _ensemble(name, g) for name, g in members(groups).items()
        if isinstance(g, h5py.Group)}
    paper = member(f, "paper")
    paper = attrs(paper) if isinstance(paper, h5py.Group) else {}
    return Stats(path, root, paper, ensembles, _fit(f, "fit"), _fit(f, "fit_z"))


def stats_path(dir_or_file):
    """`<dir>/stats.h5` for a directory, else the path itself."""
    path = os.fspath(dir_or_file)
    if os.path.isdir(path) and not path.endswith(".h5"):
        return os.path.join(path, "stats.h5")
    return path


def load_stats(dir_or_file):
    """stats.h5 of a campaign directory (or the file named) as a Stats. Raises JamioError
    naming the file when it is missing, cannot be read or breaks the schema jam checks it
    against (reference/schema/stats.toml: the field and its value)."""
    path = stats_path(dir_or_file)
    return read_hdf5(path, "stats file", lambda f: _read_stats(path, f))
