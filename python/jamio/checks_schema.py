"""The checks.json schema (reference/schema/checks.toml, here as schema/checks.toml) applied
to a parsed file: the same rules jam applies (checks/verdict_schema.cpp), read from the same
file; tests/test_checks_schema.py feeds both one corpus. Each refusal names the field and its
value: "verdict 3: field 'status' is 'maybe', not one of "pass", "fail", "inconclusive"".
Fields are checked in the order of their names, as jam checks them, so that both name the
same field first."""

from __future__ import annotations

import json
import os

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11: the same parser under its earlier name
    import tomli as tomllib

from .errors import shown

SCHEMA_PATH = os.path.join(os.path.dirname(__file__), "schema", "checks.toml")

with open(SCHEMA_PATH, "rb") as _f:
    SCHEMA = tomllib.load(_f)

_TYPE_WORDS = {"string": "a string", "number": "a number", "integer": "a whole number",
               "boolean": "true or false", "object": "an object", "array": "an array"}

NOT_A_VERDICT_FILE = "neither an array of verdicts nor an object with a 'verdicts' array"


class SchemaError(ValueError):
    """A checks.json that breaks the schema; the message names the field and its value."""


def _of_type(v, kind):
    if kind == "string":
        return isinstance(v, str)
    if kind == "number":
        return isinstance(v, (int, float)) and not isinstance(v, bool)
    if kind == "integer":
        return isinstance(v, int) and not isinstance(v, bool)
    if kind == "boolean":
        return isinstance(v, bool)
    if kind == "object":
        return isinstance(v, dict)
    if kind == "array":
        return isinstance(v, list)
    raise ValueError(f"{SCHEMA_PATH}: unknown type {kind!r}")


def _same(a, b):
    """JSON equality: 2 == 2.0 (the type was checked before), never True == 1."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    return a == b


def _refuse(field, v, words):
    raise SchemaError(f"field '{field}' is {shown(v)}, not {words}")


def check_fields(x, table, prefix=""):
    """Raises SchemaError for the first field of the object x (in the order of the names)
    that breaks its rule in the schema's `table` (object, verdict, table)."""
    for name, rule in sorted(SCHEMA[table].items()):
        field = prefix + name
        if name not in x:
            if rule.get("required", False):
                raise SchemaError(f"field '{field}' missing")
            continue
        v = x[name]
        if v is None and rule.get("null", False):
            continue
        if not _of_type(v, rule["type"]):
            _refuse(field, v, _TYPE_WORDS[rule["type"]])
        allowed = rule.get("allowed")
        if allowed is not None and not any(_same(v, a) for a in allowed):
            _refuse(field, v, "one of " + ", ".join(json.dumps(a) for a in allowed))
        entries = rule.get("entries")
        if entries:
            for key, e in sorted(v.items()):
                if not (e is None and rule.get("entries_null", False)) and not _of_type(e, entries):
                    _refuse(f"{field}.{key}", e, _TYPE_WORDS[entries])
        if rule.get("fields"):
            check_fields(v, rule["fields"], field + ".")


def checked(content):
    """(schema_version, verdicts) of a parsed checks.json that follows the schema; raises
    SchemaError naming the first field that does not."""
    if isinstance(content, list) and 1 in SCHEMA["file"]["versions"]:
        version, verdicts = 1, content
    elif isinstance(content, dict) and isinstance(content.get("verdicts"), list):
        check_fields(content, "object")
        version, verdicts = content["schema_version"], content["verdicts"]
    else:
        raise SchemaError(NOT_A_VERDICT_FILE)
    for k, v in enumerate(verdicts):
        try:
            if not isinstance(v, dict):
                raise SchemaError(f"is {shown(v)}, not an object")
            check_fields(v, "verdict")
        except SchemaError as e:
            raise SchemaError(f"verdict {k}: {e}") from None
    return version, verdicts
