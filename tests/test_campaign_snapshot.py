#!/usr/bin/python3
"""scripts/campaign_snapshot.py: a campaign stopped mid-run (SIGTERM: a checkpoint) is saved,
its directory lost, restored from the snapshot and finished; its run files are then those of
the same campaign run without a stop, value for value. Also: save keeps what DEST holds and
replaces its partial products whole; restore overwrites nothing, refuses while the campaign's
lock is held, and refuses a DEST that is not a snapshot. Neither deletes nor replaces a file it
did not write (save refuses a DEST that holds other files and is no snapshot, and a partial/
with anything but checkpoints and starts), and neither hangs on a FIFO. A run resumed from its
checkpoint records the CPU seconds of its attempts before the stop too.

Usage (ctest runs it): python3 -m pytest tests/test_campaign_snapshot.py --jam build/jam --source .
"""

import fcntl
import os
import shutil
import signal
import subprocess
import sys
import time
import tomllib

import h5py
import numpy as np
import pytest

# Two rates of one sample, the slower chained from the faster at 0.80: 1e-4 takes a fraction of
# a second, 1e-6 a few seconds, long enough to be stopped in the middle.
CAMPAIGN = """name = "snap"
dim = 2
sizes = [1024]
phi_init = [0.70]
log10_rates = [-4.0, -6.0]
chain_phi_init = [0, 0.80]
samples = 1
phi_stop = 0.86
phi_step = 0.002
relax_energy = "1e-14"
seed = 3
output = "{output}"
"""


def process_cpu_seconds(pid):
    """User and system CPU seconds of a running process, all its threads (/proc/PID/stat);
    0 once it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except FileNotFoundError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def record_cpu_seconds(run_dir, name):
    with open(os.path.join(run_dir, "runs", name + ".record"), "rb") as f:
        return float(tomllib.load(f)["cpu_seconds"])


def slurp(path):
    with open(path) as f:
        return f.read()


SLOW = "n1024_phi0.7000_r-6.00_s000"
FAST = "n1024_phi0.7000_r-4.00_s000"


@pytest.fixture
def work(tmp_path):
    """The test's scratch directory, as a string."""
    return str(tmp_path)


@pytest.fixture
def campaign(work):
    """campaign(name): writes NAME.toml, whose output is the directory NAME, both in work."""
    def write(name):
        path = os.path.join(work, name + ".toml")
        with open(path, "w") as f:
            f.write(CAMPAIGN.format(output=os.path.join(work, name)))
        return path
    return write


@pytest.fixture
def run_jam(jam):
    return lambda *args: subprocess.run([jam, *args], capture_output=True, text=True)


@pytest.fixture
def script(source):
    return source / "scripts" / "campaign_snapshot.py"


@pytest.fixture
def snapshot(script):
    """snapshot(*args): runs scripts/campaign_snapshot.py."""
    return lambda *args: subprocess.run([sys.executable, script, *args], capture_output=True,
                                        text=True)


def values(run_dir):
    out = {}
    for name in (FAST, SLOW):
        with h5py.File(os.path.join(run_dir, "runs", name + ".h5"), "r") as f:
            out[name] = {k: np.array(f[k]) for k in ("packing_fraction", "pressure",
                                                      "contacts_per_particle")}
    return out


def stopped_campaign(jam, toml, run_dir, delay=0.5):
    """Runs the campaign and stops it with SIGTERM while its slow run is under way (delay
    CPU seconds of the campaign's process after the fast run is done: on a loaded machine
    wall seconds would stop it before the run has computed anything)."""
    process = subprocess.Popen([jam, "campaign", "run", "--quiet", "--jobs", "1", toml],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    fast = os.path.join(run_dir, "runs", FAST + ".h5")
    deadline = time.monotonic() + 120
    while not os.path.exists(fast) and process.poll() is None:
        assert time.monotonic() < deadline, "the fast run never finished"
        time.sleep(0.02)
    start = process_cpu_seconds(process.pid)
    while process_cpu_seconds(process.pid) - start < delay and process.poll() is None:
        assert time.monotonic() < deadline, "the slow run never got the CPU"
        time.sleep(0.02)
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=120)
    checkpoint = os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")
    assert os.path.exists(checkpoint), \
        f"no checkpoint of the slow run (exit {process.returncode}): {err}"


