#!/usr/bin/python3
"""The batch scripts of scripts/slurm/ run as far as a machine without Slurm allows.

`sbatch`, `srun`, `scancel` and `scontrol` are fakes on PATH that record their arguments (and
the JAM* environment a job would inherit) in calls.jsonl; sbatch hands out job ids, srun runs
its command. The test then plays Slurm: it runs each recorded job with the variables Slurm would
set (SLURM_JOB_ID, SLURM_ARRAY_TASK_ID/COUNT/MIN/MAX/STEP, ...) on the tiny CI campaign:
  - a 0-based array of 2 tasks (one of them from a spool copy, as sbatch runs scripts) and a
    1-based array with a step complete the campaign (`jam campaign status` exits 0); the chain
    step then submits nothing; the finishing job runs `jam stats`, `jam check all`, `jam report`;
  - a task stopped by SIGTERM mid-run exits 130 with checkpoints; its chain step resubmits
    that array index alone (--dependency=afterany on the array job, the same share as
    --shard K/N, the submit options kept), which completes the campaign; at the maximum number of
    resubmissions the chain step stops and says so;
  - the MPI job (srun): a SIGTERM to the script is not passed on (srun would kill the ranks),
    one to jam (Slurm's --signal without B: signals the job step) stops it with checkpoints; it
    is resubmitted and completes (on the CI campaign with one sample per ensemble);
  - the chain step's decisions on planted states: failed runs stop it, a complete campaign
    submits nothing, every task done but runs missing resubmits every share;
  - a campaign file hiding `output = "<decoy>"` in a multi-line string: the scripts take the
    directory from `jam campaign output`, so submit.sh cleans and the finishing job judges the
    real one and the decoy's files stay; a job told another directory refuses to run.
Where shellcheck is installed, the scripts are also checked with it.
`jam check` and `jam report` are recorded, not run (they take a minute on the CI campaign;
test_report runs them); every other jam command is the real one.

Usage (ctest runs it): test_slurm_scripts.py --jam build/jam --source . [--scripts DIR]
"""

import argparse
import json
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
import unittest

ARGS = None

FAKE_SBATCH = r'''#!/usr/bin/python3
import fcntl, json, os, sys
d = os.environ["FAKE_SLURM_DIR"]
with open(os.path.join(d, "lock"), "a+") as lock:
    fcntl.flock(lock, fcntl.LOCK_EX)
    counter = os.path.join(d, "next_job_id")
    job = int(open(counter).read()) if os.path.exists(counter) else 1000
    with open(counter, "w") as f:
        f.write(str(job + 1))
    env = {k: v for k, v in os.environ.items() if k.startswith("JAM")}
    with open(os.path.join(d, "calls.jsonl"), "a") as f:
        f.write(json.dumps({"tool": "sbatch", "argv": sys.argv[1:], "env": env, "job": job,
                            "cwd": os.getcwd()}) + "\n")
print(job if "--parsable" in sys.argv[1:] else f"Submitted batch job {job}")
'''

# Records, then: srun runs its command (after its options); scontrol shows a job whose Command
# is FAKE_SCONTROL_COMMAND; scancel does nothing more.
FAKE_TOOL = r'''#!/usr/bin/python3
import fcntl, json, os, sys
tool = os.path.basename(sys.argv[0])
d = os.environ["FAKE_SLURM_DIR"]
with open(os.path.join(d, "lock"), "a+") as lock:
    fcntl.flock(lock, fcntl.LOCK_EX)
    with open(os.path.join(d, "calls.jsonl"), "a") as f:
        f.write(json.dumps({"tool": tool, "argv": sys.argv[1:]}) + "\n")
if tool == "srun":
    args = sys.argv[1:]
    while args and args[0].startswith("-"):
        args = args[1:]
    os.execvp(args[0], args)
if tool == "scontrol":
    print(f"JobId={sys.argv[-1]} JobName=x\n   Command={os.environ['FAKE_SCONTROL_COMMAND']}\n")
'''

