#!/usr/bin/python3
"""scripts/campaign_cost.py on a made-up campaign directory whose costs are known: ten runs of
one ensemble at 1 ms per force evaluation, one of them with a record holding a third of its
CPU seconds (a resume that lost its first attempts) and one at 1.2 ms (a loaded machine, not
short); two cheap runs that must not be judged (one with a jamming-point search, one of a
size whose runs take seconds); three chained starts left again, one run's twice (a start
lost and left again costs twice). The account must find the short record only, estimate it
from its siblings, count every start line, count a log given twice or copied earlier once,
and refuse a directory that is not a campaign's and a log that cannot be read.

Usage (ctest runs it): test_campaign_cost.py --source .
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import unittest

import h5py

ARGS = None


def write_run(directory, name, cpu, evaluations, minimizations=0):
    with open(os.path.join(directory, "runs", name + ".record"), "w") as f:
        f.write(f"cpu_seconds = {cpu}\nstatus = 'done'\nsteps = 10\n")
    with h5py.File(os.path.join(directory, "runs", name + ".h5"), "w") as f:
        f.attrs["force_evaluations"] = evaluations
        if minimizations:
            f.attrs["jamming_minimizations"] = minimizations


class CampaignCost(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.TemporaryDirectory(prefix="jam-campaign-cost-")
        self.dir = os.path.join(self.work.name, "c")
        os.makedirs(os.path.join(self.dir, "runs"))
        for s in range(10):
            cpu = {3: 100 / 3, 7: 120}.get(s, 100)
            write_run(self.dir, f"n1024_phi0.4000_r-6.00_s{s:03d}", cpu, 100_000)
        # Not judged: a run whose jamming-point search took CPU its evaluations do not count
        # (cheap per evaluation in the other direction: its dynamics short), and a size whose
        # runs take seconds, where fixed costs set the cost per evaluation.
        write_run(self.dir, "n1024_phi0.6000_r-6.00_s000", 30, 100_000, minimizations=14)
        for s in range(4):
            write_run(self.dir, f"n256_phi0.4000_r-6.00_s{s:03d}", 10 if s else 2, 10_000)
        # A running run's record is not counted.
        with open(os.path.join(self.dir, "runs", "n1024_phi0.4000_r-6.00_s010.record"), "w") as f:
            f.write("cpu_seconds = 5\nstatus = 'running'\n")
        self.log = os.path.join(self.work.name, "c.log")
        with open(self.log, "w") as f:
            for sample, cpu in ((0, 30), (1, 20), (0, 30)):
                f.write(f"campaign c: n1024_phi0.4000_r-5.00_s{sample:03d} left its start at "
                        f"0.78 again ({cpu} CPU seconds)\n")

    def tearDown(self):
        self.work.cleanup()

    def cost(self, *extra):
        script = os.path.join(ARGS.source, "scripts", "campaign_cost.py")
        return subprocess.run([sys.executable, script, *extra], capture_output=True, text=True,
                              timeout=60)

    def test_short_record_estimated_every_start_line_counted_each_log_once(self):
        # An earlier copy of the log (a snapshot's: its first line only) adds nothing.
        copy = os.path.join(self.work.name, "copy.log")
        with open(self.log) as f, open(copy, "w") as g:
            g.write(f.readline())
        r = self.cost(self.dir, "--log", self.log, copy, self.log, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        a = json.loads(r.stdout)
        self.assertEqual([x["run"] for x in a["short_records"]], ["n1024_phi0.4000_r-6.00_s003"])
        # Its siblings' median is 1 ms per evaluation (eight at 1 ms, one at 1.2 ms).
        self.assertAlmostEqual(a["short_records"][0]["estimated_cpu_seconds"], 100.0, places=6)
        self.assertAlmostEqual(a["cpu_seconds_recorded"],
                               8 * 100 + 100 / 3 + 120 + 30 + 32, places=6)
        self.assertAlmostEqual(a["cpu_seconds_missing_estimate"], 100 - 100 / 3, places=6)
        self.assertEqual(a["cpu_seconds_starts_again"], 80)
        self.assertEqual(len(a["starts_again"]), 3)
        self.assertAlmostEqual(a["cpu_seconds_total"], 10 * 100 + 20 + 80 + 62, places=6)
        # One row per size, phi_init and rate.
        rows = {(e["n"], e["phi_init"]): e["runs"] for e in a["ensembles"]}
        self.assertEqual(rows, {(256, 0.4): 4, (1024, 0.4): 10, (1024, 0.6): 1})

    def test_table_states_the_total(self):
        r = self.cost(self.dir, "--log", self.log)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("short record n1024_phi0.4000_r-6.00_s003", r.stdout)
        self.assertIn(f"{1162 / 3600:.2f} CPU h in all", r.stdout)

    def test_not_a_campaign_refused_in_one_line(self):
        r = self.cost(self.work.name)
        self.assertEqual(r.returncode, 2)
        self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)
        self.assertIn("no runs/ directory", r.stderr)

    def test_unreadable_log_refused_in_one_line(self):
        missing = os.path.join(self.work.name, "missing.log")
        r = self.cost(self.dir, "--log", missing)
        self.assertEqual(r.returncode, 2)
        self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)
        self.assertIn(missing, r.stderr)
        fifo = os.path.join(self.work.name, "fifo.log")
        os.mkfifo(fifo)
        r = self.cost(self.dir, "--log", fifo)  # refused, not read (a read would block)
        self.assertEqual(r.returncode, 2)
        self.assertIn("not a regular file", r.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", default=os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest])
