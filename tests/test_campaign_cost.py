#!/usr/bin/python3
"""scripts/campaign_cost.py on a made-up campaign directory whose costs are known: ten runs of
one ensemble at 1 ms per force evaluation, one of them with a record holding a third of its
CPU seconds (a resume that lost its first attempts) and one at 1.2 ms (a loaded machine, not
short); two cheap runs that must not be judged (one with a jamming-point search, one of a
size whose runs take seconds); three chained starts left again, one run's twice (a start
lost and left again costs twice). The account must find the short record only, estimate it
from its siblings, count every start line, count a log given twice or copied earlier once,
and refuse a directory that is not a campaign's and a log that cannot be read.

Usage (ctest runs it): python3 -m pytest tests/test_campaign_cost.py --source .
"""

import json
import os
import subprocess
import sys

import h5py
import pytest


def write_run(directory, name, cpu, evaluations, minimizations=0):
    with open(directory / "runs" / (name + ".record"), "w") as f:
        f.write(f"cpu_seconds = {cpu}\nstatus = 'done'\nsteps = 10\n")
    with h5py.File(directory / "runs" / (name + ".h5"), "w") as f:
        f.attrs["force_evaluations"] = evaluations
        if minimizations:
            f.attrs["jamming_minimizations"] = minimizations


@pytest.fixture
def campaign(tmp_path):
    """The campaign directory c/ and its log c.log, in tmp_path."""
    directory = tmp_path / "c"
    os.makedirs(directory / "runs")
    for s in range(10):
        cpu = {3: 100 / 3, 7: 120}.get(s, 100)
        write_run(directory, f"n1024_phi0.4000_r-6.00_s{s:03d}", cpu, 100_000)
    # Not judged: a run whose jamming-point search took CPU its evaluations do not count
    # (cheap per evaluation in the other direction: its dynamics short), and a size whose
    # runs take seconds, where fixed costs set the cost per evaluation.
    write_run(directory, "n1024_phi0.6000_r-6.00_s000", 30, 100_000, minimizations=14)
    for s in range(4):
        write_run(directory, f"n256_phi0.4000_r-6.00_s{s:03d}", 10 if s else 2, 10_000)
    # A running run's record is not counted.
    with open(directory / "runs" / "n1024_phi0.4000_r-6.00_s010.record", "w") as f:
        f.write("cpu_seconds = 5\nstatus = 'running'\n")
    log = tmp_path / "c.log"
    with open(log, "w") as f:
        for sample, cpu in ((0, 30), (1, 20), (0, 30)):
            f.write(f"campaign c: n1024_phi0.4000_r-5.00_s{sample:03d} left its start at "
                    f"0.78 again ({cpu} CPU seconds)\n")
    return directory, log


@pytest.fixture
def cost(source):
    def run(*extra):
        script = source / "scripts" / "campaign_cost.py"
        return subprocess.run([sys.executable, script, *extra], capture_output=True, text=True,
                              timeout=60)
    return run


def test_short_record_estimated_every_start_line_counted_each_log_once(campaign, cost, tmp_path):
    directory, log = campaign
    # An earlier copy of the log (a snapshot's: its first line only) adds nothing.
    copy = tmp_path / "copy.log"
    with open(log) as f, open(copy, "w") as g:
        g.write(f.readline())
    r = cost(directory, "--log", log, copy, log, "--json")
    assert r.returncode == 0, r.stderr
    a = json.loads(r.stdout)
    assert [x["run"] for x in a["short_records"]] == ["n1024_phi0.4000_r-6.00_s003"]
    # Its siblings' median is 1 ms per evaluation (eight at 1 ms, one at 1.2 ms).
    assert a["short_records"][0]["estimated_cpu_seconds"] == pytest.approx(100.0, abs=5e-7)
    assert a["cpu_seconds_recorded"] == pytest.approx(8 * 100 + 100 / 3 + 120 + 30 + 32,
                                                      abs=5e-7)
    assert a["cpu_seconds_missing_estimate"] == pytest.approx(100 - 100 / 3, abs=5e-7)
    assert a["cpu_seconds_starts_again"] == 80
    assert len(a["starts_again"]) == 3
    assert a["cpu_seconds_total"] == pytest.approx(10 * 100 + 20 + 80 + 62, abs=5e-7)
    # One row per size, phi_init and rate.
    rows = {(e["n"], e["phi_init"]): e["runs"] for e in a["ensembles"]}
    assert rows == {(256, 0.4): 4, (1024, 0.4): 10, (1024, 0.6): 1}


def test_table_states_the_total(campaign, cost):
    directory, log = campaign
    r = cost(directory, "--log", log)
    assert r.returncode == 0, r.stderr
    assert "short record n1024_phi0.4000_r-6.00_s003" in r.stdout
    assert f"{1162 / 3600:.2f} CPU h in all" in r.stdout


def test_not_a_campaign_refused_in_one_line(cost, tmp_path):
    r = cost(tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.splitlines()) == 1, r.stderr
    assert "no runs/ directory" in r.stderr


@pytest.mark.parametrize("log, says", [
    ("missing.log", "missing.log"),
    # A FIFO: refused, not read (a read would block).
    ("fifo.log", "not a regular file"),
])
def test_unreadable_log_refused_in_one_line(campaign, cost, tmp_path, log, says):
    directory, _ = campaign
    path = tmp_path / log
    if log == "fifo.log":
        os.mkfifo(path)
    r = cost(directory, "--log", path)
    assert r.returncode == 2
    assert len(r.stderr.splitlines()) == 1, r.stderr
    assert says in r.stderr
    if log == "missing.log":
        assert str(path) in r.stderr
