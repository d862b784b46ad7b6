"""A campaign's verdicts (`checks.json`, written by `jam check`) and the curves behind them
(`checks.h5`). checks.json is an object {schema_version, campaign, code_version, created,
verdicts} since schema 2; schema 1 files are the bare array of verdicts. Both read, and
checked against the one schema jam checks them against (reference/schema/checks.toml)."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field

import h5py

from .checks_schema import SchemaError, checked
from .errors import JamioError, open_regular, reading
from .hdf5 import attrs, group, member, members, read_hdf5


@dataclass
class Checks:
    """`verdicts`: one dict per verdict, as in the JSON (`check`, `case`, `status`, `reason`,
    `statistic`, ... ; None where the JSON has null). `metadata`: the other keys of a schema 2
    file ({} for schema 1). `curves`: checks.h5's groups `verdicts/<index>_<check>` by name
    (Groups: dicts of arrays with `.attrs`), `curves_attrs` its root attributes; both empty and
    `curves_path` None without checks.h5."""

    path: str
    schema_version: int
    metadata: dict
    verdicts: list
    curves_path: str | None = None
    curves_attrs: dict = field(default_factory=dict)
    curves: dict = field(default_factory=dict)

    @property
    def campaign(self):
        return self.metadata.get("campaign")

    @property
    def code_version(self):
        return self.metadata.get("code_version")

    @property
    def created(self):
        return self.metadata.get("created")

    @property
    def registry(self):
        """The registered checks of the jam that wrote the file (`checks`: one dict per check,
        with `name`, `figure`, `margin_unit`, ...), None in files written before it was there."""
        registry = self.metadata.get("checks")
        return registry if isinstance(registry, list) else None

    def curves_of(self, index):
        """The checks.h5 group of verdict `index` (its position in `verdicts`), or None."""
        for name, g in self.curves.items():
            if name.split("_", 1)[0].isdigit() and int(name.split("_", 1)[0]) == index:
                return g
        return None


# The largest checks.json read: a campaign's verdicts take kilobytes to a few megabytes (the
# curves are in checks.h5); a larger file is refused before it is read into memory.
MOST_JSON_BYTES = 256 << 20


def _no_constant(name):
    """NaN and Infinity are not JSON (jam writes null): refused, as jam refuses them."""
    raise ValueError(f"{name} is not JSON")


def _parse(path):
    """The JSON of `path` (a regular file of at most MOST_JSON_BYTES); invalid JSON is a
    JamioError naming the line."""
    with open_regular(path, "verdict file", MOST_JSON_BYTES) as f:
        text = f.read().decode("utf-8")
    try:
        return json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as e:
        raise JamioError(path, f"line {e.lineno}: not valid JSON ({e.msg})") from e
    except ValueError as e:
        raise JamioError(path, f"not valid JSON ({e})") from e


def read_verdicts(path):
    """checks.json (either schema) as a Checks without curves, checked against the schema
    (reference/schema/checks.toml, checks_schema.py): a field of another type or value is a
    JamioError naming the verdict, the field and the value."""
    path = os.fspath(path)
    with reading(path, "verdict file"):
        content = _parse(path)
        try:
            schema, verdicts = checked(content)
        except SchemaError as e:
            raise JamioError(path, str(e)) from None
    metadata = {} if schema == 1 else {k: v for k, v in content.items() if k != "verdicts"}
    return Checks(path, schema, metadata, verdicts)


def _read_curves(f):
    groups = member(f, "verdicts")
    curves = {} if groups is None else {
        name: group(g) for name, g in members(groups).items() if isinstance(g, h5py.Group)}
    return attrs(f), curves


def checks_paths(dir_or_file):
    """(checks.json, checks.h5) of a campaign directory, or of the JSON file named (the HDF5
    file beside it with the same stem: checks-NAME.json -> checks-NAME.h5)."""
    path = os.fspath(dir_or_file)
    if os.path.isdir(path) and not path.endswith(".json"):
        path = os.path.join(path, "checks.json")
    stem = path[:-5] if path.endswith(".json") else path
    return path, stem + ".h5"


def load_checks(dir_or_file):
    """The verdicts of a campaign directory (or of the checks JSON file named) with the curves
    of checks.h5 when it is there. Raises JamioError naming the file that is missing (only
    checks.json must exist) or cannot be read."""
    json_path, h5_path = checks_paths(dir_or_file)
    checks = read_verdicts(json_path)
    if os.path.lexists(h5_path):
        checks.curves_attrs, checks.curves = read_hdf5(h5_path, "checks file", _read_curves)
        checks.curves_path = h5_path
    return checks
