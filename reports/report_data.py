"""Reads what a campaign directory holds for its report: stats.h5, checks.json, checks.h5,
manifest.toml and campaign.toml (schemas in reference/schema.md).

Nothing here computes physics: it only reads numbers that `jam stats` and `jam check` wrote.
"""

import contextlib
import json
import os
import tomllib
from dataclasses import dataclass, field

import h5py
import numpy as np


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
CURVES = {"finite_size": ("grid", "delta", "sigma"),
          "lammps": ("grid", "pressure_jam", "pressure_lammps", "delta", "sigma")}
JAMMING = ("mean", "error", "found")
ENSEMBLE = ("n", "phi_init", "log10_rate", "compression_rate", "samples")

# What a malformed input raises while it is read: h5py's OSError, RuntimeError and KeyError
# (garbled internals, missing objects), ValueError and TypeError from values of the wrong kind.
MALFORMED = (OSError, RuntimeError, KeyError, ValueError, TypeError, IndexError, AttributeError)


def cause(e):
    """One line saying why, from a low-level exception: errno's words, else its message."""
    if isinstance(e, OSError) and e.errno is not None:
        words = os.strerror(e.errno)
        text = words[:1].lower() + words[1:]
    elif isinstance(e, KeyError) and e.args and isinstance(e.args[0], str):
        text = e.args[0] if " " in e.args[0] else f"'{e.args[0]}' missing"
    else:
        text = str(e) or type(e).__name__
    return " ".join(text.split())


@contextlib.contextmanager
def reading(path, what):
    """Turns a low-level failure while `path` is read into a ReportInputError naming it."""
    try:
        yield
    except ReportInputError:
        raise
    except MALFORMED as e:
        raise ReportInputError(f"{path}: not a readable {what} ({cause(e)})") from e


def _probe(path):
    """Opens `path` as a plain file first: permission denied, is a directory, in plain words."""
    with open(path, "rb"):
        pass


def _require(names, present, where, kind):
    for name in names:
        if name not in present:
            raise ValueError(f"{kind} {where}/{name} missing")


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def _attrs(obj):
    out = {}
    for key, value in obj.attrs.items():
        if isinstance(value, bytes):
            value = value.decode()
        elif isinstance(value, np.generic):
            value = value.item()
        out[key] = value
    return out


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


def _read_group(group, required=()):
    """The datasets of `group`; when it has any, `required` must be among them, equally long."""
    out = {key: np.asarray(group[key][()]) for key in group
           if isinstance(group[key], h5py.Dataset)}
    if out and required:
        _require(required, out, group.name, "dataset")
        lengths = {name: len(np.atleast_1d(out[name])) for name in required}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"{group.name}: datasets of different lengths {lengths}")
    return out


def _read_ensemble(name, g):
    a = _attrs(g)
    _require(ENSEMBLE, a, g.name, "attribute")
    jamming = None
    if "jamming" in g:
        jamming = _attrs(g["jamming"])
        _require(JAMMING, jamming, g.name + "/jamming", "attribute")
        jamming["packing_fraction_samples"] = np.asarray(
            g["jamming/packing_fraction_samples"][()])
    return Ensemble(name, int(a["n"]), float(a["phi_init"]), float(a["log10_rate"]),
                    float(a["compression_rate"]), int(a["samples"]),
                    _read_group(g["constant_phi"], CONSTANT_PHI) if "constant_phi" in g else {},
                    _read_group(g["constant_z"], CONSTANT_Z) if "constant_z" in g else {},
                    jamming)


def _read_fit(f):
    fit = {"attrs": _attrs(f["fit"])}
    if "representative" in f["fit"]:
        rep = f["fit/representative"]
        fit["representative"] = _attrs(rep)
        fit["coefficients"] = np.asarray(rep["coefficients"][()])
        if "collapse" in rep:
            fit["collapse"] = _read_group(rep["collapse"], COLLAPSE)
    if "scan" in f["fit"]:
        fit["scan"] = _read_group(f["fit/scan"], SCAN)
        fit["scan_failures"] = _attrs(f["fit/scan"]).get("failures", "")
    return fit


def _read_paper(f):
    paper = _attrs(f["paper"]) if "paper" in f else {}
    _require([name + "_error" for name in ("phi_j", "beta", "y") if name in paper], paper,
             "/paper", "attribute")
    return paper


