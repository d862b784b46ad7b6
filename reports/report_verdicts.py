"""The verdicts of checks.json with the curves of checks.h5, as the report's figures and tables
read them (through jamio, which checks checks.json against reference/schema/checks.toml): each
verdict with the figure its check's registry entry names and what its margin measures.
"""

import re
from dataclasses import dataclass, field

from report_inputs import (NOT_READY, ReportInputError, _datasets, _loaded, _shown, cause, jamio,
                           reading, require)

# Curves a figure draws from the verdicts it shows, by figure (the registry's `figure`).
# (sample_pairs: one curve pair_<k> per pair of samples besides the grid, each checked too.)
CURVES = {"finite_size": ("grid", "delta", "sigma"), "compare": ("grid", "delta", "sigma"),
          "lammps": ("grid", "pressure_jam", "pressure_lammps", "delta", "sigma"),
          "sample_pairs": ("grid",)}

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
