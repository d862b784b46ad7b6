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

Usage (ctest runs it): test_report_errors.py --source .
Prints one line per case and a last line `N passed, M failed`; exit status 1 if any failed.
"""

import argparse
import os
import shutil
import sys
import tempfile

import report_errors_fixture as fixture
from report_errors_fixture import Skip, campaign, report
from report_errors_inputs import INPUT_CASES
from report_errors_outputs import OUTPUT_CASES

CASES = [*OUTPUT_CASES, *INPUT_CASES]


def check_fixture(keep):
    """The unmodified campaign copy makes a report, so the failures below are the planted ones;
    None, or why not. The report stays in keep as fixture.INTACT_REPORT."""
    try:
        out = os.path.join(keep, "reports", "r")
        r = report(campaign(keep), out)
        if r.returncode != 0 or not os.path.isfile(os.path.join(out, "index.html")):
            return f"the intact campaign makes no report (exit {r.returncode}):\n{r.stderr}"
        fixture.INTACT_REPORT = out
        return None
    except AssertionError as e:
        return str(e)


def run_case(case):
    """Runs one case in its own scratch directory: 'passed', 'failed' or 'skipped'."""
    name = case.__name__.removeprefix("case_")
    work = tempfile.mkdtemp(prefix="jam-report-errors-")
    try:
        case(work)
        print(f"passed  {name}")
        return "passed"
    except Skip as e:
        print(f"skipped {name}: {e}")
        return "skipped"
    except AssertionError as e:
        print(f"FAILED  {name}: {e}")
        return "failed"
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", default=fixture.SOURCE,
                        help="the source tree (holds reports/)")
    fixture.SOURCE = os.path.abspath(parser.parse_args().source)
    keep = tempfile.mkdtemp(prefix="jam-report-errors-")
    try:
        broken = check_fixture(keep)
        if broken:
            print(f"FAILED  fixture: {broken}")
            print("0 passed, 1 failed")
            return 1
        results = [run_case(case) for case in CASES]
    finally:
        shutil.rmtree(keep, ignore_errors=True)
    passed, failed = results.count("passed"), results.count("failed")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