def _read_stats(path):
    if not os.path.exists(path):
        raise ReportInputError(f"{path}: missing; run `jam stats` on the campaign first", NOT_READY)
    with reading(path, "stats file"):
        _probe(path)
        with h5py.File(path, "r") as f:
            attrs = _attrs(f)
            for key in ("campaign", "dim", "version"):
                if key not in attrs:
                    raise ValueError(f"root attribute '{key}' missing")
            int(attrs["dim"])
            ensembles = [_read_ensemble(name, g) for name, g in f.get("ensembles", {}).items()]
            fit = _read_fit(f) if "fit" in f else None
            attrs["paper"] = _read_paper(f)
    ensembles.sort(key=lambda e: (e.n, e.phi_init, -e.log10_rate))
    return attrs, ensembles, fit


def _number(x):
    return None if x is None else float(x)


def _verdict(x):
    return Verdict(x["check"], x["case"], x["status"], x.get("reason", ""),
                   x.get("statistic_name", ""), _number(x.get("statistic")),
                   _number(x.get("threshold")), _number(x.get("detectable_effect")),
                   _number(x.get("excluded_above")), x.get("values") or {},
                   margin=_number(x.get("margin")),
                   samples_needed=_number(x.get("samples_needed")),
                   expected_failure=bool(x.get("expected_failure", False)))


def _read_verdict_list(path):
    if not os.path.exists(path):
        raise ReportInputError(f"{path}: missing; run `jam check all` on the campaign first",
                               NOT_READY)
    with reading(path, "verdict file"):
        try:
            with open(path) as f:
                entries = json.load(f)
        except json.JSONDecodeError as e:
            raise ReportInputError(f"{path}: line {e.lineno}: not valid JSON ({e.msg})") from e
        if isinstance(entries, dict):  # schema 2: the verdicts inside an object
            entries = entries.get("verdicts")
        if not isinstance(entries, list):
            raise ValueError("not a JSON array of verdicts")
        verdicts = []
        for k, x in enumerate(entries):
            try:
                verdicts.append(_verdict(x))
            except KeyError as e:
                raise ReportInputError(f"{path}: verdict {k}: field {e} missing") from e
    return verdicts


def _read_curves(path, verdicts):
    """checks.h5 (optional): its root attributes; the curves go into `verdicts`."""
    if not os.path.exists(path):
        return {}
    with reading(path, "checks file"):
        _probe(path)
        with h5py.File(path, "r") as f:
            checks_attrs = _attrs(f)
            for name, g in f.get("verdicts", {}).items():
                k = int(name.split("_", 1)[0])
                if k >= len(verdicts) or verdicts[k].check != _text(g.attrs["check"]):
                    raise ReportInputError(
                        f"{path}: group {name} does not match checks.json; "
                        "rerun `jam check` (the two files come from different runs)", NOT_READY)
                verdicts[k].curves = _read_group(g, CURVES.get(verdicts[k].check, ()))
    return checks_attrs


def _read_manifest(directory):
    path = os.path.join(directory, "manifest.toml")
    if not os.path.exists(path):
        return {}, []
    with reading(path, "manifest"):
        with open(path, "rb") as f:
            try:
                manifest = tomllib.load(f)
            except tomllib.TOMLDecodeError as e:
                raise ReportInputError(f"{path}: {cause(e)}") from e
        run_wall = [float(r.get("wall_seconds", 0.0))
                    for r in manifest.get("runs", {}).values() if r.get("status") == "done"]
    return manifest, run_wall


def _read_campaign_text(directory):
    path = os.path.join(directory, "campaign.toml")
    if not os.path.exists(path):
        return ""
    with reading(path, "campaign file"):
        with open(path) as f:
            return f.read()


def load_campaign(directory):
    """Everything the report draws, read from DIR. Raises ReportInputError naming the file."""
    if not os.path.isdir(directory):
        raise ReportInputError(f"{directory}: not a campaign directory", NOT_READY)
    stats_attrs, ensembles, fit = _read_stats(os.path.join(directory, "stats.h5"))
    verdicts = _read_verdict_list(os.path.join(directory, "checks.json"))
    checks_attrs = _read_curves(os.path.join(directory, "checks.h5"), verdicts)
    manifest, run_wall = _read_manifest(directory)
    return Campaign(directory, _text(stats_attrs["campaign"]), int(stats_attrs["dim"]),
                    stats_attrs, ensembles, fit, verdicts, checks_attrs, manifest,
                    _read_campaign_text(directory), run_wall)
