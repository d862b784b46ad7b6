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

Usage (ctest runs it): python3 -m pytest tests/test_report_registry.py --jam build/jam --source .
"""

import json
import os
import subprocess
import sys

import pytest

import report_errors_fixture
from report_errors_fixture import small_campaign, synthetic_checks_h5

TIMEOUT = 120  # seconds for one report


@pytest.fixture(autouse=True, scope="module")
def fixture_source(source):
    report_errors_fixture.SOURCE = str(source)


@pytest.fixture
def work(tmp_path):
    """The test's scratch directory, as a string."""
    return str(tmp_path)


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
    script = os.path.join(report_errors_fixture.SOURCE, "reports", "jam_report.py")
    r = subprocess.run([sys.executable, script, directory, "--out", out], capture_output=True,
                       text=True, timeout=TIMEOUT)
    assert r.returncode == 0, f"report exit status {r.returncode}: {r.stderr}"
    return r.stdout, set(os.listdir(out))


@pytest.fixture
def registry(jam):
    """jam's check registry (`jam check --list --json`), a fresh copy for each test."""
    r = subprocess.run([jam, "check", "--list", "--json"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, f"jam check --list --json: exit status {r.returncode}: {r.stderr}"
    return json.loads(r.stdout)


def verdict_rows(summary):
    """The summary's verdict rows: in each check's table, indented, led by the outcome."""
    return [line for line in summary.splitlines()
            if line.startswith("  ") and line.split()[0] in ("pass", "fail", "inconclusive")]


def test_stored(work):
    _, files = report(campaign(work), os.path.join(work, "out"))
    assert "finite_size.png" in files, \
        f"no finite_size.png from a checks.json without a registry: {files}"


def test_jam_registry(registry, work):
    figures = {e["name"]: e["figure"] for e in registry}
    assert figures.get("finite_size") == "finite_size", \
        f"jam's registry: finite_size drawn in {figures.get('finite_size')}"

    def add(checks):
        checks["checks"] = registry
    _, files = report(campaign(work, add), os.path.join(work, "out"))
    assert "finite_size.png" in files, f"no finite_size.png with jam's registry: {files}"


def test_table_only(registry, work):
    for e in registry:
        if e["name"] == "finite_size":
            e["figure"] = "verdicts"

    def add(checks):
        checks["checks"] = registry
    directory = campaign(work, add)
    summary, files = report(directory, os.path.join(work, "out"))
    assert "finite_size.png" not in files, \
        "finite_size.png drawn for a check the registry shows in the table only"
    with open(os.path.join(directory, "checks.json")) as f:
        count = len(json.load(f)["verdicts"])
    assert len(verdict_rows(summary)) == count, \
        f"{len(verdict_rows(summary))} rows in the summary, {count} verdicts"


def test_new_check(registry, work):
    registry.append({"name": "planted_check", "kind": "stats", "part_of": None,
                     "default_margin": 0.1, "margin_unit": "packing_fraction",
                     "margin_reason": "a test", "in_all": True, "figure": "finite_size"})

    def rename(checks):
        checks["checks"] = registry
        for v in checks["verdicts"]:
            if v["check"] == "finite_size":
                v["check"] = "planted_check"
    summary, files = report(campaign(work, rename), os.path.join(work, "out"))
    assert "finite_size.png" in files, \
        f"the registered figure did not draw an unknown check: {files}"
    headline = [line for line in summary.splitlines() if line.startswith("planted check:")]
    assert len(headline) == 1 and "no effect above 0.1 " in headline[0], \
        f"headline of the new check: {headline}"
