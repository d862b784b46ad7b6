#!/usr/bin/python3
"""The fake Slurm that the Slurm script tests share (test_slurm_scripts.py, test_slurm_resources.py).

`sbatch`, `srun`, `scancel`, `scontrol` and `sinfo` are fakes on PATH that record their arguments
(and the JAM* environment a job would inherit) in calls.jsonl; sbatch hands out job ids, srun runs
its command, sinfo prints FAKE_SINFO (unset: it fails as without a controller). A Chain is one fake
cluster with a copy of the CI campaign; the tests play Slurm by running the recorded jobs with the
variables Slurm would set. jam as the jobs see it records its commands; `check` and `report` are
recorded, not run. A Cluster (a test module's fixture) holds the fake tools and a copy of jam.
"""

import json
import os
import re
import shutil
import signal
import stat
import subprocess
import time

FAKE_SBATCH = r'''#!/usr/bin/python3
import fcntl, json, os, sys
d = os.environ["FAKE_SLURM_DIR"]
with open(os.path.join(d, "lock"), "a+") as lock:
    fcntl.flock(lock, fcntl.LOCK_EX)
    if "--test-only" in sys.argv[1:]:  # submits nothing: recorded apart, every request fits
        with open(os.path.join(d, "calls.jsonl"), "a") as f:
            f.write(json.dumps({"tool": "sbatch --test-only", "argv": sys.argv[1:]}) + "\n")
        print("sbatch: Job 1 to start now", file=sys.stderr)
        sys.exit(0)
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

# sinfo: prints FAKE_SINFO (lines as `sinfo -h -N -o "%P %c %m %l"` prints them); unset, it fails
# as sinfo does without a controller.
FAKE_SINFO = r'''#!/usr/bin/python3
import fcntl, json, os, sys
d = os.environ["FAKE_SLURM_DIR"]
with open(os.path.join(d, "lock"), "a+") as lock:
    fcntl.flock(lock, fcntl.LOCK_EX)
    with open(os.path.join(d, "calls.jsonl"), "a") as f:
        f.write(json.dumps({"tool": "sinfo", "argv": sys.argv[1:]}) + "\n")
if "FAKE_SINFO" not in os.environ:
    sys.exit("slurm_load_partitions: Unable to contact slurm controller (connect failure)")
