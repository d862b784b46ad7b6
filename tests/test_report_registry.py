#!/usr/bin/python3
"""The report takes which figure shows which check, and what a check's margin measures, from
the check registry that checks.json carries (`jam check --list --json`), not from a list of its
own; checks.json files written before they carried it are still drawn as before.

On the stored reduced-scale 2D result (reference/results/reduced-2d, cut to a few ensembles and
verdicts) with a checks.h5 written here, drawn by reports/jam_report.py:
  - as stored (no registry): the finite-size figure is drawn;
  - with jam's registry: the same;
  - with a registry that sends finite_size to the verdict table only: no finite-size figure,
    every verdict still in the table;
  - with the finite-size verdicts renamed to a check the report has never heard of, registered
    with the finite-size figure and a packing-fraction margin: that figure draws them and the
    headline gives their margin as a packing fraction, not a percentage.

Usage (ctest runs it): test_report_registry.py --jam build/jam --source .
Prints one line per case and a last line `N passed, M failed`; exit status 1 if any failed.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import report_errors_fixture
from report_errors_fixture import small_campaign, synthetic_checks_h5

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
JAM = "jam"
TIMEOUT = 120  # seconds for one report


def campaign(work, edit=None):
    """The stored campaign, cut (report_errors_fixture.small_campaign), in work/campaign;
    edit(checks.json object) changes its verdict file first. Returns the directory."""
    out = os.path.join(work, "campaign")
    checks = small_campaign(out)
    path = os.path.join(out, "checks.json")
    if edit:
        edit(checks)
        with open(path, "w") as f:
            json.dump(checks, f, indent=2)
    curves = {v["check"] for v in checks["verdicts"]
              if v["check"] not in ("sample_pairs", "phi_init", "jamming_point", "lammps",
                                    "regression")}
    synthetic_checks_h5(os.path.join(out, "checks.h5"), checks["verdicts"], curves, 200)
    return out


def report(directory, out):
    """The report of directory in out; (summary text, files written)."""
    script = os.path.join(SOURCE, "reports", "jam_report.py")
    r = subprocess.run([sys.executable, script, directory, "--out", out], capture_output=True,
                       text=True, timeout=TIMEOUT)
    if r.returncode != 0:
        raise AssertionError(f"report exit status {r.returncode}: {r.stderr}")
    return r.stdout, set(os.listdir(out))


def jam_registry():
    r = subprocess.run([JAM, "check", "--list", "--json"], capture_output=True, text=True,
                       timeout=60)
    if r.returncode != 0:
        raise AssertionError(f"jam check --list --json: exit status {r.returncode}: {r.stderr}")
    return json.loads(r.stdout)


def verdict_rows(summary):
    """The summary's verdict rows: in each check's table, indented, led by the outcome."""
    return [line for line in summary.splitlines()
            if line.startswith("  ") and line.split()[0] in ("pass", "fail", "inconclusive")]


def case_stored(work):
    summary, files = report(campaign(work), os.path.join(work, "out"))
    if "finite_size.png" not in files:
        raise AssertionError(f"no finite_size.png from a checks.json without a registry: {files}")
    return summary


def case_jam_registry(work):
    registry = jam_registry()
    figures = {e["name"]: e["figure"] for e in registry}
    if figures.get("finite_size") != "finite_size":
        raise AssertionError(f"jam's registry: finite_size drawn in {figures.get('finite_size')}")

    def add(checks):
        checks["checks"] = registry
    _, files = report(campaign(work, add), os.path.join(work, "out"))
    if "finite_size.png" not in files:
        raise AssertionError(f"no finite_size.png with jam's registry: {files}")


def case_table_only(work):
    registry = jam_registry()
    for e in registry:
        if e["name"] == "finite_size":
            e["figure"] = "verdicts"

    def add(checks):
        checks["checks"] = registry
    directory = campaign(work, add)
    summary, files = report(directory, os.path.join(work, "out"))
    if "finite_size.png" in files:
        raise AssertionError("finite_size.png drawn for a check the registry shows in the "
                             "table only")
    with open(os.path.join(directory, "checks.json")) as f:
        count = len(json.load(f)["verdicts"])
    if len(verdict_rows(summary)) != count:
        raise AssertionError(f"{len(verdict_rows(summary))} rows in the summary, {count} "
                             "verdicts")


def case_new_check(work):
    registry = jam_registry()
    registry.append({"name": "planted_check", "kind": "stats", "part_of": None,
                     "default_margin": 0.1, "margin_unit": "packing_fraction",
                     "margin_reason": "a test", "in_all": True, "figure": "finite_size"})

    def rename(checks):
        checks["checks"] = registry
        for v in checks["verdicts"]:
            if v["check"] == "finite_size":
                v["check"] = "planted_check"
    summary, files = report(campaign(work, rename), os.path.join(work, "out"))
    if "finite_size.png" not in files:
        raise AssertionError(f"the registered figure did not draw an unknown check: {files}")
    headline = [line for line in summary.splitlines() if line.startswith("planted check:")]
    if len(headline) != 1 or "no effect above 0.1 " not in headline[0]:
        raise AssertionError(f"headline of the new check: {headline}")


CASES = [case_stored, case_jam_registry, case_table_only, case_new_check]


def run_case(case):
    name = case.__name__[len("case_"):]
    work = tempfile.mkdtemp(prefix="jam-report-registry-")
    try:
        case(work)
        print(f"passed  {name}")
        return True
    except (AssertionError, subprocess.TimeoutExpired) as e:
        print(f"FAILED  {name}: {e}")
        return False
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main():
    global SOURCE, JAM
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jam", default=JAM, help="the jam executable")
    parser.add_argument("--source", default=SOURCE, help="the source tree (holds reports/)")
    a = parser.parse_args()
    SOURCE, JAM = os.path.abspath(a.source), os.path.abspath(a.jam)
    report_errors_fixture.SOURCE = SOURCE
    results = [run_case(case) for case in CASES]
    print(f"{results.count(True)} passed, {results.count(False)} failed")
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