# jam as the jobs see it: records the command; `check` and `report` stop there (check: 3,
# inconclusive, as on the CI campaign), everything else is the real jam (exec: same pid, so a
# signal to it reaches jam). FAKE_JAM_STATUS set: `campaign status` only exits with it.
JAM_WRAPPER = r'''#!/usr/bin/python3
import fcntl, json, os, sys
d = os.environ["FAKE_SLURM_DIR"]
with open(os.path.join(d, "lock"), "a+") as lock:
    fcntl.flock(lock, fcntl.LOCK_EX)
    with open(os.path.join(d, "calls.jsonl"), "a") as f:
        f.write(json.dumps({"tool": "jam", "argv": sys.argv[1:],
                            "task": os.environ.get("SLURM_ARRAY_TASK_ID")}) + "\n")
args = sys.argv[1:]
if args[:1] == ["check"]:
    sys.exit(3)
if args[:1] == ["report"]:
    sys.exit(0)
if args[:2] == ["campaign", "status"] and os.environ.get("FAKE_JAM_STATUS"):
    sys.exit(int(os.environ["FAKE_JAM_STATUS"]))
os.execv(os.environ["REAL_JAM"], [os.environ["REAL_JAM"]] + args)
'''


def write_executable(path, text):
    with open(path, "w") as f:
        f.write(text)
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)


def array_indices(spec):
    """The indices of an sbatch --array spec: A-B[:S], lists of those, %limit ignored."""
    out = []
    for part in spec.split("%")[0].split(","):
        m = re.fullmatch(r"(\d+)(?:-(\d+)(?::(\d+))?)?", part)
        if not m:
            raise AssertionError(f"--array={spec}: not understood")
        first, last, step = int(m[1]), int(m[2] or m[1]), int(m[3] or 1)
        out += list(range(first, last + 1, step))
    return out


