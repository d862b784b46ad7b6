#!/usr/bin/python3
"""scripts/campaign_snapshot.py: a campaign stopped mid-run (SIGTERM: a checkpoint) is saved,
its directory lost, restored from the snapshot and finished; its run files are then those of
the same campaign run without a stop, value for value. Also: save keeps what DEST holds and
replaces its partial products whole; restore overwrites nothing, refuses while the campaign's
lock is held, and refuses a DEST that is not a snapshot. Neither deletes nor replaces a file it
did not write (save refuses a DEST that holds other files and is no snapshot, and a partial/
with anything but checkpoints and starts), and neither hangs on a FIFO. A run resumed from its checkpoint
records the CPU seconds of its attempts before the stop too.

Usage (ctest runs it): test_campaign_snapshot.py --jam build/jam --source .
"""

import argparse
import fcntl
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
import unittest

import h5py
import numpy as np

ARGS = None

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


class Snapshot(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="jam-snapshot-")
        self.script = os.path.join(ARGS.source, "scripts", "campaign_snapshot.py")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def campaign(self, name):
        path = os.path.join(self.dir, name + ".toml")
        with open(path, "w") as f:
            f.write(CAMPAIGN.format(output=os.path.join(self.dir, name)))
        return path

    def jam(self, *args):
        return subprocess.run([ARGS.jam, *args], capture_output=True, text=True)

    def snapshot(self, *args):
        return subprocess.run([sys.executable, self.script, *args], capture_output=True,
                              text=True)

    def values(self, run_dir):
        out = {}
        for name in (FAST, SLOW):
            with h5py.File(os.path.join(run_dir, "runs", name + ".h5"), "r") as f:
                out[name] = {k: np.array(f[k]) for k in ("packing_fraction", "pressure",
                                                          "contacts_per_particle")}
        return out

    def stopped_campaign(self, toml, run_dir, delay=0.5):
        """Runs the campaign and stops it with SIGTERM while its slow run is under way (delay
        CPU seconds of the campaign's process after the fast run is done: on a loaded machine
        wall seconds would stop it before the run has computed anything)."""
        process = subprocess.Popen([ARGS.jam, "campaign", "run", "--quiet", "--jobs", "1", toml],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        fast = os.path.join(run_dir, "runs", FAST + ".h5")
        deadline = time.monotonic() + 120
        while not os.path.exists(fast) and process.poll() is None:
            self.assertLess(time.monotonic(), deadline, "the fast run never finished")
            time.sleep(0.02)
        start = process_cpu_seconds(process.pid)
        while process_cpu_seconds(process.pid) - start < delay and process.poll() is None:
            self.assertLess(time.monotonic(), deadline, "the slow run never got the CPU")
            time.sleep(0.02)
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=120)
        checkpoint = os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")
        self.assertTrue(os.path.exists(checkpoint),
                        f"no checkpoint of the slow run (exit {process.returncode}): {err}")

    def test_a_lost_directory_continues_from_its_snapshot(self):
        reference = self.campaign("reference")
        result = self.jam("campaign", "run", "--quiet", reference)
        self.assertEqual(result.returncode, 0, result.stderr)

        toml = self.campaign("work")
        run_dir = os.path.join(self.dir, "work")
        self.stopped_campaign(toml, run_dir)
        dest = os.path.join(self.dir, "kept")
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("1/2 runs done", result.stdout)
        self.assertEqual(sorted(os.listdir(os.path.join(dest, "runs"))),
                         [FAST + ".h5", FAST + ".record"])
        self.assertEqual(sorted(os.listdir(os.path.join(dest, "partial"))),
                         [SLOW + ".h5.checkpoint", SLOW + ".start.h5"])
        for name in ("status.json", "campaign.toml", ".jam-snapshot"):
            self.assertTrue(os.path.isfile(os.path.join(dest, name)), name)

        # Saved again: the run files are kept, the partial products replaced whole (a planted
        # stale file in partial/ goes).
        open(os.path.join(dest, "partial", "stale.start.h5"), "w").close()
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)
        self.assertIn("0 files copied, 2 kept", result.stdout)
        self.assertNotIn("stale.start.h5", os.listdir(os.path.join(dest, "partial")))
        # A snapshot saved before snapshots were marked is known by its status.json.
        os.unlink(os.path.join(dest, ".jam-snapshot"))
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(os.path.isfile(os.path.join(dest, ".jam-snapshot")))
        # A checkpoint over --max-partial-mb is left out and named; the start (smaller) is kept.
        checkpoint = os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")
        start = os.path.join(run_dir, "chain", SLOW + ".start.h5")
        limit = (os.path.getsize(checkpoint) + os.path.getsize(start)) / 2e6
        self.assertLess(os.path.getsize(start), os.path.getsize(checkpoint))
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam, "--max-partial-mb",
                               str(limit))
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("left out", result.stdout)
        self.assertIn(SLOW + ".h5.checkpoint", result.stdout)
        self.assertEqual(os.listdir(os.path.join(dest, "partial")), [SLOW + ".start.h5"])
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam, "--max-partial-mb",
                               "-1")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--max-partial-mb", result.stderr)
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)  # no limit: all again
        self.assertEqual(sorted(os.listdir(os.path.join(dest, "partial"))),
                         [SLOW + ".h5.checkpoint", SLOW + ".start.h5"])

        shutil.rmtree(run_dir)  # the machine is lost
        result = self.snapshot("restore", dest, run_dir)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("5 files restored", result.stdout)
        self.assertTrue(os.path.exists(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")))
        self.assertTrue(os.path.exists(os.path.join(run_dir, "chain", SLOW + ".start.h5")))
        result = self.jam("campaign", "run", toml)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("1 done, 1 to run", result.stdout)  # the fast run is not redone
        self.assertFalse(os.path.exists(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint")))

        ours, theirs = self.values(run_dir), self.values(os.path.join(self.dir, "reference"))
        for name in (FAST, SLOW):
            for key in ours[name]:
                np.testing.assert_array_equal(ours[name][key], theirs[name][key],
                                              err_msg=f"{name} {key}")

        # Restored again over the finished directory: nothing is overwritten.
        record = os.path.join(run_dir, "runs", FAST + ".record")
        before = slurp(record)
        result = self.snapshot("restore", dest, run_dir)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("0 files restored", result.stdout)
        self.assertEqual(slurp(record), before)

    def test_a_resumed_run_records_the_cost_of_its_earlier_attempts(self):
        reference = self.campaign("reference")
        result = self.jam("campaign", "run", "--quiet", reference)
        self.assertEqual(result.returncode, 0, result.stderr)
        total = record_cpu_seconds(os.path.join(self.dir, "reference"), SLOW)

        toml = self.campaign("work")
        run_dir = os.path.join(self.dir, "work")
        self.stopped_campaign(toml, run_dir, delay=0.5 * total)
        with h5py.File(os.path.join(run_dir, "runs", SLOW + ".h5.checkpoint"), "r") as f:
            before = float(f.attrs["cpu_seconds"])
        self.assertGreater(before, 0.1 * total)
        result = self.jam("campaign", "run", "--quiet", toml)
        self.assertEqual(result.returncode, 0, result.stderr)
        recorded = record_cpu_seconds(run_dir, SLOW)
        # Both attempts: the second alone (about total - before, what a record held before the
        # checkpoints kept the count) would fall short of this.
        self.assertGreater(recorded, before + 0.25 * total, f"total {total}, before {before}")
        self.assertLess(recorded, 2.0 * total)

    def test_restore_refuses_a_running_campaign_and_a_non_snapshot(self):
        run_dir = os.path.join(self.dir, "busy")
        os.makedirs(os.path.join(self.dir, "kept", "runs"))
        os.makedirs(run_dir)
        with open(os.path.join(run_dir, ".lock"), "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # as `jam campaign run` holds it
            result = self.snapshot("restore", os.path.join(self.dir, "kept"), run_dir)
        self.assertEqual(result.returncode, 2)
        self.assertIn("a campaign is running there", result.stderr)
        result = self.snapshot("restore", self.dir, run_dir)
        self.assertEqual(result.returncode, 2)
        self.assertIn("not a snapshot", result.stderr)
        result = self.snapshot("save", os.path.join(self.dir, "none"), self.dir, "--jam",
                               ARGS.jam)
        self.assertEqual(result.returncode, 2)
        self.assertIn("no such directory", result.stderr)

    def test_save_replaces_nothing_it_did_not_write(self):
        run_dir = os.path.join(self.dir, "run")  # refused before it is read
        os.makedirs(run_dir)
        dest = os.path.join(self.dir, "results")
        os.makedirs(os.path.join(dest, "partial"))
        notes = os.path.join(dest, "partial", "notes.txt")
        with open(notes, "w") as f:
            f.write("mine")
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
        self.assertIn("not empty and not a snapshot", result.stderr)
        # Even a snapshot's partial/ is replaced only when it holds save's files alone.
        with open(os.path.join(dest, "status.json"), "w") as f:
            f.write('{"run": {}}')
        result = self.snapshot("save", run_dir, dest, "--jam", ARGS.jam)
        self.assertEqual(result.returncode, 2)
        self.assertIn("partial/ holds notes.txt", result.stderr)
        self.assertEqual(slurp(notes), "mine")

    def test_save_refuses_a_status_with_corrupt_runs(self):
        # From the wrong directory a chained campaign's runs all read as corrupt: the snapshot's
        # partial products must not be replaced by what such a status says.
        run_dir = os.path.join(self.dir, "run")
        os.makedirs(os.path.join(run_dir, "runs"))
        dest = os.path.join(self.dir, "results")
        os.makedirs(os.path.join(dest, "partial"))
        kept = os.path.join(dest, "partial", "n64_s001.h5.checkpoint")
        with open(kept, "w") as f:
            f.write("checkpoint")
        with open(os.path.join(dest, "status.json"), "w") as f:
            f.write('{"run": {}}')
        fake = os.path.join(self.dir, "fake-jam")
        with open(fake, "w") as f:
            f.write(f"#!{sys.executable}\nimport json\nprint(json.dumps({{'run': {{'n64_s001': "
                    "{'status': 'corrupt', 'detail': 'run file belongs to another run'}, "
                    "'n64_s000': {'status': 'done', 'detail': ''}}}))\n")
        os.chmod(fake, 0o755)
        result = self.snapshot("save", run_dir, dest, "--jam", fake)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("1 runs corrupt", result.stderr)
        self.assertEqual(slurp(kept), "checkpoint")

    def test_no_hang_on_a_fifo(self):
        dest = os.path.join(self.dir, "kept")
        os.makedirs(os.path.join(dest, "runs"))
        os.mkfifo(os.path.join(dest, "runs", FAST + ".h5"))
        result = subprocess.run([sys.executable, self.script, "restore", dest,
                                 os.path.join(self.dir, "a")], capture_output=True, text=True,
                                timeout=60)
        self.assertEqual(result.returncode, 2)
        self.assertIn("is a FIFO", result.stderr)
        self.assertEqual(os.listdir(os.path.join(self.dir, "a", "runs")), [])  # no temporary
        run_dir = os.path.join(self.dir, "b")
        os.makedirs(run_dir)
        os.mkfifo(os.path.join(run_dir, ".lock"))
        os.unlink(os.path.join(dest, "runs", FAST + ".h5"))
        result = subprocess.run([sys.executable, self.script, "restore", dest, run_dir],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 2)
        self.assertIn(".lock", result.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--jam", required=True)
    parser.add_argument("--source", required=True)
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest])
