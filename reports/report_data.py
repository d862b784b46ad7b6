"""Reads what a campaign directory holds for its report: stats.h5, checks.json, checks.h5,
manifest.toml and campaign.toml (schemas in reference/schema.md).

Nothing here computes physics: it only reads numbers that `jam stats` and `jam check` wrote.
"""

import json
import os
import tomllib
from dataclasses import dataclass, field

import h5py
import numpy as np


class ReportInputError(Exception):
    """A campaign directory that cannot be reported on; the message names the file."""


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


def _read_group(group):
    return {key: np.asarray(group[key][()]) for key in group if isinstance(group[key], h5py.Dataset)}


def _read_stats(path):
    if not os.path.exists(path):
        raise ReportInputError(f"{path}: missing; run `jam stats` on the campaign first")
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise ReportInputError(f"{path}: not a readable HDF5 file ({e})") from e
    with f:
        attrs = _attrs(f)
        for key in ("campaign", "dim", "version"):
            if key not in attrs:
                raise ReportInputError(f"{path}: root attribute '{key}' missing")
        ensembles = []
        for name, g in f.get("ensembles", {}).items():
            a = _attrs(g)
            jamming = _attrs(g["jamming"]) if "jamming" in g else None
            if jamming is not None:
                jamming["packing_fraction_samples"] = np.asarray(
                    g["jamming/packing_fraction_samples"][()])
            ensembles.append(
                Ensemble(name, int(a["n"]), float(a["phi_init"]), float(a["log10_rate"]),
                         float(a["compression_rate"]), int(a["samples"]),
                         _read_group(g["constant_phi"]) if "constant_phi" in g else {},
                         _read_group(g["constant_z"]) if "constant_z" in g else {}, jamming))
        fit = None
        if "fit" in f:
            fit = {"attrs": _attrs(f["fit"])}
            if "representative" in f["fit"]:
                rep = f["fit/representative"]
                fit["representative"] = _attrs(rep)
                fit["coefficients"] = np.asarray(rep["coefficients"][()])
                if "collapse" in rep:
                    fit["collapse"] = _read_group(rep["collapse"])
            if "scan" in f["fit"]:
                fit["scan"] = _read_group(f["fit/scan"])
                fit["scan_failures"] = _attrs(f["fit/scan"]).get("failures", "")
        attrs["paper"] = _attrs(f["paper"]) if "paper" in f else {}
    ensembles.sort(key=lambda e: (e.n, e.phi_init, -e.log10_rate))
    return attrs, ensembles, fit


def _number(x):
    return None if x is None else float(x)


def _read_verdicts(directory):
    json_path = os.path.join(directory, "checks.json")
    h5_path = os.path.join(directory, "checks.h5")
    if not os.path.exists(json_path):
        raise ReportInputError(f"{json_path}: missing; run `jam check all` on the campaign first")
    try:
        with open(json_path) as f:
            entries = json.load(f)
    except json.JSONDecodeError as e:
        raise ReportInputError(f"{json_path}: line {e.lineno}: not valid JSON ({e.msg})") from e
    verdicts = []
    for k, x in enumerate(entries):
        try:
            verdicts.append(
                Verdict(x["check"], x["case"], x["status"], x.get("reason", ""),
                        x.get("statistic_name", ""), _number(x.get("statistic")),
                        _number(x.get("threshold")), _number(x.get("detectable_effect")),
                        _number(x.get("excluded_above")), x.get("values") or {}))
        except KeyError as e:
            raise ReportInputError(f"{json_path}: verdict {k}: field {e} missing") from e
    checks_attrs = {}
    if os.path.exists(h5_path):
        with h5py.File(h5_path, "r") as f:
            checks_attrs = _attrs(f)
            for name, g in f.get("verdicts", {}).items():
                k = int(name.split("_", 1)[0])
                if k >= len(verdicts) or verdicts[k].check != _text(g.attrs["check"]):
                    raise ReportInputError(
                        f"{h5_path}: group {name} does not match checks.json; "
                        "rerun `jam check` (the two files come from different runs)")
                verdicts[k].curves = _read_group(g)
    return verdicts, checks_attrs


def _read_manifest(directory):
    path = os.path.join(directory, "manifest.toml")
    if not os.path.exists(path):
        return {}
    with open(path, "rb") as f:
        try:
            return tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            raise ReportInputError(f"{path}: {e}") from e


def load_campaign(directory):
    """Everything the report draws, read from DIR. Raises ReportInputError naming the file."""
    if not os.path.isdir(directory):
        raise ReportInputError(f"{directory}: not a campaign directory")
    stats_attrs, ensembles, fit = _read_stats(os.path.join(directory, "stats.h5"))
    verdicts, checks_attrs = _read_verdicts(directory)
    manifest = _read_manifest(directory)
    campaign_path = os.path.join(directory, "campaign.toml")
    campaign_text = ""
    if os.path.exists(campaign_path):
        with open(campaign_path) as f:
            campaign_text = f.read()
    run_wall = [float(r.get("wall_seconds", 0.0)) for r in manifest.get("runs", {}).values()
                if r.get("status") == "done"]
    return Campaign(directory, _text(stats_attrs["campaign"]), int(stats_attrs["dim"]),
                    stats_attrs, ensembles, fit, verdicts, checks_attrs, manifest, campaign_text,
                    run_wall)
