"""Reads what a campaign directory holds for its report: stats.h5, checks.json, checks.h5
(through jamio, the project's reader of its files: python/jamio), manifest.toml and
campaign.toml (schemas in reference/schema.md).

Nothing here computes physics: it only reads numbers that `jam stats` and `jam check` wrote,
and checks that what the figures draw is there.
"""

import contextlib
import os
import re
import sys
import tomllib
from dataclasses import dataclass, field

import numpy as np


def _import_jamio():
    """jamio from python/ beside reports/ (the reader of the same source tree), else an
    installed one (reports/ copied elsewhere, JAM_REPORTS_DIR)."""
    beside = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python")
    if os.path.isfile(os.path.join(beside, "jamio", "__init__.py")) and beside not in sys.path:
        sys.path.insert(0, beside)
    try:
        import jamio
    except ImportError as e:
        raise ImportError(f"jamio not found in {beside} nor installed (docs/python.md): "
                          f"{e}") from e
    return jamio


jamio = _import_jamio()
cause = jamio.errors.cause
require = jamio.hdf5.require
shown = jamio.errors.shown
visible = jamio.errors.visible


# Exit status of a campaign that is not ready for a report (a step has not been run yet) and
# of an input that exists but cannot be read (unreadable, corrupt, malformed): both are tool
# errors, exit status 2 as in every jam subcommand.
NOT_READY = 2
UNREADABLE = 2


class ReportInputError(Exception):
    """A campaign directory that cannot be reported on; the message names the file."""

    def __init__(self, message, status=UNREADABLE):
        super().__init__(message)
        self.status = status


# Datasets the figures draw from, in groups that hold any datasets at all (reference/schema.md).
CONSTANT_PHI = ("packing_fraction", "pressure_mean", "pressure_error", "pressure_relative_error")
CONSTANT_Z = ("packing_fraction_mean", "pressure_mean", "pressure_relative_error")
COLLAPSE = ("x", "compression_rate", "in_fit", "scaled_pressure", "scaled_pressure_error")
SCAN = ("rate_max", "phi_min", "phi_max", "phi_j", "phi_j_error", "beta", "beta_error", "y",
        "y_error")
# Curves a figure draws from the verdicts it shows, by figure (the registry's `figure`).
# (sample_pairs: one curve pair_<k> per pair of samples besides the grid, each checked too.)
CURVES = {"finite_size": ("grid", "delta", "sigma"), "compare": ("grid", "delta", "sigma"),
          "lammps": ("grid", "pressure_jam", "pressure_lammps", "delta", "sigma"),
          "sample_pairs": ("grid",)}
JAMMING = ("mean", "error", "found")
ENSEMBLE = ("n", "phi_init", "log10_rate", "compression_rate", "samples")

MALFORMED = jamio.errors.MALFORMED

# Which figure shows which check and what its margin measures come from the registry that
# checks.json carries (`jam check --list`). Files written before it carried one name only
# these checks; this describes them as that jam registered them and is never extended (a new
# check is described by the files that have it).
REGISTRY_BEFORE_CHECKS_JSON_HAD_IT = [
    {"name": "finite_size", "figure": "finite_size", "margin_unit": "relative"},
    {"name": "sample_pairs", "figure": "sample_pairs", "margin_unit": "relative"},
    {"name": "phi_init", "figure": "jamming_points", "margin_unit": "relative"},
    {"name": "jamming_point", "figure": "verdicts", "margin_unit": "packing_fraction"},
    {"name": "lammps", "figure": "lammps", "margin_unit": "relative"},
    {"name": "regression", "figure": "verdicts", "margin_unit": "relative"}]
# A check a registry does not name (none that jam writes): the verdict table shows it.
UNREGISTERED = {"figure": "verdicts", "margin_unit": "relative"}
# What a check's margin can measure (the registry's `margin_unit`).
MARGIN_UNITS = ("relative", "packing_fraction")


