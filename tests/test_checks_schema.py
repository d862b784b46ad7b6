"""checks.json has one schema (reference/schema/checks.toml) and two readers that check it: jam
(checks/verdict_file.cpp, through `jam validate --checks`) and jamio (python/jamio/checks.py,
which reports/report_data.py reads through). The same corpus of valid and invalid files goes
to both; the test fails when they disagree on any file: one accepts what the other refuses, or
they name another verdict or field. Each case also states which it is, so a rule lost from the
schema, or from both readers, fails too.

    /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/test_checks_schema.py \
        --jam build/jam --source .
"""

import copy
import json
import re

import pytest

import jamio
import schema_agreement
from jamio import checks_schema


def base(source):
    """A few verdicts of the stored reduced-2d result (every field jam writes, `table` and
    `values` included), as the object of schema 2."""
    with open(source / "reference/results/reduced-2d/checks.json") as f:
        stored = json.load(f)
    out = {k: v for k, v in stored.items() if k != "verdicts"}
    out["verdicts"] = stored["verdicts"][:4]
    return out


def edit(path_value):
    """A case that sets one key path (a tuple: ("verdicts", 1, "status")) to a value, or
    deletes it when the value is DELETE."""
    keys, value = path_value

    def apply(doc):
        x = doc
        for k in keys[:-1]:
            x = x[k]
        if value is DELETE:
            del x[keys[-1]]
        else:
            x[keys[-1]] = value
        return doc
    return apply


DELETE = object()

# (name, valid, what to do to the base: a function of the parsed base, or raw text)
CASES = [
    ("as_written", True, lambda d: d),
    ("schema_1_bare_array", True, lambda d: d["verdicts"]),
    ("no_verdicts", True, edit((("verdicts",), []))),
    ("only_required_fields", True,
     lambda d: {"schema_version": 2, "verdicts": [{"check": "x", "case": "c", "status": "pass"}]}),
    ("null_numbers", True, edit((("verdicts", 0, "statistic"), None))),
    ("null_value_entry", True, edit((("verdicts", 0, "values", "n_a"), None))),
    ("region_asked", True, edit((("verdicts", 1, "region"), "asked"))),
    ("region_empty", True, edit((("verdicts", 1, "region"), ""))),
    ("options_null", True, edit((("options",), None))),
    ("unknown_field_kept", True, edit((("verdicts", 0, "added_later"), [1, "x"]))),
    ("status_maybe", False, edit((("verdicts", 3, "status"), "maybe"))),
    ("status_missing", False, edit((("verdicts", 2, "status"), DELETE))),
    ("case_missing", False, edit((("verdicts", 1, "case"), DELETE))),
    ("case_a_number", False, edit((("verdicts", 1, "case"), 42))),
    ("check_null", False, edit((("verdicts", 0, "check"), None))),
    ("region_middle", False, edit((("verdicts", 2, "region"), "middle"))),
    ("range_variable_x", False, edit((("verdicts", 2, "range_variable"), "x"))),
    ("statistic_text", False, edit((("verdicts", 3, "statistic"), "abc"))),
    ("margin_a_list", False, edit((("verdicts", 3, "margin"), [1, 2]))),
    ("margin_true", False, edit((("verdicts", 0, "margin"), True))),
    ("expected_failure_yes", False, edit((("verdicts", 3, "expected_failure"), "yes"))),
    ("expected_failure_one", False, edit((("verdicts", 3, "expected_failure"), 1))),
    ("unit_a_number", False, edit((("verdicts", 0, "unit"), 5))),
    ("values_text", False, edit((("verdicts", 3, "values"), "none"))),
    ("values_entry_text", False, edit((("verdicts", 0, "values", "phi_init"), "0.4"))),
    ("values_entry_bool", False, edit((("verdicts", 0, "values", "n_a"), True))),
    ("values_entry_list", False, edit((("verdicts", 0, "values", "log10_rate"), [1]))),
    ("table_text", False, edit((("verdicts", 1, "table"), "row"))),
    ("table_cell_missing", False, edit((("verdicts", 1, "table", "short_reason"), DELETE))),
    ("table_cell_number", False, edit((("verdicts", 1, "table", "estimate"), 1.5))),
    ("schema_version_3", False, edit((("schema_version",), 3))),
    ("schema_version_text", False, edit((("schema_version",), "2"))),
    ("schema_version_real", False, edit((("schema_version",), 2.0))),
    ("schema_version_missing", False, edit((("schema_version",), DELETE))),
    ("campaign_a_number", False, edit((("campaign",), 5))),
    ("options_text", False, edit((("options",), "x"))),
    ("verdicts_an_object", False, edit((("verdicts",), {}))),
    ("a_string", False, lambda d: "checks"),
    ("verdict_a_number", False, edit((("verdicts", 2), 7))),
    ("not_json", False, '{"schema_version": 2, "verdicts": [\n{"check": }\n'),
    ("nan_literal", False, '{"schema_version": 2, "verdicts": [{"check": "x", "case": "c", '
                           '"status": "pass", "statistic": NaN}]}'),
]


def jam_says(jam, path):
    return schema_agreement.jam_says(jam, "checks", path)


def jamio_says(path):
    return schema_agreement.jamio_says(jamio.load_checks, jamio.JamioError, path)


def named(message):
    """The verdict and field a refusal names (None where it names none)."""
    verdict = re.search(r"verdict (\d+)", message)
    field = re.search(r"field '([^']+)'", message)
    return (verdict and verdict.group(1), field and field.group(1))


@pytest.mark.parametrize("name,valid,change", CASES, ids=[c[0] for c in CASES])
def test_jam_and_jamio_agree_on_the_corpus(jam, source, tmp_path, name, valid, change):
    path = tmp_path / f"{name}.json"
    if isinstance(change, str):
        path.write_text(change)
    else:
        path.write_text(json.dumps(change(copy.deepcopy(base(source))), indent=1))
    jam_ok, jam_words = jam_says(jam, path)
    py_ok, py_words = jamio_says(path)
    assert jam_ok == py_ok, f"jam: {jam_words} | jamio: {py_words}"
    assert jam_ok == valid, f"jam: {jam_words} | jamio: {py_words}"
    if not valid:
        assert named(jam_words) == named(py_words), f"jam: {jam_words} | jamio: {py_words}"
        if not name.startswith(("not_json", "nan", "a_string", "verdicts_an", "verdict_a_")):
            assert named(jam_words)[1] is not None, jam_words


def test_every_stored_verdict_file_follows_the_schema(jam, source):
    files = sorted((source / "reference/results").glob("*/*checks*.json"))
    assert files
    for path in files:
        assert jam_says(jam, path)[0], jam_says(jam, path)
        assert jamio_says(path)[0], jamio_says(path)


def test_jam_writes_the_version_the_schema_calls_current(source):
    schema = checks_schema.SCHEMA
    header = (source / "checks/verdict_file.hpp").read_text()
    assert f"kChecksSchemaVersion = {schema['file']['current']};" in header
    assert schema["object"]["schema_version"]["allowed"] == [schema["file"]["current"]]
