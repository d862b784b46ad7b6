"""Reads what a campaign directory holds for its report: stats.h5, checks.json, checks.h5
(through jamio, the project's reader of its files: python/jamio), manifest.toml and
campaign.toml (schemas in reference/schema.md). The verdict files are read in
report_verdicts.py, over what every input shares (report_inputs.py).

Nothing here computes physics: it only reads numbers that `jam stats` and `jam check` wrote,
and checks that what the figures draw is there.
"""

import os
import tomllib
from dataclasses import dataclass

import numpy as np

from report_inputs import (NOT_READY, FieldError, _datasets, _loaded, _number, _numbers,
                           _require, _shown, jamio, reading, require)
from report_verdicts import _read_checks
# Read from here by jam_report.py, report_output.py and the tests: the inputs' error and exit
# status, jamio's words (report_inputs.py) and the verdicts' reader (report_verdicts.py).
from report_inputs import UNREADABLE, ReportInputError, cause, shown, visible  # noqa: F401
from report_verdicts import Verdict, _verdicts  # noqa: F401

# Datasets the figures draw from, in groups that hold any datasets at all (reference/schema.md).
CONSTANT_PHI = ("packing_fraction", "pressure_mean", "pressure_error", "pressure_relative_error")
CONSTANT_Z = ("packing_fraction_mean", "pressure_mean", "pressure_relative_error")
COLLAPSE = ("x", "compression_rate", "in_fit", "scaled_pressure", "scaled_pressure_error")
SCAN = ("rate_max", "phi_min", "phi_max", "phi_j", "phi_j_error", "beta", "beta_error", "y",
        "y_error")
JAMMING = ("mean", "error", "found")
ENSEMBLE = ("n", "phi_init", "log10_rate", "compression_rate", "samples")


@dataclass
class Ensemble:
    """One (size, phi_init, rate) average of stats.h5 `ensembles/<name>/`."""

    name: str
    n: int
    phi_init: float
    log10_rate: float
    compression_rate: float
    samples: int
    constant_phi: dict  # dataset name -> array
    constant_z: dict
    jamming: dict | None  # attributes mean, error, spread, found; None when not sought


@dataclass
class Campaign:
    directory: str
    name: str
    dim: int
    stats_attrs: dict
    ensembles: list
    fit: dict | None  # representative fit attributes, plus 'collapse' and 'scan' dicts
    verdicts: list
    checks_attrs: dict
    manifest: dict
    campaign_text: str
    run_wall_seconds: list
    # checks.json's "question" (the range asked, checks, margins, alpha as judged), or None.
    question: dict | None = None


def _jamming(e, where):
    if e.jamming is None:
        return None
    jamming = dict(e.jamming.attrs)
    _require(JAMMING, jamming, where, "attribute")
    require(jamming, where, numbers=JAMMING + ("spread",))
    _require(["packing_fraction_samples"], e.jamming, where, "dataset")
    _numbers(e.jamming, ["packing_fraction_samples"], where)
    jamming["packing_fraction_samples"] = e.jamming["packing_fraction_samples"]
    return jamming


def _ensemble(e):
    """A jamio Ensemble with what the figures draw checked, as the report's Ensemble."""
    where, a = f"/ensembles/{e.name}", e.attrs
    _require(ENSEMBLE, a, where, "attribute")
    require(a, where, numbers=("phi_init", "log10_rate", "compression_rate"),
            integers=("n", "samples"))
    return Ensemble(e.name, int(a["n"]), float(a["phi_init"]), float(a["log10_rate"]),
                    float(a["compression_rate"]), int(a["samples"]),
                    _datasets(e.constant_phi, CONSTANT_PHI, where + "/constant_phi"),
                    _datasets(e.constant_z, CONSTANT_Z, where + "/constant_z"),
                    _jamming(e, where + "/jamming"))


# Attributes of a fit that are text; every other attribute of fit/representative is a number.
FIT_TEXT = ("quality", "quality_reason", "fixed", "start", "chosen_because", "error_method")


def _typed(attrs, where, text=()):
    """attrs, each a string where its name is in `text` and a number (not bool) otherwise:
    what the page formats as a number must be one, so no file can put markup in its place."""
    for name, value in attrs.items():
        if name in text:
            if not isinstance(value, str):
                raise FieldError(f"{where}: attribute '{name}' is {_shown(value)}, not text")
        elif isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
            raise FieldError(f"{where}: attribute '{name}' is {_shown(value)}, not a number")
    return attrs


def _fit(fit, where="/fit"):
    """A jamio Fit as the dict the figures read: attrs, representative, coefficients,
    collapse, scan, scan_failures (the keys present only where the file has them)."""
    out = {"attrs": require(fit.attrs, where, numbers=("phi_init", "n"),
                            strings=("rates_note", "failure"))}
    if fit.representative is not None:
        out["representative"] = _typed(fit.representative, where + "/representative", FIT_TEXT)
        if fit.coefficients is None:
            raise ValueError(f"dataset {where}/representative/coefficients missing")
        _numbers({"coefficients": fit.coefficients}, ["coefficients"], where + "/representative")
        out["coefficients"] = fit.coefficients
        if fit.collapse is not None:
            out["collapse"] = _datasets(fit.collapse, COLLAPSE, where + "/representative/collapse")
    families = _families(getattr(fit, "families", None) or {}, where + "/families")
    if families:
        out["families"] = families
    if fit.scan is not None:
        out["scan"] = _datasets(fit.scan, SCAN, where + "/scan",
                                ("half_window", "chosen", "quality_ok",
                                 "papers_protocol"))
        out["scan_failures"] = require(fit.scan.attrs, where + "/scan",
                                       strings=("failures",)).get("failures", "")
    return out