@contextlib.contextmanager
def reading(path, what):
    """Turns a failure while `path` is read or checked into a ReportInputError naming it."""
    try:
        yield
    except ReportInputError:
        raise
    except jamio.JamioError as e:
        raise ReportInputError(str(e)) from e
    except MALFORMED as e:
        raise ReportInputError(f"{path}: not a readable {what} ({cause(e)})") from e


def _loaded(load, path, step):
    """load(path); a missing file says which step to run, any other failure names the file."""
    try:
        return load(path)
    except jamio.JamioError as e:
        if e.missing and e.path == path:
            raise ReportInputError(f"{path}: missing; run `{step}` on the campaign first",
                                   NOT_READY) from e
        raise ReportInputError(str(e)) from e


def _require(names, present, where, kind):
    for name in names:
        if name not in present:
            raise ValueError(f"{kind} '{name}' of {shown(where)} missing")


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
class Verdict:
    """One entry of checks.json with its curves from checks.h5 (same index)."""

    check: str
    case: str
    status: str
    reason: str
    statistic_name: str
    statistic: float | None
    threshold: float | None
    detectable: float | None
    excluded_above: float | None
    values: dict
    curves: dict = field(default_factory=dict)
    margin: float | None = None
    samples_needed: float | None = None
    expected_failure: bool = False
    figure: str = "verdicts"  # the figure that shows the check (its registry entry)
    margin_unit: str = "relative"  # what the margin measures: relative or packing_fraction
    unit: str | None = None  # the unit of this verdict's effects (checks.json `unit`), if given
    # Where along the compression it judges: pooled, below, at or above jamming ("": not a
    # stretch of the compression, or an older file).
    region: str = ""
    estimate: float | None = None  # the signed effect measured
    excluded_below: float | None = None  # the effect surely exceeds this
    # The cells of its row in every table, as jam wrote them (checks.json `table`,
    # report_html.TABLE_KEYS); None in files written before jam wrote them.
    table: dict | None = None


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


def _numbers(out, names, where):
    """Each of `names` present in `out` a one-dimensional array of numbers: what a figure draws
    must be one (a string dataset would be drawn as categories, its text in the SVG)."""
    for name in names:
        data = out.get(name)
        if data is not None and (np.ndim(data) != 1 or np.asarray(data).dtype.kind not in "biuf"):
            raise ValueError(f"dataset '{name}' of {shown(where)} is "
                             f"{np.ndim(data)}-dimensional of {np.asarray(data).dtype}, "
                             "expected one dimension of numbers")


def _datasets(group, required, where, optional=()):
    """The arrays of a jamio Group (None: {}); when it has any, `required` must be among them,
    one-dimensional arrays of numbers, equally long (and `optional`, where present, too)."""
    out = dict(group or {})
    if out and required:
        _require(required, out, where, "dataset")
        _numbers(out, tuple(required) + tuple(optional), where)
        lengths = {name: len(out[name]) for name in tuple(required) + tuple(optional)
                   if name in out}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"{where}: datasets of different lengths {lengths}")
    return out


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


def _shown(value):
    """A value in an error message: its repr, shortened, control characters made visible."""
    return shown(value)


class FieldError(ValueError):
    """A checks.json field of the wrong type; the message names the field and the value."""


def _number(x, key, field=None):
    """The number at x[key] (None when absent or null); a string, list or bool is refused."""
    v = x.get(key)
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise FieldError(f"field '{field or key}' is {_shown(v)}, not a number")
    return float(v)


def _string(x, key, default=None):
    """The string at x[key] (`default` when absent and one is given)."""
    v = x[key] if default is None else x.get(key, default)
    if not isinstance(v, str):
        raise FieldError(f"field '{key}' is {_shown(v)}, not a string")
    return v