print(os.environ["FAKE_SINFO"])
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

    def __init__(self, cluster, name, campaign_text=None):
        self.cluster = cluster
        self.dir = os.path.join(cluster.tmp, name)
        os.makedirs(self.dir)
        self.campaign_dir = os.path.join(self.dir, "runs", "ci")
        if campaign_text is None:
            with open(os.path.join(cluster.source, "reference", "campaigns", "ci.toml")) as f:
                campaign_text = f.read()
        text = campaign_text
        # relative output: the jobs run in the submit directory, as under Slurm
        text = re.sub(r'(?m)^output = .*$', 'output = "runs/ci"', text)
        self.file = os.path.join(self.dir, "ci.toml")
        with open(self.file, "w") as f:
            f.write(text)
        self.env = {"PATH": f"{cluster.bin}:/usr/bin:/bin", "HOME": self.dir, "LANG": "C.UTF-8",
                    "FAKE_SLURM_DIR": self.dir, "REAL_JAM": cluster.jam,
                    "JAM": os.path.join(cluster.bin, "jam")}

    def calls(self, tool=None):
        path = os.path.join(self.dir, "calls.jsonl")
        if not os.path.exists(path):
            return []
        with open(path) as f:
            calls = [json.loads(line) for line in f]
        return [c for c in calls if tool is None or c["tool"] == tool]

    def submit(self, *args, expect=0):
        r = subprocess.run([os.path.join(self.cluster.scripts, "submit.sh"), *args], cwd=self.dir,
                           env=self.env, capture_output=True, text=True, timeout=60)
        assert r.returncode == expect, r.stdout + r.stderr
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
        self.cluster.logs.append(log)  # finish() closes it; the cluster, when a test fails first
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
            assert p.poll() is None, "the job ended before any run started"
            assert time.time() - started < 60, "no run started"
            time.sleep(0.05)
        time.sleep(then)
        assert p.poll() is None, "the job ended before the signal"

    def finish(self, procs):
        """Waits for the processes (SIGTERM to those asked for, once a run is under way);
        returns (exit status, log) of each."""
        for p in procs:
            if p.term_after is not None:
                self.wait_for_a_run(p, p.term_after)
                # jam is held (SIGSTOP) until the script has passed the SIGTERM on, so the
                # signal cannot come after jam finished its last run on a fast machine.
                jam = campaign_run_child(p.pid)
                os.kill(jam, signal.SIGSTOP)
                p.send_signal(signal.SIGTERM)
                deadline = time.time() + 30
                while not signal_pending(jam, signal.SIGTERM):
                    assert time.time() < deadline, "SIGTERM not passed on"
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
        return subprocess.run([self.cluster.jam, "campaign", "status", self.campaign_dir],
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


def catches(pid, sig):
    """Whether process pid has a handler installed for signal sig."""
    with open(f"/proc/{pid}/status") as f:
        masks = [int(line.split()[1], 16) for line in f if line.startswith("SigCgt:")]
    return any(m >> (sig - 1) & 1 for m in masks)


def campaign_run_child(pid):
    """The one child of pid that runs the campaign (an argument `run`), once it is there and
    catches SIGTERM. The scripts first ask `jam campaign output`, a child of their own that must
    not be taken for it (a SIGSTOP there would hold the wrong process). Until jam has installed
    its handler the child may still be the Python wrapper before its exec, or jam starting up:
    a SIGTERM passed on there is fatal even to a stopped process (the kernel ends it at once),
    so it would never be seen pending. On a loaded machine the other array task can start the
    first run while this one is still there."""
    deadline = time.time() + 60
    while True:
        runs = []
        for child in children(pid):
            try:
                with open(f"/proc/{child}/cmdline", "rb") as f:
                    if b"run" in f.read().split(b"\0") and catches(child, signal.SIGTERM):
                        runs.append(child)
            except OSError:
                continue
        if len(runs) == 1:
            return runs[0]
        assert time.time() < deadline, f"no single campaign run under {pid}: {runs}"
        time.sleep(0.01)


def option(argv, name):
    """The value of --name=value in argv (None when absent)."""
    values = [a.split("=", 1)[1] for a in argv if a.startswith(f"--{name}=")]
    return values[-1] if values else None


def script_of(argv):
    return os.path.basename(next(a for a in argv if a.endswith(".sbatch")))


class Cluster:
    """The fake cluster's tools and a copy of jam, shared by a module's tests (its `cluster`
    fixture); close() ends it."""

    def __init__(self, jam, source, tmp):
        self.tmp = str(tmp)
        self.source = str(source)
        self.scripts = os.path.join(self.source, "scripts", "slurm")
        self.logs = []  # the jobs' logs, closed at the end when a test failed before finish()
        self.bin = os.path.join(self.tmp, "bin")
        os.makedirs(self.bin)
        write_executable(os.path.join(self.bin, "sbatch"), FAKE_SBATCH)
        for tool in ("srun", "scancel", "scontrol"):
            write_executable(os.path.join(self.bin, tool), FAKE_TOOL)
        write_executable(os.path.join(self.bin, "sinfo"), FAKE_SINFO)
        write_executable(os.path.join(self.bin, "jam"), JAM_WRAPPER)
        # a copy: a rebuild of the build tree meanwhile does not pull it away under the jobs
        self.jam = shutil.copy2(jam, os.path.join(self.tmp, "jam-under-test"))

    def close(self):
        for log in self.logs:
            log.close()


def submitted(chain, before):
    """The sbatch calls since `before` of them, as (work, finish, chain step)."""
    new = chain.calls("sbatch")[before:]
    assert [script_of(c["argv"]) for c in new][1:] == \
        ["campaign-finish.sbatch", "campaign-chain.sbatch"], \
        "a round is the work job, the finishing job and the chain step"
    work, finish, step = new
    assert option(finish["argv"], "dependency") == f"afterok:{work['job']}"
    assert option(step["argv"], "dependency") == f"afterany:{work['job']}"
    assert step["env"]["JAM_SLURM_WORK_JOB"] == str(work["job"])
    assert step["env"]["JAM_SLURM_FINISH_JOB"] == str(finish["job"])
    return work, finish, step


def assert_finishing_job(chain, finish):
    jam_before = len(chain.calls("jam"))
    rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]})
    assert rc == 0, log
    commands = [c["argv"] for c in chain.calls("jam")[jam_before:]]
    assert commands == [["campaign", "output", chain.file],
                        ["campaign", "status", chain.campaign_dir],
                        ["stats", chain.campaign_dir],
                        ["check", "all", chain.campaign_dir],
                        ["report", chain.campaign_dir]], log
    assert os.path.exists(os.path.join(chain.campaign_dir, "stats.h5")), log


def assert_nothing_more(chain, step):
    sbatch_before, cancel_before = len(chain.calls("sbatch")), len(chain.calls("scancel"))
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
    assert rc == 0, log
    assert "campaign complete" in log
    assert len(chain.calls("sbatch")) == sbatch_before, "submitted more: " + log
    assert len(chain.calls("scancel")) == cancel_before, log
