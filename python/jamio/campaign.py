"""What a campaign file asks for (its design): the nominal values that name a campaign's runs
and ensembles, read from the campaign directory's `campaign.toml` (the file it was last run
with) or, without it, from `manifest.toml` (which holds the same text)."""

from __future__ import annotations

import os
from dataclasses import dataclass

from .errors import JamioError, open_regular, reading, shown

# A campaign file is a few kilobytes; anything much larger is not one.
MOST_CAMPAIGN_BYTES = 1 << 20
# A manifest lists every run (a few lines each): large campaigns have tens of thousands.
MOST_MANIFEST_BYTES = 256 << 20


@dataclass(frozen=True)
class Design:
    """The campaign file's `sizes`, `phi_init` and `log10_rates` (tuples of its values, as the
    floats Python and jam both parse them to), `chain_phi_init` (log10_rate -> the packing that
    rate's runs continue from, for the chained rates only), `phi_step` and `phi_stop` (None when
    the file leaves them to their defaults: the run files then say), `dim` and `name`."""

    path: str
    name: str
    dim: int
    sizes: tuple
    phi_init: tuple
    log10_rates: tuple
    chain_phi_init: dict
    phi_step: float | None
    phi_stop: float | None


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


def load_design(campaign_dir):
    """The Design of a campaign directory: its campaign.toml, else the campaign text its
    manifest.toml keeps. A JamioError naming the directory when it has neither."""
    campaign_dir = os.fspath(campaign_dir)
    path = os.path.join(campaign_dir, "campaign.toml")
    if os.path.exists(path):
        return _design(path, _read_toml(path, "campaign file", MOST_CAMPAIGN_BYTES))
    manifest = os.path.join(campaign_dir, "manifest.toml")
    if not os.path.exists(manifest):
        raise JamioError(campaign_dir, "has no campaign.toml or manifest.toml: the nominal "
                                       "values come from the campaign file", missing=True)
    text = _read_toml(manifest, "manifest", MOST_MANIFEST_BYTES).get("campaign")
    if not isinstance(text, str):
        raise JamioError(manifest, "has no key 'campaign' (the campaign file's text)")
    return _design(manifest, _parse_toml(manifest, text))