def test_a_lost_directory_continues_from_its_snapshot(jam, work, campaign, run_jam, snapshot):
    reference = campaign("reference")
    result = run_jam("campaign", "run", "--quiet", reference)
    assert result.returncode == 0, result.stderr

    toml = campaign("work")
    run_dir = os.path.join(work, "work")
    stopped_campaign(jam, toml, run_dir)
    dest = os.path.join(work, "kept")
    result = snapshot("save", run_dir, dest, "--jam", jam)
    assert result.returncode == 0, result.stderr
    assert "1/2 runs done" in result.stdout
    assert sorted(os.listdir(os.path.join(dest, "runs"))) == [FAST + ".h5", FAST + ".record"]
    assert sorted(os.listdir(os.path.join(dest, "partial"))) == \
        [SLOW + ".h5.checkpoint", SLOW + ".start.h5"]
    for name in ("status.json", "campaign.toml", ".jam-snapshot"):
        assert os.path.isfile(os.path.join(dest, name)), name

    # Saved again: the run files are kept, the partial products replaced whole (a planted
    # stale file in partial/ goes).
    open(os.path.join(dest, "partial", "stale.start.h5"), "w").close()
    result = snapshot("save", run_dir, dest, "--jam", jam)
    assert "0 files copied, 2 kept" in result.stdout
    assert "stale.start.h5" not in os.listdir(os.path.join(dest, "partial"))
    # A snapshot saved before snapshots were marked is known by its status.json.
    os.unlink(os.path.join(dest, ".jam-snapshot"))
    result = snapshot("save", run_dir, dest, "--jam", jam)
    assert result.returncode == 0, result.stderr
    assert os.path.isfile(os.path.join(dest, ".jam-snapshot"))
    # A checkpoint over --max-partial-mb is left out and named; the start (smaller) is kept.
    checkpoint = os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")
    start = os.path.join(run_dir, "chain", SLOW + ".start.h5")
    limit = (os.path.getsize(checkpoint) + os.path.getsize(start)) / 2e6
    assert os.path.getsize(start) < os.path.getsize(checkpoint)
    result = snapshot("save", run_dir, dest, "--jam", jam, "--max-partial-mb",
                           str(limit))
    assert result.returncode == 0, result.stderr
    assert "left out" in result.stdout
    assert SLOW + ".h5.checkpoint" in result.stdout
    assert os.listdir(os.path.join(dest, "partial")) == [SLOW + ".start.h5"]
    result = snapshot("save", run_dir, dest, "--jam", jam, "--max-partial-mb",
                           "-1")
    assert result.returncode == 2
    assert "--max-partial-mb" in result.stderr
    result = snapshot("save", run_dir, dest, "--jam", jam)  # no limit: all again
    assert sorted(os.listdir(os.path.join(dest, "partial"))) == \
        [SLOW + ".h5.checkpoint", SLOW + ".start.h5"]

    shutil.rmtree(run_dir)  # the machine is lost
    result = snapshot("restore", dest, run_dir)
    assert result.returncode == 0, result.stderr
    assert "5 files restored" in result.stdout
    assert os.path.exists(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint"))
    assert os.path.exists(os.path.join(run_dir, "chain", SLOW + ".start.h5"))
    result = run_jam("campaign", "run", toml)
    assert result.returncode == 0, result.stderr
    assert "1 done, 1 to run" in result.stdout  # the fast run is not redone
    assert not os.path.exists(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint"))

    ours, theirs = values(run_dir), values(os.path.join(work, "reference"))
    for name in (FAST, SLOW):
        for key in ours[name]:
            np.testing.assert_array_equal(ours[name][key], theirs[name][key],
                                          err_msg=f"{name} {key}")

    # Restored again over the finished directory: nothing is overwritten.
    record = os.path.join(run_dir, "runs", FAST + ".record")
    before = slurp(record)
    result = snapshot("restore", dest, run_dir)
    assert result.returncode == 0, result.stderr
    assert "0 files restored" in result.stdout
    assert slurp(record) == before


def test_a_resumed_run_records_the_cost_of_its_earlier_attempts(jam, work, campaign, run_jam):
    reference = campaign("reference")
    result = run_jam("campaign", "run", "--quiet", reference)
    assert result.returncode == 0, result.stderr
    total = record_cpu_seconds(os.path.join(work, "reference"), SLOW)

    toml = campaign("work")
    run_dir = os.path.join(work, "work")
    stopped_campaign(jam, toml, run_dir, delay=0.5 * total)
    with h5py.File(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint"), "r") as f:
        before = float(f.attrs["cpu_seconds"])
    assert before > 0.1 * total
    result = run_jam("campaign", "run", "--quiet", toml)
    assert result.returncode == 0, result.stderr
    recorded = record_cpu_seconds(run_dir, SLOW)
    # Both attempts: the second alone (about total - before, what a record held before the
    # checkpoints kept the count) would fall short of this.
    assert recorded > before + 0.25 * total, f"total {total}, before {before}"
    assert recorded < 2.0 * total


def test_restore_refuses_a_running_campaign_and_a_non_snapshot(jam, work, snapshot):
    run_dir = os.path.join(work, "busy")
    os.makedirs(os.path.join(work, "kept", "runs"))
    os.makedirs(run_dir)
    with open(os.path.join(run_dir, ".lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # as `jam campaign run` holds it
        result = snapshot("restore", os.path.join(work, "kept"), run_dir)
    assert result.returncode == 2
    assert "a campaign is running there" in result.stderr
    result = snapshot("restore", work, run_dir)
    assert result.returncode == 2
    assert "not a snapshot" in result.stderr
    result = snapshot("save", os.path.join(work, "none"), work, "--jam",
                           jam)
    assert result.returncode == 2
    assert "no such directory" in result.stderr


def test_save_replaces_nothing_it_did_not_write(jam, work, snapshot):
    run_dir = os.path.join(work, "run")  # refused before it is read
    os.makedirs(run_dir)
    dest = os.path.join(work, "results")
    os.makedirs(os.path.join(dest, "partial"))
    notes = os.path.join(dest, "partial", "notes.txt")
    with open(notes, "w") as f:
        f.write("mine")
    result = snapshot("save", run_dir, dest, "--jam", jam)
    assert result.returncode == 2
    assert len(result.stderr.splitlines()) == 1, result.stderr
    assert "not empty and not a snapshot" in result.stderr
    # Even a snapshot's partial/ is replaced only when it holds save's files alone.
    with open(os.path.join(dest, "status.json"), "w") as f:
        f.write('{"run": {}}')
    result = snapshot("save", run_dir, dest, "--jam", jam)
    assert result.returncode == 2
    assert "partial/ holds notes.txt" in result.stderr
    assert slurp(notes) == "mine"


def test_save_refuses_a_status_with_corrupt_runs(work, snapshot):
    # From the wrong directory a chained campaign's runs all read as corrupt: the snapshot's
    # partial products must not be replaced by what such a status says.
    run_dir = os.path.join(work, "run")
    os.makedirs(os.path.join(run_dir, "runs"))
    dest = os.path.join(work, "results")
    os.makedirs(os.path.join(dest, "partial"))
    kept = os.path.join(dest, "partial", "n64_s001.h5.checkpoint")
    with open(kept, "w") as f:
        f.write("checkpoint")
    with open(os.path.join(dest, "status.json"), "w") as f:
        f.write('{"run": {}}')
    fake = os.path.join(work, "fake-jam")
    with open(fake, "w") as f:
        f.write(f"#!{sys.executable}\nimport json\nprint(json.dumps({{'run': {{'n64_s001': "
                "{'status': 'corrupt', 'detail': 'run file belongs to another run'}, "
                "'n64_s000': {'status': 'done', 'detail': ''}}}))\n")
    os.chmod(fake, 0o755)
    result = snapshot("save", run_dir, dest, "--jam", fake)
    assert result.returncode == 2, result.stderr
    assert "1 runs corrupt" in result.stderr
    assert slurp(kept) == "checkpoint"


def test_no_hang_on_a_fifo(work, script):
    dest = os.path.join(work, "kept")
    os.makedirs(os.path.join(dest, "runs"))
    os.mkfifo(os.path.join(dest, "runs", FAST + ".h5"))
    result = subprocess.run([sys.executable, script, "restore", dest,
                             os.path.join(work, "a")], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 2
    assert "is a FIFO" in result.stderr
    assert os.listdir(os.path.join(work, "a", "runs")) == []  # no temporary
    run_dir = os.path.join(work, "b")
    os.makedirs(run_dir)
    os.mkfifo(os.path.join(run_dir, ".lock"))
    os.unlink(os.path.join(dest, "runs", FAST + ".h5"))
    result = subprocess.run([sys.executable, script, "restore", dest, run_dir],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert ".lock" in result.stderr
