"""The open run format's schema as jamio reads it (reference/schema/open_run.toml, written by
`jam schema open-run`), its values under their former names, and Invalid, the error of a field
the format refuses. open_run.py re-exports every name."""

from __future__ import annotations

import os
from dataclasses import dataclass

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

from .errors import JamioError, cause


@dataclass(frozen=True)
class Schema:
    """The open run format as jam validates it, read from the schema file `jam schema open-run`
    writes (reference/schema/open_run.toml): the contact laws and integrators of jam's own
    registry, the dynamics, the attributes and series with their units, the limits."""

    path: str
    format: str
    format_version: int
    protocol: str
    units: str
    contacts: tuple
    dynamics: tuple
    integrators: dict  # name -> its table (dynamics, adaptive, order, force_evaluations)
    limits: dict  # name -> its table (value or min/max or above/below, why)
    attributes: tuple  # the root attributes an open run states, in the format's order
    optional_attributes: tuple
    series_units: dict  # series -> the unit its `units` attribute must state
    required_series: tuple
    frames_units: dict  # a frames file's datasets -> their units


def load_schema(path=None):
    """The schema at `path` (default: the one jamio ships, schema/open_run.toml)."""
    path = os.fspath(path) if path is not None else os.path.join(
        os.path.dirname(__file__), "schema", "open_run.toml")
    try:
        with open(path, "rb") as f:
            t = tomllib.load(f)
        attributes = t["attribute"]
        dynamics = next(a["allowed"] for a in attributes if a["name"] == "dynamics")
        return Schema(
            path=path, format=t["format"], format_version=t["format_version"],
            protocol=t["protocol"], units=t["units"],
            contacts=tuple(c["name"] for c in t["contact_law"]), dynamics=tuple(dynamics),
            integrators={i["name"]: i for i in t["integrator"]}, limits=t["limits"],
            attributes=tuple(a["name"] for a in attributes if a["required"] != "no"),
            optional_attributes=tuple(a["name"] for a in attributes if a["required"] == "no"),
            series_units={d["name"]: d["units"] for d in t["dataset"]},
            required_series=tuple(d["name"] for d in t["dataset"] if d["required"]),
            frames_units={d["name"]: d["units"] for d in t["frames_dataset"]})
    except (OSError, tomllib.TOMLDecodeError, KeyError, TypeError, StopIteration) as e:
        raise JamioError(path, f"cannot read the open run schema ({cause(e)})") from None


# The schema of jam's own registry and limits, and its values under their former names.
SCHEMA = load_schema()
FORMAT, FORMAT_VERSION = SCHEMA.format, SCHEMA.format_version
PROTOCOL, UNITS = SCHEMA.protocol, SCHEMA.units
CONTACTS, DYNAMICS = SCHEMA.contacts, SCHEMA.dynamics
SERIES_UNITS, REQUIRED_SERIES = SCHEMA.series_units, SCHEMA.required_series
FRAMES_UNITS = SCHEMA.frames_units
LIMITS = SCHEMA.limits
MAX_WHOLE = LIMITS["max_whole"]["value"]  # n and sample: 2^53
MAX_POINTS = LIMITS["max_points"]["value"]
MAX_CONTACTS = LIMITS["max_contacts_per_particle"]["value"]
# The first packing may lie this far (relative) below phi_init: round-off.
PHI_INIT_SLACK = LIMITS["phi_init_slack"]["value"]
# phi(t) = phi_init exp(D rate t) must hold to this, relative.
RATE_TOLERANCE = LIMITS["rate_tolerance"]["value"]
# The order of the root attributes in the format's table (and in a written file's listing).
ATTRIBUTES, OPTIONAL_ATTRIBUTES = SCHEMA.attributes, SCHEMA.optional_attributes


class Invalid(ValueError):
    """One field of a run that the format refuses; its message names the field and the value."""