def _families(families, where):
    """The per-(N, phi_init) fits that have a collapse: name -> {attrs..., 'collapse': arrays};
    a family whose fit failed (attribute `failure`) is left out."""
    out = {}
    for name, family in sorted(families.items()):
        here = f"{where}/{name}"
        attrs = _typed(dict(family.attrs), here, FIT_TEXT + ("failure",))
        if "failure" in attrs or family.collapse is None:
            continue
        require(attrs, here, numbers=("n", "family_phi_init", "phi_j", "q", "inv_znu"))
        out[name] = dict(attrs, collapse=_datasets(family.collapse, COLLAPSE, here + "/collapse"))
    return out


def _paper(paper):
    _require([name + "_error" for name in ("phi_j", "beta", "y") if name in paper], paper,
             "/paper", "attribute")
    return require(dict(paper), "/paper", numbers=tuple(paper))


# Root attributes of stats.h5 the report shows, by type (jamio checks campaign, dim, version).
STATS_NUMBERS = ("wall_time",)
STATS_INTEGERS = ("runs", "runs_skipped")


def _read_stats(path):
    stats = _loaded(jamio.load_stats, path, "jam stats")
    with reading(path, "stats file"):
        require(stats.attrs, "/", numbers=STATS_NUMBERS, integers=STATS_INTEGERS)
        if stats.attrs["dim"] not in (2, 3):
            raise ValueError(f"attribute 'dim' of '/' is {shown(stats.attrs['dim'])}, not 2 or 3")
        ensembles = [_ensemble(e) for e in stats.ensembles.values()]
        fit = _fit(stats.fit) if stats.fit else None
        attrs = dict(stats.attrs, paper=_paper(stats.paper))
    ensembles.sort(key=lambda e: (e.n, e.phi_init, -e.log10_rate))
    return attrs, ensembles, fit


# The largest manifest.toml read (a campaign of 100,000 runs, the most a campaign file may
# plan, writes about 40 MB) and the most of campaign.toml shown (a campaign file is a page).
MOST_MANIFEST_BYTES = 256 << 20
MOST_CAMPAIGN_BYTES = 1 << 20


def _input(path):
    """Whether the optional input `path` is there (a symbolic link to nothing counts: opening
    it names the problem)."""
    return os.path.lexists(path)


def _manifest_runs(manifest, path):
    """The wall times of the finished runs of a manifest, its fields type-checked."""
    for key in ("campaign_file", "code_version"):
        if key in manifest and not isinstance(manifest[key], str):
            raise ReportInputError(f"{path}: field '{key}' is {_shown(manifest[key])}, "
                                   "not a string")
    runs = manifest.get("runs", {})
    if not isinstance(runs, dict):
        raise ReportInputError(f"{path}: field 'runs' is {_shown(runs)}, not a table")
    wall = []
    for name, r in runs.items():
        if not isinstance(r, dict):
            raise ReportInputError(f"{path}: field 'runs.{visible(name)}' is {_shown(r)}, "
                                   "not a table")
        seconds = _number(r, "wall_seconds", f"runs.{visible(name)}.wall_seconds")
        if r.get("status") == "done":
            wall.append(seconds or 0.0)
    return wall


def _read_manifest(directory):
    path = os.path.join(directory, "manifest.toml")
    if not _input(path):
        return {}, []
    with reading(path, "manifest"):
        with jamio.errors.open_regular(path, "manifest", MOST_MANIFEST_BYTES) as f:
            try:
                manifest = tomllib.load(f)
            except tomllib.TOMLDecodeError as e:
                raise ReportInputError(f"{path}: {cause(e)}") from e
        try:
            run_wall = _manifest_runs(manifest, path)
        except FieldError as e:
            raise ReportInputError(f"{path}: {e}") from e
    return manifest, run_wall


def _read_campaign_text(directory):
    """campaign.toml as shown on the page: at most MOST_CAMPAIGN_BYTES of it, with its length
    said when it is longer (the page shows the text; jam itself refuses a campaign file that
    is not valid)."""
    path = os.path.join(directory, "campaign.toml")
    if not _input(path):
        return ""
    with reading(path, "campaign file"):
        with jamio.errors.open_regular(path, "campaign file") as f:
            data = f.read(MOST_CAMPAIGN_BYTES + 1)
            size = os.fstat(f.fileno()).st_size
        text = data[:MOST_CAMPAIGN_BYTES].decode("utf-8", errors="replace")
        if len(data) > MOST_CAMPAIGN_BYTES:
            text += f"\n... (campaign.toml is {size} bytes; the first {MOST_CAMPAIGN_BYTES} shown)"
        return text


def load_campaign(directory):
    """Everything the report draws, read from DIR. Raises ReportInputError naming the file."""
    if not os.path.isdir(directory):
        raise ReportInputError(f"{directory}: no such campaign directory", NOT_READY)
    stats_attrs, ensembles, fit = _read_stats(os.path.join(directory, "stats.h5"))
    verdicts, checks_attrs, question = _read_checks(os.path.join(directory, "checks.json"))
    manifest, run_wall = _read_manifest(directory)
    return Campaign(directory, str(stats_attrs["campaign"]), int(stats_attrs["dim"]),
                    stats_attrs, ensembles, fit, verdicts, checks_attrs, manifest,
                    _read_campaign_text(directory), run_wall, question)