def _verdict(x):
    """One verdict of checks.json as the figures read it. jamio has checked every field
    against the schema (reference/schema/checks.toml, jamio.checks_schema): each is of its
    type and `status` one of pass, fail, inconclusive."""
    number = (lambda key: None if x.get(key) is None else float(x[key]))
    return Verdict(x["check"], x["case"], x["status"], x.get("reason", ""),
                   x.get("statistic_name", ""), number("statistic"), number("threshold"),
                   number("detectable_effect"), number("excluded_above"), x.get("values") or {},
                   margin=number("margin"), samples_needed=number("samples_needed"),
                   expected_failure=x.get("expected_failure", False),
                   unit=x.get("unit"),  # older files: none
                   region=x.get("region", ""), estimate=number("estimate"),
                   excluded_below=number("excluded_below"),
                   # The cells of its row in every table (checks/verdict_table.cpp, table_row):
                   # the schema's [table]; None in files written before jam wrote them.
                   table=dict(x["table"]) if "table" in x else None)


def _registry(checks):
    """check name -> its registry entry: checks.json's own registry, else the older files'."""
    with reading(checks.path, "verdict file"):
        entries = checks.registry
        if entries is None:
            entries = REGISTRY_BEFORE_CHECKS_JSON_HAD_IT
        out = {}
        for k, e in enumerate(entries):
            try:
                name, figure, unit = e["name"], e["figure"], e["margin_unit"]
            except (KeyError, TypeError) as x:
                raise ReportInputError(
                    f"{checks.path}: checks {k}: not a registry entry ({cause(x)})") from x
            for key, v in (("name", name), ("figure", figure)):
                if not isinstance(v, str):
                    raise ReportInputError(
                        f"{checks.path}: checks {k}: field '{key}' is {_shown(v)}, "
                        "not a string")
            if unit not in MARGIN_UNITS:
                raise ReportInputError(
                    f"{checks.path}: checks {k}: field 'margin_unit' is {_shown(unit)}, not "
                    f"{' or '.join(MARGIN_UNITS)}")
            out[name] = {"figure": figure, "margin_unit": unit}
    return out


# The most verdicts a report shows: a campaign's checks give hundreds; each verdict is a row of
# the page and the summary, so a file of millions would make a page of gigabytes.
MOST_VERDICTS = 20_000


def _verdicts(checks):
    registry = _registry(checks)
    verdicts = []
    if len(checks.verdicts) > MOST_VERDICTS:
        raise ReportInputError(f"{checks.path}: {len(checks.verdicts)} verdicts, more than a "
                               f"report shows ({MOST_VERDICTS})")
    with reading(checks.path, "verdict file"):
        for x in checks.verdicts:
            v = _verdict(x)
            entry = registry.get(v.check, UNREGISTERED)
            v.figure, v.margin_unit = entry["figure"], entry["margin_unit"]
            verdicts.append(v)
    return verdicts


def _attach_curves(checks, verdicts):
    """checks.h5's curves (when present) onto their verdicts; its root attributes."""
    path = checks.curves_path
    with reading(path, "checks file"):
        require(checks.curves_attrs, "/", numbers=("wall_time",), strings=("version",))
        seen = set()
        for name, g in checks.curves.items():
            # jam names a verdict's group <index>_<check>, the index zero-padded.
            head = name.split("_", 1)[0]
            if not re.fullmatch(r"[0-9]+", head) or int(head) in seen:
                raise ReportInputError(f"{path}: group /verdicts/{name}: not named "
                                       "<index>_<check> with an index of its own")
            k = int(head)
            seen.add(k)
            require(g.attrs, f"/verdicts/{name}", strings=("check",))
            if k >= len(verdicts) or verdicts[k].check != g.attrs["check"]:
                raise ReportInputError(
                    f"{path}: group {name} does not match checks.json; "
                    "rerun `jam check` (the two files come from different runs)", NOT_READY)
            figure = verdicts[k].figure
            pairs = tuple(c for c in (g or {}) if c.startswith("pair_")) \
                if figure == "sample_pairs" else ()
            verdicts[k].curves = _datasets(g, CURVES.get(figure, ()), f"/verdicts/{name}", pairs)
    return checks.curves_attrs


def _read_checks(path):
    """The verdicts of checks.json with the curves of checks.h5; checks.h5's attributes."""
    checks = _loaded(jamio.load_checks, path, "jam check all")
    verdicts = _verdicts(checks)
    question = checks.metadata.get("question")
    return verdicts, _attach_curves(checks, verdicts), (
        question if isinstance(question, dict) else None)


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
