#!/usr/bin/python3
"""The resources of the Slurm chain's finishing job, and requests no node could ever meet.

With the fake Slurm of slurm_fixture.py (sinfo prints FAKE_SINFO, or fails as without a
controller):
  - by default the finishing job asks for 1 CPU, no memory and 04:00:00 on the command line
    (its header used to fix 4 CPUs and 16G, which a 2-CPU node never offers: it pended for ever
    with reason PartitionConfig); with the work job's -c and --mem it takes those;
  - submit.sh --finish-cpus, --finish-mem and --finish-time set them, never reach the work job,
    and every later finishing job of the chain (a resubmitted round, the replacement the chain
    step submits) keeps them;
  - where sinfo answers, a CPU, memory or time request of the work or the finishing job that no
    node of its partition meets is refused in one line naming the option and the value, before
    anything is submitted or written; a default time longer than the partition's limit is cut
    to it;
  - the chain log says which job finishes and how to see its state.

Usage (ctest runs it): test_slurm_resources.py --jam build/jam --source . [--scripts DIR]
"""

import os
import unittest

import slurm_fixture as fx
from slurm_fixture import Chain, option, script_of

# One partition "debug" (the default) of one 2-CPU node with 1900 MB and a 1 h limit, and a
# partition "big" of a 64-CPU node without a time limit.
SMALL_NODE = "debug* 2 1900 1:00:00"
TWO_PARTITIONS = SMALL_NODE + "\nbig 64 256000 infinite"


class FinishingJobResources(fx.SlurmTestCase):
    def finish_call(self, chain):
        work, finish, step = self.submitted(chain, 0)
        self.assertEqual(script_of(finish["argv"]), "campaign-finish.sbatch")
        return work, finish, step

    def test_default_fits_any_node(self):
        chain = Chain(self, "default")
        r = chain.submit("array", "ci.toml", "--array=0-1")
        work, finish, step = self.finish_call(chain)
        self.assertEqual(option(finish["argv"], "cpus-per-task"), "1")
        self.assertEqual(option(finish["argv"], "time"), "04:00:00")
        self.assertIsNone(option(finish["argv"], "mem"))
        self.assertIn("not checked against the partition (no answer from sinfo)", r.stdout)
        with open(os.path.join(fx.ARGS.scripts, "campaign-finish.sbatch")) as f:
            header = f.read()
        self.assertIn("\n#SBATCH --cpus-per-task=1\n", header)
        self.assertNotIn("\n#SBATCH --mem", header)

    def test_work_job_request_is_taken(self):
        chain = Chain(self, "derived")
        chain.submit("array", "ci.toml", "--array=0-1", "-c", "2", "--mem=1500M")
        work, finish, step = self.finish_call(chain)
        self.assertEqual(option(finish["argv"], "cpus-per-task"), "2")
        self.assertEqual(option(finish["argv"], "mem"), "1500M")

    def test_given_resources_are_kept_by_the_chain(self):
        chain = Chain(self, "given")
        chain.submit("array", "ci.toml", "--finish-cpus", "3", "--array=0-1",
                     "--finish-mem=2G", "--finish-time", "00:30:00")
        work, finish, step = self.finish_call(chain)
        self.assertEqual([a for a in work["argv"] if "finish" in a], [], work["argv"])
        wanted = {"cpus-per-task": "3", "mem": "2G", "time": "00:30:00"}
        self.assertEqual({k: option(finish["argv"], k) for k in wanted}, wanted)
        with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
            self.assertIn(f"finishing job {finish['job']} (afterok; --cpus-per-task=3 "
                          "--time=00:30:00 --mem=2G)", f.read())

        # Share 2 never ran: the chain step's next round keeps the finishing job's resources.
        chain.state("array", "2 0 1\n")
        chain.state("share-1", f"{work['job']} 0\n")
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]}, env={"FAKE_JAM_STATUS": "4"})
        self.assertEqual(rc, 0, log)
        _, finish1, step1 = self.submitted(chain, 3)
        self.assertEqual({k: option(finish1["argv"], k) for k in wanted}, wanted)

        # Every run done, yet a task recorded nothing: the replacement keeps them as well, and
        # the chain log says which job finishes and how to see its state.
        rc, log = chain.run_job(step1, {"SLURM_JOB_ID": step1["job"]},
                                env={"FAKE_JAM_STATUS": "0"})
        self.assertEqual(rc, 0, log)
        replacement = chain.calls("sbatch")[-1]
        self.assertEqual(script_of(replacement["argv"]), "campaign-finish.sbatch")
        self.assertIsNone(option(replacement["argv"], "dependency"))
        self.assertEqual({k: option(replacement["argv"], k) for k in wanted}, wanted)
        with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
            last = f.read().splitlines()[-1]
        job = replacement["job"]
        self.assertIn(f"finishing job {job} submitted in place of {finish1['job']}", last)
        self.assertIn(f"its state: squeue -j {job} (pending, reason PartitionConfig: it can "
                      "never start;", last)
        self.assertIn(f"sacct -j {job} once it ended", last)

    def test_complete_campaign_names_the_finishing_job_state(self):
        chain = Chain(self, "complete")
        chain.submit("array", "ci.toml", "--array=0-1")
        work, finish, step = self.finish_call(chain)
        chain.state("array", "2 0 1\n")
        for k in (1, 2):
            chain.state(f"share-{k}", f"{work['job']} 0\n")
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]}, env={"FAKE_JAM_STATUS": "0"})
        self.assertEqual(rc, 0, log)
        self.assertIn(f"finishing job {finish['job']} makes the statistics, checks and report; "
                      f"its state: squeue -j {finish['job']}", log)