class Chain:
    """One fake cluster: a directory with calls.jsonl and job ids, and the campaign copy."""

    def __init__(self, test, name, campaign_text=None):
        self.test = test
        self.dir = os.path.join(test.tmp, name)
        os.makedirs(self.dir)
        self.campaign_dir = os.path.join(self.dir, "runs", "ci")
        if campaign_text is None:
            with open(os.path.join(ARGS.source, "reference", "campaigns", "ci.toml")) as f:
                campaign_text = f.read()
        text = campaign_text
        # relative output: the jobs run in the submit directory, as under Slurm
        text = re.sub(r'(?m)^output = .*$', 'output = "runs/ci"', text)
        self.file = os.path.join(self.dir, "ci.toml")
        with open(self.file, "w") as f:
            f.write(text)
        self.env = {"PATH": f"{test.bin}:/usr/bin:/bin", "HOME": self.dir, "LANG": "C.UTF-8",
                    "FAKE_SLURM_DIR": self.dir, "REAL_JAM": test.jam,
                    "JAM": os.path.join(test.bin, "jam")}

    def calls(self, tool=None):
        path = os.path.join(self.dir, "calls.jsonl")
        if not os.path.exists(path):
            return []
        with open(path) as f:
            calls = [json.loads(line) for line in f]
        return [c for c in calls if tool is None or c["tool"] == tool]

    def submit(self, *args, expect=0):
        r = subprocess.run([os.path.join(ARGS.scripts, "submit.sh"), *args], cwd=self.dir,
                           env=self.env, capture_output=True, text=True, timeout=60)
        self.test.assertEqual(r.returncode, expect, r.stdout + r.stderr)
        return r

    def job(self, call, slurm, env=None, script=None, term_after=None):
        """Starts a recorded sbatch call as Slurm would; returns the process."""
        argv = call["argv"]
        at = next(i for i, a in enumerate(argv) if a.endswith(".sbatch"))
        full = dict(self.env)
        full.update(call["env"])
        full.update({"SLURM_SUBMIT_DIR": call["cwd"], "SLURM_CPUS_PER_TASK": "1",
                     "SLURM_NTASKS": "1"})
        full.update({k: str(v) for k, v in slurm.items()})
        for k, v in (env or {}).items():
            if v is None:
                full.pop(k, None)
            else:
                full[k] = v
        log = open(os.path.join(self.dir, f"job-{slurm['SLURM_JOB_ID']}.log"), "w+")
        p = subprocess.Popen([script or argv[at], *argv[at + 1:]], cwd=call["cwd"], env=full,
                             stdout=log, stderr=subprocess.STDOUT)
        self.test.addCleanup(log.close)  # finish() closes it; this, when a test fails first
        p.log = log
        p.term_after = term_after
        return p

    def array_tasks(self, call, per_task=None):
        """Processes of every task of a recorded array submission (per_task: index -> the
        keyword arguments of job() for that task)."""
        spec = next(a.split("=", 1)[1] for a in call["argv"] if a.startswith("--array="))
        ids = array_indices(spec)
        procs = []
        for n, i in enumerate(ids):
            slurm = {"SLURM_JOB_ID": call["job"] + 100 + n, "SLURM_ARRAY_JOB_ID": call["job"],
                     "SLURM_ARRAY_TASK_ID": i, "SLURM_ARRAY_TASK_COUNT": len(ids),
                     "SLURM_ARRAY_TASK_MIN": min(ids), "SLURM_ARRAY_TASK_MAX": max(ids),
                     "SLURM_ARRAY_TASK_STEP": ids[1] - ids[0] if len(ids) > 1 else 1}
            procs.append(self.job(call, slurm, **(per_task or {}).get(i, {})))
        return ids, procs

    def wait_for_a_run(self, p, then):
        """Returns `then` seconds after the campaign's first run file appeared."""
        started = time.time()
        runs = os.path.join(self.campaign_dir, "runs")
        while not (os.path.isdir(runs) and os.listdir(runs)):
            self.test.assertIsNone(p.poll(), "the job ended before any run started")
            self.test.assertLess(time.time() - started, 60, "no run started")
            time.sleep(0.05)
        time.sleep(then)
        self.test.assertIsNone(p.poll(), "the job ended before the signal")

    def finish(self, procs):
        """Waits for the processes (SIGTERM to those asked for, once a run is under way);
        returns (exit status, log) of each."""
        for p in procs:
            if p.term_after is not None:
                self.wait_for_a_run(p, p.term_after)
                # jam is held (SIGSTOP) until the script has passed the SIGTERM on, so the
                # signal cannot come after jam finished its last run on a fast machine.
                jam = campaign_run_child(p.pid, self.test)
                os.kill(jam, signal.SIGSTOP)
                p.send_signal(signal.SIGTERM)
                deadline = time.time() + 30
                while not signal_pending(jam, signal.SIGTERM):
                    self.test.assertLess(time.time(), deadline, "SIGTERM not passed on")
                    time.sleep(0.01)
                os.kill(jam, signal.SIGCONT)
        out = []
        for p in procs:
            rc = p.wait(timeout=300)
            p.log.seek(0)
            out.append((rc, p.log.read()))
            p.log.close()
        return out

    def run_job(self, call, slurm, **kw):
        return self.finish([self.job(call, slurm, **kw)])[0]

    def status(self):
        return subprocess.run([self.test.jam, "campaign", "status", self.campaign_dir],
                              capture_output=True, text=True, timeout=60).returncode

    def state(self, name, text):
        os.makedirs(os.path.join(self.campaign_dir, "slurm"), exist_ok=True)
        with open(os.path.join(self.campaign_dir, "slurm", name), "w") as f:
            f.write(text)


def signal_pending(pid, sig):
    """Whether signal sig waits for process pid (its shared or its thread's pending set)."""
    with open(f"/proc/{pid}/status") as f:
        masks = [int(line.split()[1], 16) for line in f
                 if line.startswith(("ShdPnd:", "SigPnd:"))]
    return any(m >> (sig - 1) & 1 for m in masks)


