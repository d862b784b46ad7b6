#!/usr/bin/python3
"""`jam report` (reports/jam_report.py) on inputs it cannot read and outputs it cannot write:
each case must fail in one line on stderr, `jam report: error: <file>: <cause>`, with exit
status 2, naming the cause, and leave nothing behind: no temporary directory, no directory the
report created on the way, the output path as it was.

The campaign is the stored reduced-scale 2D result (reference/results/reduced-2d) with a
checks.h5 written here, so no `jam` binary is needed. The read-only file system and the full
disk are small tmpfs mounts; where mounting is not allowed the full disk is skipped, and the
read-only case uses a mode-0555 directory instead (which only a user other than root feels).

The cases are in report_errors_outputs.py (where a report is written) and
report_errors_inputs.py (what it reads), their shared fixture in report_errors_fixture.py.

Usage (ctest runs it): python3 -m pytest tests/test_report_errors.py --source .
"""

import os

import pytest

import report_errors_fixture as fixture
from report_errors_fixture import Skip, campaign, report
from report_errors_inputs import INPUT_CASES
from report_errors_outputs import OUTPUT_CASES

CASES = [*OUTPUT_CASES, *INPUT_CASES]


@pytest.fixture(scope="module")
def intact(source, tmp_path_factory):
    """The unmodified campaign copy makes a report, so the failures below are the planted ones.
    The report stays as fixture.INTACT_REPORT (the output cases copy it)."""
    fixture.SOURCE = str(source)
    keep = str(tmp_path_factory.mktemp("intact"))
    out = os.path.join(keep, "reports", "r")
    r = report(campaign(keep), out)
    assert r.returncode == 0 and os.path.isfile(os.path.join(out, "index.html")), \
        f"the intact campaign makes no report (exit {r.returncode}):\n{r.stderr}"
    fixture.INTACT_REPORT = out
    return out


@pytest.mark.parametrize("case", CASES, ids=[c.__name__.removeprefix("case_") for c in CASES])
def test_report_error(intact, tmp_path, case):
    try:
        case(str(tmp_path))
    except Skip as e:
        pytest.skip(str(e))