class RequestsNoNodeMeets(fx.SlurmTestCase):
    def refused(self, chain, args, message, env=None):
        """submit.sh refuses in one line with message; nothing submitted, nothing written."""
        chain.env.update(env or {})
        r = chain.submit("array", "ci.toml", "--array=0-1", *args, expect=2)
        self.assertEqual(r.stderr, f"jam-slurm: error: {message}\n", args)
        self.assertEqual(chain.calls("sbatch"), [], args)
        self.assertFalse(os.path.exists(os.path.join(chain.campaign_dir, "slurm")), args)

    def test_each_impossible_request_is_named(self):
        chain = Chain(self, "impossible")
        chain.env["FAKE_SINFO"] = SMALL_NODE
        never = "the job could never start"
        where = "partition debug (sinfo)"
        for args, message in [
            (["--finish-cpus", "4"], f"--finish-cpus 4: no node of {where} has more than 2 "
                                     f"CPUs: {never}"),
            (["--finish-mem=16G"], f"--finish-mem 16G: no node of {where} has more than 1900 MB "
                                   f"of memory: {never}"),
            (["--finish-time", "02:00:00"], f"--finish-time 02:00:00: the time limit of {where} "
                                            f"is 60 minutes: {never}"),
            (["-c", "4"], f"--cpus-per-task 4: no node of {where} has more than 2 CPUs: {never}"),
            (["--mem", "2G"], f"--mem 2G: no node of {where} has more than 1900 MB of memory: "
                              f"{never}"),
            (["--time=1-0"], f"--time 1-0: the time limit of {where} is 60 minutes: {never}"),
            (["--finish-mem", "16GB"], "--finish-mem '16GB' must be a whole number with an "
                                       "optional K, M, G or T suffix"),
            (["--finish-cpus=0"], "--finish-cpus '0' must be a whole number >= 1"),
            (["--finish-time", "1h"], "--finish-time '1h' is not a Slurm time (minutes, H:M:S or "
                                      "D-H:M:S)"),
            (["--finish-gpus", "1"], "--finish-gpus: unknown (--finish-cpus, --finish-mem, "
                                     "--finish-time)"),
        ]:
            with self.subTest(args=args):
                self.refused(chain, args, message)

    def test_fitting_request_goes_with_the_partition_limit(self):
        chain = Chain(self, "fits")
        chain.env["FAKE_SINFO"] = SMALL_NODE
        r = chain.submit("array", "ci.toml", "--array=0-1", "-c", "2", "--finish-mem", "1900M")
        self.assertIn("checked against partition debug (sinfo)", r.stdout)
        work, finish, step = self.submitted(chain, 0)
        # the default 04:00:00 is longer than the partition allows: its limit, in minutes
        self.assertEqual(option(finish["argv"], "time"), "60")
        self.assertEqual(option(finish["argv"], "cpus-per-task"), "2")
        self.assertEqual(option(finish["argv"], "mem"), "1900M")

    def test_each_job_is_judged_in_its_partition(self):
        # The work job's --partition is its own; the finishing job goes to SBATCH_PARTITION or
        # the default, so the work job's 32 CPUs, its default, cannot follow it there.
        chain = Chain(self, "partitions")
        chain.env["FAKE_SINFO"] = TWO_PARTITIONS
        self.refused(chain, ["--partition=big", "-c", "32"],
                     "--finish-cpus (by default the work job's -c) 32: no node of partition "
                     "debug (sinfo) has more than 2 CPUs: the job could never start")
        chain.submit("array", "ci.toml", "--array=0-1", "--partition=big", "-c", "32",
                     "--finish-cpus", "1")
        self.assertEqual(option(self.submitted(chain, 0)[1]["argv"], "cpus-per-task"), "1")
        other = Chain(self, "partitions-env")
        other.env.update({"FAKE_SINFO": TWO_PARTITIONS, "SBATCH_PARTITION": "big"})
        other.submit("array", "ci.toml", "--array=0-1", "-c", "32")
        work, finish, step = self.submitted(other, 0)
        self.assertEqual(option(finish["argv"], "cpus-per-task"), "32")
        self.assertEqual(option(finish["argv"], "time"), "04:00:00")


if __name__ == "__main__":
    unittest.TestCase.maxDiff = None
    fx.main(__doc__)