def children(pid):
    """The pids of the processes whose parent is pid."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                out.append(int(entry))
    return out


def campaign_run_child(pid, test):
    """The one child of pid that runs the campaign (an argument `run`), once it is there: the
    scripts first ask `jam campaign output`, a child of their own that must not be taken for
    it (a SIGSTOP there would hold the wrong process)."""
    deadline = time.time() + 60
    while True:
        runs = []
        for child in children(pid):
            try:
                with open(f"/proc/{child}/cmdline", "rb") as f:
                    if b"run" in f.read().split(b"\0"):
                        runs.append(child)
            except OSError:
                continue
        if len(runs) == 1:
            return runs[0]
        test.assertLess(time.time(), deadline, f"no single campaign run under {pid}: {runs}")
        time.sleep(0.01)


def option(argv, name):
    """The value of --name=value in argv (None when absent)."""
    values = [a.split("=", 1)[1] for a in argv if a.startswith(f"--{name}=")]
    return values[-1] if values else None


def script_of(argv):
    return os.path.basename(next(a for a in argv if a.endswith(".sbatch")))


class SlurmScripts(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="jam-slurm-")
        cls.bin = os.path.join(cls.tmp, "bin")
        os.makedirs(cls.bin)
        write_executable(os.path.join(cls.bin, "sbatch"), FAKE_SBATCH)
        for tool in ("srun", "scancel", "scontrol"):
            write_executable(os.path.join(cls.bin, tool), FAKE_TOOL)
        write_executable(os.path.join(cls.bin, "jam"), JAM_WRAPPER)
        # a copy: a rebuild of the build tree meanwhile does not pull it away under the jobs
        cls.jam = shutil.copy2(ARGS.jam, os.path.join(cls.tmp, "jam-under-test"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def submitted(self, chain, before):
        """The sbatch calls since `before` of them, as (work, finish, chain step)."""
        new = chain.calls("sbatch")[before:]
        self.assertEqual([script_of(c["argv"]) for c in new][1:],
                         ["campaign-finish.sbatch", "campaign-chain.sbatch"],
                         "a round is the work job, the finishing job and the chain step")
        work, finish, step = new
        self.assertEqual(option(finish["argv"], "dependency"), f"afterok:{work['job']}")
        self.assertEqual(option(step["argv"], "dependency"), f"afterany:{work['job']}")
        self.assertEqual(step["env"]["JAM_SLURM_WORK_JOB"], str(work["job"]))
        self.assertEqual(step["env"]["JAM_SLURM_FINISH_JOB"], str(finish["job"]))
        return work, finish, step

    def assert_finishing_job(self, chain, finish):
        jam_before = len(chain.calls("jam"))
        rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]})
        self.assertEqual(rc, 0, log)
        commands = [c["argv"] for c in chain.calls("jam")[jam_before:]]
        self.assertEqual(commands, [["campaign", "output", chain.file],
                                    ["campaign", "status", chain.campaign_dir],
                                    ["stats", chain.campaign_dir],
                                    ["check", "all", chain.campaign_dir],
                                    ["report", chain.campaign_dir]], log)
        self.assertTrue(os.path.exists(os.path.join(chain.campaign_dir, "stats.h5")), log)

    def assert_nothing_more(self, chain, step):
        sbatch_before, cancel_before = len(chain.calls("sbatch")), len(chain.calls("scancel"))
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
        self.assertEqual(rc, 0, log)
        self.assertIn("campaign complete", log)
        self.assertEqual(len(chain.calls("sbatch")), sbatch_before, "submitted more: " + log)
        self.assertEqual(len(chain.calls("scancel")), cancel_before, log)

    def test_zero_based_array_completes(self):
        chain = Chain(self, "zero-based")
        chain.submit("array", "ci.toml", "--array=0-1")
        work, finish, step = self.submitted(chain, 0)
        self.assertEqual(script_of(work["argv"]), "campaign-array.sbatch")
        self.assertEqual(option(work["argv"], "array"), "0-1")
        self.assertIsNone(option(work["argv"], "dependency"))
        # task 1 runs as sbatch runs scripts: a copy in a spool directory, found back by scontrol
        spool = os.path.join(chain.dir, "spool")
        os.makedirs(spool)
        copy = shutil.copy(os.path.join(ARGS.scripts, "campaign-array.sbatch"), spool)
        real = next(a for a in work["argv"] if a.endswith(".sbatch"))
        ids, procs = chain.array_tasks(work, {1: {"script": copy, "env": {
            "JAM_SLURM_DIR": None, "FAKE_SCONTROL_COMMAND": real}}})
        results = chain.finish(procs)
        for rc, log in results:
            self.assertEqual(rc, 0, log)
        self.assertTrue(chain.calls("scontrol"), "the spool copy asked scontrol for its script")
        runs = [c for c in chain.calls("jam") if c["argv"][:2] == ["campaign", "run"]]
        self.assertEqual(sorted((c["task"], c["argv"][c["argv"].index("--shard") + 1])
                                for c in runs), [("0", "auto"), ("1", "auto")])
        self.assertEqual(chain.status(), 0, "the two tasks together complete the campaign")
        self.assert_nothing_more(chain, step)
        self.assert_finishing_job(chain, finish)

    def test_interrupted_task_is_resubmitted(self):
        chain = Chain(self, "one-based")
        chain.submit("array", "ci.toml", "--array=1-3:2", "--time=00:30:00",
                     "--", "--log-every", "5")
        work, finish, step = self.submitted(chain, 0)
        self.assertEqual(work["argv"][-3:], [chain.file, "--log-every", "5"])
        ids, procs = chain.array_tasks(work, {3: {"term_after": 0.2}})
        self.assertEqual(ids, [1, 3])
        (rc1, log1), (rc3, log3) = chain.finish(procs)
        self.assertEqual(rc1, 0, log1)
        self.assertEqual(rc3, 130, "SIGTERM: jam checkpoints and exits 130\n" + log3)
        self.assertIn("interrupted", log3)
        self.assertEqual(chain.status(), 4, "share 2 is unfinished")

        # At the maximum number of resubmissions: stops, says so, submits nothing.
        before = len(chain.calls("sbatch"))
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]},
                                env={"JAM_SLURM_MAX_RESUBMIT": "0"})
        self.assertEqual(rc, 1, log)
        self.assertIn("maximum of 0 resubmissions", log)
        self.assertEqual(len(chain.calls("sbatch")), before, log)
        self.assertIn(["{}".format(finish["job"])], [c["argv"] for c in chain.calls("scancel")])

        # The chain step resubmits index 3 alone, after the array job, with the options kept.
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
        self.assertEqual(rc, 0, log)
        work1, finish1, step1 = self.submitted(chain, before)
        self.assertEqual(script_of(work1["argv"]), "campaign-array.sbatch")
        self.assertEqual(option(work1["argv"], "array"), "3")
        self.assertEqual(option(work1["argv"], "dependency"), f"afterany:{work['job']}")
        self.assertEqual(option(work1["argv"], "time"), "00:30:00")
        self.assertEqual(work1["argv"][-3:], [chain.file, "--log-every", "5"])
        self.assertEqual(step1["env"]["JAM_SLURM_ROUND"], "1")

        # Slurm numbers the new array alone (1 task from 3); the share stays 2 of 2.
        ids, procs = chain.array_tasks(work1)
        (rc, log), = chain.finish(procs)
        self.assertEqual(rc, 0, log)
        last = [c for c in chain.calls("jam") if c["argv"][:2] == ["campaign", "run"]][-1]
        self.assertEqual(last["argv"][last["argv"].index("--shard") + 1], "2/2")
        self.assertEqual(chain.status(), 0)
        self.assert_nothing_more(chain, step1)
        self.assert_finishing_job(chain, finish1)
        with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
            self.assertEqual(len(f.read().splitlines()), 5, "2 rounds, 1 stop, 1 complete, 1 finish")

    def test_mpi_job_is_resubmitted(self):
        # the CI campaign with one sample per ensemble (8 runs): the array tests run all 16
        with open(os.path.join(ARGS.source, "reference", "campaigns", "ci.toml")) as f:
            text = re.sub(r"(?m)^samples = .*$", "samples = 1", f.read())
        chain = Chain(self, "mpi", text)
        chain.submit("mpi", "ci.toml")
        work, finish, step = self.submitted(chain, 0)
        self.assertEqual(script_of(work["argv"]), "campaign-mpi.sbatch")
        self.assertIsNone(option(work["argv"], "array"))
        p = chain.job(work, {"SLURM_JOB_ID": work["job"], "SLURM_CPUS_PER_TASK": 2})
        chain.wait_for_a_run(p, 0.2)
        jam = campaign_run_child(p.pid, self)  # the fake srun is jam (exec)
        # Held (SIGSTOP) so that it cannot finish the campaign while the test looks.
        os.kill(jam, signal.SIGSTOP)
        # A SIGTERM to the batch shell is not passed on: srun would SIGKILL the ranks.
        p.send_signal(signal.SIGTERM)
        time.sleep(0.5)
        self.assertIsNone(p.poll())
        self.assertFalse(signal_pending(jam, signal.SIGTERM))
        # --signal=TERM@300 (no B:): Slurm signals the job step's tasks, here jam.
        os.kill(jam, signal.SIGTERM)
        os.kill(jam, signal.SIGCONT)
        (rc, log), = chain.finish([p])
        self.assertEqual(rc, 130, log)
        self.assertIn("waiting for the job step", log)
        srun = chain.calls("srun")[-1]["argv"]
        self.assertEqual(srun[:1], ["--cpus-per-task=2"])
        self.assertEqual(srun[2:], ["campaign", "run", chain.file, "--jobs", "2"])
        self.assertEqual(chain.status(), 4)
        before = len(chain.calls("sbatch"))
        rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
        self.assertEqual(rc, 0, log)
        work1, finish1, step1 = self.submitted(chain, before)
        self.assertEqual(script_of(work1["argv"]), "campaign-mpi.sbatch")
        self.assertEqual(option(work1["argv"], "dependency"), f"afterany:{work['job']}")
        self.assertIsNone(option(work1["argv"], "array"))
        rc, log = chain.run_job(work1, {"SLURM_JOB_ID": work1["job"], "SLURM_CPUS_PER_TASK": 2})
        self.assertEqual(rc, 0, log)
        self.assertEqual(chain.status(), 0)
        self.assert_nothing_more(chain, step1)

    def test_chain_decisions_on_planted_states(self):
        chain = Chain(self, "planted")
        chain.submit("array", "ci.toml", "--array=0-1")
        work, finish, step = self.submitted(chain, 0)
        job = {"SLURM_JOB_ID": step["job"]}
        chain.state("array", "2 0 1\n")

        # A run failed (status 1), the other share done: nothing to resubmit, it stops.
        chain.state("share-1", f"{work['job']} 0\n")
        chain.state("share-2", f"{work['job']} 1\n")
        rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "1"})
        self.assertEqual(rc, 1, log)
        self.assertIn("a run failed", log)
        self.assertEqual(len(chain.calls("sbatch")), 3, log)
        self.assertEqual(chain.calls("scancel")[-1]["argv"], [str(finish["job"])])

        # Complete, every task succeeded: nothing more, the finishing job is left to run.
        chain.state("share-2", f"{work['job']} 0\n")
        rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "0"})
        self.assertEqual(rc, 0, log)
        self.assertEqual(len(chain.calls("sbatch")), 3, log)
        self.assertEqual(len(chain.calls("scancel")), 1, log)

        # A record of another job (an earlier round) is no record: that share goes again.
        chain.state("share-2", f"{work['job'] - 1} 0\n")
        rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "4"})
        self.assertEqual(rc, 0, log)
        resubmitted, _, _ = self.submitted(chain, 3)
        self.assertEqual(option(resubmitted["argv"], "array"), "1")
        self.assertEqual(resubmitted["env"]["JAM_SLURM_SHARES"], "2")

        # Every task done, yet runs missing: every share again.
        chain.state("share-2", f"{work['job']} 0\n")
        rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "4"})
        self.assertEqual(rc, 0, log)
        resubmitted, _, _ = self.submitted(chain, 6)
        self.assertEqual(option(resubmitted["argv"], "array"), "0,1")

        # Not a campaign directory: an error, nothing submitted.
        rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "2"})
        self.assertEqual(rc, 2, log)
        self.assertEqual(len(chain.calls("sbatch")), 9, log)

    def test_output_hidden_in_a_multi_line_string_is_not_taken(self):
        chain = Chain(self, "hidden")
        decoy = os.path.join(chain.dir, "decoy")
        os.makedirs(os.path.join(decoy, "slurm"))
        planted = ["array", "share-1", "mpi"]
        for name in planted:
            with open(os.path.join(decoy, "slurm", name), "w") as f:
                f.write("1 0\n")
        with open(chain.file) as f:
            text = f.read()
        # A valid campaign file: the line-ending backslashes make the string one line for TOML
        # ("zeta: a note output = ... # "), while a line regex sees a top-level output key first.
        quotes = '"' * 3
        hidden = (f'expected_failures = [{quotes}zeta: a note \\\n'
                  f'output = "{decoy}" # \\\n'
                  f'{quotes}]\n')
        text = text.replace('output = "runs/ci"', hidden + 'output = "runs/ci"')
        with open(chain.file, "w") as f:
            f.write(text)
        self.assertIn(f'\noutput = "{decoy}" # \\\n', text)
        plan = subprocess.run([self.jam, "campaign", "plan", chain.file], cwd=chain.dir,
                              capture_output=True, text=True, timeout=120)
        self.assertEqual(plan.returncode, 0, "jam reads it as a campaign: " + plan.stderr)

        r = chain.submit("array", "ci.toml", "--array=0-1")
        for name in planted:
            self.assertTrue(os.path.exists(os.path.join(decoy, "slurm", name)),
                            f"submit.sh removed the decoy's {name}: {r.stdout}{r.stderr}")
        self.assertTrue(os.path.exists(os.path.join(chain.campaign_dir, "slurm", "chain.log")))
        work, finish, step = self.submitted(chain, 0)
        for call in (work, finish, step):
            self.assertEqual(call["env"]["JAM_CAMPAIGN_DIR"], chain.campaign_dir)

        # The finishing job judges the real directory (incomplete: it stops there).
        jam_before = len(chain.calls("jam"))
        rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]})
        self.assertEqual(rc, 1, log)
        self.assertIn("campaign not complete", log)
        self.assertEqual([c["argv"] for c in chain.calls("jam")[jam_before:]],
                         [["campaign", "output", chain.file],
                          ["campaign", "status", chain.campaign_dir]], log)

        # A job told another directory than jam's refuses before doing anything.
        jam_before = len(chain.calls("jam"))
        rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]},
                                env={"JAM_CAMPAIGN_DIR": decoy})
        self.assertEqual(rc, 2, log)
        self.assertIn(f"JAM_CAMPAIGN_DIR '{decoy}' is not the output of", log)
        self.assertEqual([c["argv"][:2] for c in chain.calls("jam")[jam_before:]],
                         [["campaign", "output"]], log)


class Headers(unittest.TestCase):
    def read(self, name):
        with open(os.path.join(ARGS.scripts, name)) as f:
            return f.read()

    def test_signal_lines(self):
        # jam runs in the array task's batch step: only B: reaches it (through the script).
        self.assertRegex(self.read("campaign-array.sbatch"), r"(?m)^#SBATCH --signal=B:TERM@\d+$")
        # srun turns a SIGTERM of its own into SIGKILL of the ranks: the job step is signalled.
        self.assertRegex(self.read("campaign-mpi.sbatch"), r"(?m)^#SBATCH --signal=TERM@\d+$")

    def test_strict_mode_and_no_eval(self):
        for name in sorted(os.listdir(ARGS.scripts)):
            text = self.read(name)
            if name.endswith((".sh", ".sbatch")) and name != "common.sh":
                self.assertIn("\nset -euo pipefail\n", text, name)
            self.assertNotRegex(text, r"(?m)^[^#]*\beval\b", name)


class ShellCheck(unittest.TestCase):
    @unittest.skipUnless(shutil.which("shellcheck"), "shellcheck is not installed")
    def test_scripts_are_shellcheck_clean(self):
        names = sorted(n for n in os.listdir(ARGS.scripts) if n.endswith((".sh", ".sbatch")))
        self.assertIn("submit.sh", names)
        r = subprocess.run(["shellcheck", "-x", "-s", "bash", *names], cwd=ARGS.scripts,
                           capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)


def main():
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jam", required=True, help="the jam executable")
    parser.add_argument("--source", required=True, help="the source tree")
    parser.add_argument("--scripts", help="the scripts (default: SOURCE/scripts/slurm)")
    ARGS, rest = parser.parse_known_args()
    ARGS.jam = os.path.abspath(ARGS.jam)
    ARGS.source = os.path.abspath(ARGS.source)
    ARGS.scripts = os.path.abspath(ARGS.scripts or os.path.join(ARGS.source, "scripts", "slurm"))
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)


if __name__ == "__main__":
    main()
