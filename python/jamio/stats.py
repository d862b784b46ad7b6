"""A campaign's statistics (`<campaign>/stats.h5`, written by `jam stats DIR`)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import h5py

from .hdf5 import Group, array, attrs, optional_group, read_hdf5, require

# The root attributes every stats.h5 has.
REQUIRED = ("campaign", "dim", "version")


@dataclass
class Ensemble:
    """`ensembles/<name>/`: one (size, phi_init, rate) average. `attrs`: `n`, `phi_init`,
    `log10_rate`, `compression_rate`, `samples`; `constant_phi`, `constant_z`, `jamming`: Groups
    (dicts of arrays with `.attrs`), None where the file has no such group."""

    name: str
    attrs: dict
    constant_phi: Group | None
    constant_z: Group | None
    jamming: Group | None


@dataclass
class FamilyFit:
    """`fit/families/<name>/`: one (N, phi_init) fitted at the representative's window.
    `attrs`: `n`, `family_phi_init`, and the representative's attributes (`phi_j`, `beta`,
    `y` with `_error` ...) or only `failure`; `coefficients` and `collapse` None on failure."""

    attrs: dict
    coefficients: object
    collapse: Group | None


@dataclass
class Fit:
    """`fit/` (at constant phi) or `fit_z/` (at constant Z). `attrs`: of the group itself
    (`phi_init`, `n`, `rates_note`, `failure`); `representative`: the attributes of
    `representative/` (None without a representative fit); `coefficients`: its c_0..c_K;
    `collapse`, `scan`: Groups (`scan.attrs["failures"]` says why rows failed);
    `families`: `families/` (each (N, phi_init) fitted as the representative), name ->
    FamilyFit."""

    attrs: dict
    representative: dict | None
    coefficients: object
    collapse: Group | None
    scan: Group | None
    families: dict = field(default_factory=dict)


@dataclass
class Stats:
    """stats.h5: root `attrs`, `paper` (the paper's published values, attributes of `paper/`),
    `ensembles` (name -> Ensemble, in the file's order), `fit` and `fit_z` (None when absent)."""

    path: str
    attrs: dict
    paper: dict
    ensembles: dict
    fit: Fit | None
    fit_z: Fit | None


def _ensemble(name, g):
    return Ensemble(name, attrs(g), optional_group(g, "constant_phi"),
                    optional_group(g, "constant_z"), optional_group(g, "jamming"))


def _fit(f, name):
    if not isinstance(f.get(name), h5py.Group):
        return None
    g = f[name]
    families = g.get("families")
    families = {} if not isinstance(families, h5py.Group) else {
        k: FamilyFit(attrs(v), array(v["coefficients"]) if "coefficients" in v else None,
                     optional_group(v, "collapse"))
        for k, v in families.items() if isinstance(v, h5py.Group)}
    rep = g.get("representative")
    if not isinstance(rep, h5py.Group):
        return Fit(attrs(g), None, None, None, optional_group(g, "scan"), families)
    coefficients = array(rep["coefficients"]) if "coefficients" in rep else None
    return Fit(attrs(g), attrs(rep), coefficients, optional_group(rep, "collapse"),
               optional_group(g, "scan"), families)


def _read_stats(path, f):
    root = attrs(f)
    for key in REQUIRED:
        if key not in root:
            raise ValueError(f"root attribute '{key}' missing")
    require(root, "/", integers=("dim",), strings=("campaign", "version"))
    groups = f.get("ensembles")
    ensembles = {} if groups is None else {
        name: _ensemble(name, g) for name, g in groups.items() if isinstance(g, h5py.Group)}
    paper = attrs(f["paper"]) if isinstance(f.get("paper"), h5py.Group) else {}
    return Stats(path, root, paper, ensembles, _fit(f, "fit"), _fit(f, "fit_z"))


def stats_path(dir_or_file):
    """`<dir>/stats.h5` for a directory, else the path itself."""
    path = os.fspath(dir_or_file)
    if os.path.isdir(path) and not path.endswith(".h5"):
        return os.path.join(path, "stats.h5")
    return path


def load_stats(dir_or_file):
    """stats.h5 of a campaign directory (or the file named) as a Stats. Raises JamioError
    naming the file when it is missing or cannot be read."""
    path = stats_path(dir_or_file)
    return read_hdf5(path, "stats file", lambda f: _read_stats(path, f))
