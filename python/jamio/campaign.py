"""What a campaign file asks for (its design): the nominal values that name a campaign's runs
and ensembles, read from the campaign directory's `campaign.toml` (the file it was last run
with) or, without it, from `manifest.toml` (which holds the same text).

An external campaign (runs jam did not plan, gathered by `jam campaign import DIR FILES...`,
campaign/external_campaign.hpp) has `external.toml` instead: the model its runs share, the
output grid's phi_step, and one table per imported run with the ensemble's nominal n, phi_init
and log10_rate, its sample and its provenance. Its design is read from there (load_external)."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from .errors import JamioError, open_regular, reading, shown

# A campaign file is a few kilobytes; anything much larger is not one.
MOST_CAMPAIGN_BYTES = 1 << 20
# A manifest lists every run (a few lines each): large campaigns have tens of thousands.
MOST_MANIFEST_BYTES = 256 << 20
# external.toml: about 300 bytes per imported run.
MOST_EXTERNAL_BYTES = 256 << 20
EXTERNAL_FILE = "external.toml"


@dataclass(frozen=True)
class ExternalRun:
    """One `[[run]]` table of external.toml: the run's name (its file is runs/<name>.h5), the
    nominal coordinates of its ensemble (n, phi_init, log10_rate: the first imported run's
    values, which later runs of the ensemble share to within what a run name tells), its
    sample, and where it came from (source, source_checksum: FNV-1a of that file as imported,
    simulator, simulator_version)."""

    name: str
    n: int
    phi_init: float
    log10_rate: float
    sample: int
    source: str
    source_checksum: str
    simulator: str
    simulator_version: str


@dataclass(frozen=True)
class ExternalCampaign:
    """external.toml: `name`, `phi_step` (the grid the statistics average on), the model every
    run shares (`dim`, `diameter_ratio`, `contact`, `dynamics`, `q`: 0 unless inertial),
    `runs` (ExternalRun, in the file's order) and `set_aside` ((file, reason) pairs: the files
    an import refused)."""

    path: str
    name: str
    phi_step: float
    dim: int
    diameter_ratio: float
    contact: str
    dynamics: str
    q: float
    runs: tuple
    set_aside: tuple


@dataclass(frozen=True)
class Design:
    """The campaign file's `sizes`, `phi_init` and `log10_rates` (tuples of its values, as the
    floats Python and jam both parse them to), `chain_phi_init` (log10_rate -> the packing that
    rate's runs continue from, for the chained rates only), `phi_step` and `phi_stop` (None when
    the file leaves them to their defaults: the run files then say), `dim` and `name`.

    Of an external campaign: `sizes`, `phi_init` and `log10_rates` are the distinct nominal
    values of external.toml's runs (sorted), `phi_step` its grid, `phi_stop` None,
    `chain_phi_init` empty, and `external` the ExternalCampaign (None for a planned one)."""

    path: str
    name: str
    dim: int
    sizes: tuple
    phi_init: tuple
    log10_rates: tuple
    chain_phi_init: dict
    phi_step: float | None
    phi_stop: float | None
    external: ExternalCampaign | None = None


def _parse_toml(path, text):
    try:
        import tomllib
    except ImportError:  # Python before 3.11
        try:
            import tomli as tomllib
        except ImportError:
            raise JamioError(path, "reading a campaign file needs Python 3.11 (tomllib) or "
                                   "tomli (Debian: python3-tomli)") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise JamioError(path, f"not valid TOML ({e})") from e


def _read_toml(path, what, most_bytes):
    with open_regular(path, what, most_bytes) as f:
        with reading(path, what):
            text = f.read().decode("utf-8")
    return _parse_toml(path, text)


def _numbers(table, key, path, kind=float, required=True):
    """table[key] as a tuple of `kind` (a list of numbers in the file)."""
    values = table.get(key)
    if values is None and not required:
        return ()
    if not isinstance(values, list) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        raise JamioError(path, f"key '{key}' is {shown(values)}, expected a list of numbers")
    if kind is int and not all(float(v).is_integer() for v in values):
        raise JamioError(path, f"key '{key}' is {shown(values)}, expected whole numbers")
    return tuple(kind(v) for v in values)


def _number(table, key, path):
    value = table.get(key)
    if value is None:
        return None
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        raise JamioError(path, f"key '{key}' is {shown(value)}, expected a number")
    return float(value)


def _design(path, table):
    rates = _numbers(table, "log10_rates", path)
    chain = _numbers(table, "chain_phi_init", path, required=False)
    if chain and len(chain) != len(rates):
        raise JamioError(path, f"chain_phi_init has {len(chain)} values for {len(rates)} rates")
    dim = table.get("dim", 2)
    if not isinstance(dim, int) or isinstance(dim, bool):
        raise JamioError(path, f"key 'dim' is {shown(dim)}, expected a whole number")
    return Design(path=path, name=str(table.get("name", "")), dim=dim,
                  sizes=_numbers(table, "sizes", path, int),
                  phi_init=_numbers(table, "phi_init", path), log10_rates=rates,
                  chain_phi_init={r: p for r, p in zip(rates, chain) if p > 0},
                  phi_step=_number(table, "phi_step", path),
                  phi_stop=_number(table, "phi_stop", path))


def _value(table, key, path, where, kind):
    """table[key] as `kind` ("string", "number" or "whole number"; bool is never a number,
    nor is inf or NaN); a JamioError naming the file, the table (`where`) and the key
    otherwise."""
    v = table.get(key)
    if kind == "string":
        ok = isinstance(v, str)
    else:
        ok = (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
              and (kind == "number" or float(v).is_integer()))
    if not ok:
        got = "missing" if v is None else shown(v)
        raise JamioError(path, f"{where}key '{key}' is {got}, expected a {kind}")
    return v if kind == "string" else float(v) if kind == "number" else int(v)


def _external_run(table, path, k):
    where = f"run[{k}]: "
    if not isinstance(table, dict):
        raise JamioError(path, f"run[{k}] is {shown(table)}, expected a table")
    fields = {"name": "string", "n": "whole number", "phi_init": "number",
              "log10_rate": "number", "sample": "whole number", "source": "string",
              "source_checksum": "string", "simulator": "string",
              "simulator_version": "string"}
    run = ExternalRun(**{key: _value(table, key, path, where, kind)
                         for key, kind in fields.items()})
    # As jam reads it: a name is a file in runs/, never a path out of it.
    if not run.name or any(c in run.name for c in ("/", "\\", "..", "\0")):
        raise JamioError(path, f"{where}name {shown(run.name)} is not a run name")
    return run


def is_external(campaign_dir):
    """True when `campaign_dir` is an external campaign (holds external.toml)."""
    return os.path.exists(os.path.join(os.fspath(campaign_dir), EXTERNAL_FILE))


def load_external(campaign_dir):
    """The ExternalCampaign of `campaign_dir`/external.toml; a JamioError naming the file, the
    run table and the key when a field is missing or of the wrong type, or two runs share a
    name or (n, phi_init, log10_rate, sample)."""
    path = os.path.join(os.fspath(campaign_dir), EXTERNAL_FILE)
    t = _read_toml(path, "external campaign file", MOST_EXTERNAL_BYTES)
    phi_step = _value(t, "phi_step", path, "", "number")
    if not 0 < phi_step <= 0.05:
        raise JamioError(path, f"phi_step {phi_step!r} must be in (0, 0.05]")
    runs = t.get("run", [])
    aside = t.get("set_aside", [])
    for key, v in (("run", runs), ("set_aside", aside)):
        if not isinstance(v, list):
            raise JamioError(path, f"key '{key}' is {shown(v)}, expected an array of tables")
    runs = tuple(_external_run(r, path, k) for k, r in enumerate(runs))
    names, coordinates = set(), {}
    for r in runs:
        if r.name in names:
            raise JamioError(path, f"two runs are named {shown(r.name)}")
        names.add(r.name)
        key = (r.n, r.phi_init, r.log10_rate, r.sample)
        if key in coordinates:
            raise JamioError(path, f"runs {shown(coordinates[key])} and {shown(r.name)} have the "
                                   f"same (n, phi_init, log10_rate, sample) {key}")
        coordinates[key] = r.name
    set_aside = []
    for k, a in enumerate(aside):
        if not isinstance(a, dict):
            raise JamioError(path, f"set_aside[{k}] is {shown(a)}, expected a table")
        where = f"set_aside[{k}]: "
        set_aside.append((_value(a, "file", path, where, "string"),
                          _value(a, "reason", path, where, "string")))
    model = {"name": "string", "dim": "whole number", "diameter_ratio": "number",
             "contact": "string", "dynamics": "string", "q": "number"}
    return ExternalCampaign(path=path, phi_step=phi_step, runs=runs, set_aside=tuple(set_aside),
                            **{key: _value(t, key, path, "", kind) for key, kind in model.items()})


def _external_design(campaign):
    runs = campaign.runs
    return Design(path=campaign.path, name=campaign.name, dim=campaign.dim,
                  sizes=tuple(sorted({r.n for r in runs})),
                  phi_init=tuple(sorted({r.phi_init for r in runs})),
                  log10_rates=tuple(sorted({r.log10_rate for r in runs})),
                  chain_phi_init={}, phi_step=campaign.phi_step, phi_stop=None,
                  external=campaign)


def load_design(campaign_dir):
    """The Design of a campaign directory: its campaign.toml, else the campaign text its
    manifest.toml keeps; of an external campaign, its external.toml (which jam reads first,
    as here). A JamioError naming the directory when it has none of them."""
    campaign_dir = os.fspath(campaign_dir)
    if is_external(campaign_dir):
        return _external_design(load_external(campaign_dir))
    path = os.path.join(campaign_dir, "campaign.toml")
    if os.path.exists(path):
        return _design(path, _read_toml(path, "campaign file", MOST_CAMPAIGN_BYTES))
    manifest = os.path.join(campaign_dir, "manifest.toml")
    if not os.path.exists(manifest):
        raise JamioError(campaign_dir, "has no campaign.toml, manifest.toml or external.toml: "
                                       "the nominal values come from the campaign file",
                         missing=True)
    text = _read_toml(manifest, "manifest", MOST_MANIFEST_BYTES).get("campaign")
    if not isinstance(text, str):
        raise JamioError(manifest, "has no key 'campaign' (the campaign file's text)")
    return _design(manifest, _parse_toml(manifest, text))
