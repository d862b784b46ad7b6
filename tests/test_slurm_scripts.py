#!/usr/bin/python3
"""The batch scripts of scripts/slurm/ run as far as a machine without Slurm allows.

`sbatch`, `srun`, `scancel` and `scontrol` are fakes on PATH (slurm_fixture.py, shared with
test_slurm_resources.py) that record their arguments (and the JAM* environment a job would
inherit) in calls.jsonl; sbatch hands out job ids, srun runs its command. The test then plays
Slurm: it runs each recorded job with the variables Slurm would
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

Usage (ctest runs it): python3 -m pytest tests/test_slurm_scripts.py --jam build/jam --source .
"""

import os
import re
import shutil
import signal
import subprocess
import time

import pytest

import slurm_fixture as fx
from slurm_fixture import (Chain, assert_finishing_job, assert_nothing_more, campaign_run_child,
                           option, script_of, signal_pending, submitted)


@pytest.fixture(scope="module")
def cluster(jam, source, tmp_path_factory):
    cluster = fx.Cluster(jam, source, tmp_path_factory.mktemp("slurm"))
    yield cluster
    cluster.close()


@pytest.fixture(scope="module")
def scripts(source):
    return source / "scripts" / "slurm"


def test_zero_based_array_completes(cluster):
    chain = Chain(cluster, "zero-based")
    chain.submit("array", "ci.toml", "--array=0-1")
    work, finish, step = submitted(chain, 0)
    assert script_of(work["argv"]) == "campaign-array.sbatch"
    assert option(work["argv"], "array") == "0-1"
    assert option(work["argv"], "dependency") is None
    # task 1 runs as sbatch runs scripts: a copy in a spool directory, found back by scontrol
    spool = os.path.join(chain.dir, "spool")
    os.makedirs(spool)
    copy = shutil.copy(os.path.join(cluster.scripts, "campaign-array.sbatch"), spool)
    real = next(a for a in work["argv"] if a.endswith(".sbatch"))
    ids, procs = chain.array_tasks(work, {1: {"script": copy, "env": {
        "JAM_SLURM_DIR": None, "FAKE_SCONTROL_COMMAND": real}}})
    results = chain.finish(procs)
    for rc, log in results:
        assert rc == 0, log
    assert chain.calls("scontrol"), "the spool copy asked scontrol for its script"
    runs = [c for c in chain.calls("jam") if c["argv"][:2] == ["campaign", "run"]]
    assert sorted((c["task"], c["argv"][c["argv"].index("--shard") + 1])
                  for c in runs) == [("0", "auto"), ("1", "auto")]
    assert chain.status() == 0, "the two tasks together complete the campaign"
    assert_nothing_more(chain, step)
    assert_finishing_job(chain, finish)


def test_interrupted_task_is_resubmitted(cluster):
    chain = Chain(cluster, "one-based")
    chain.submit("array", "ci.toml", "--array=1-3:2", "--time=00:30:00",
                 "--", "--log-every", "5")
    work, finish, step = submitted(chain, 0)
    assert work["argv"][-3:] == [chain.file, "--log-every", "5"]
    ids, procs = chain.array_tasks(work, {3: {"term_after": 0.2}})
    assert ids == [1, 3]
    (rc1, log1), (rc3, log3) = chain.finish(procs)
    assert rc1 == 0, log1
    assert rc3 == 130, "SIGTERM: jam checkpoints and exits 130\n" + log3
    assert "interrupted" in log3
    assert chain.status() == 4, "share 2 is unfinished"

    # At the maximum number of resubmissions: stops, says so, submits nothing.
    before = len(chain.calls("sbatch"))
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]},
                            env={"JAM_SLURM_MAX_RESUBMIT": "0"})
    assert rc == 1, log
    assert "maximum of 0 resubmissions" in log
    assert len(chain.calls("sbatch")) == before, log
    assert ["{}".format(finish["job"])] in [c["argv"] for c in chain.calls("scancel")]

    # The chain step resubmits index 3 alone, after the array job, with the options kept.
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
    assert rc == 0, log
    work1, finish1, step1 = submitted(chain, before)
    assert script_of(work1["argv"]) == "campaign-array.sbatch"
    assert option(work1["argv"], "array") == "3"
    assert option(work1["argv"], "dependency") == f"afterany:{work['job']}"
    assert option(work1["argv"], "time") == "00:30:00"
    assert work1["argv"][-3:] == [chain.file, "--log-every", "5"]
    assert step1["env"]["JAM_SLURM_ROUND"] == "1"

    # Slurm numbers the new array alone (1 task from 3); the share stays 2 of 2.
    ids, procs = chain.array_tasks(work1)
    (rc, log), = chain.finish(procs)
    assert rc == 0, log
    last = [c for c in chain.calls("jam") if c["argv"][:2] == ["campaign", "run"]][-1]
    assert last["argv"][last["argv"].index("--shard") + 1] == "2/2"
    assert chain.status() == 0
    assert_nothing_more(chain, step1)
    assert_finishing_job(chain, finish1)
    with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
        assert len(f.read().splitlines()) == 5, "2 rounds, 1 stop, 1 complete, 1 finish"


def test_mpi_job_is_resubmitted(cluster):
    # the CI campaign with one sample per ensemble (8 runs): the array tests run all 16
    with open(os.path.join(cluster.source, "reference", "campaigns", "ci.toml")) as f:
        text = re.sub(r"(?m)^samples = .*$", "samples = 1", f.read())
    chain = Chain(cluster, "mpi", text)
    chain.submit("mpi", "ci.toml")
    work, finish, step = submitted(chain, 0)
    assert script_of(work["argv"]) == "campaign-mpi.sbatch"
    assert option(work["argv"], "array") is None
    p = chain.job(work, {"SLURM_JOB_ID": work["job"], "SLURM_CPUS_PER_TASK": 2})
    chain.wait_for_a_run(p, 0.2)
    jam = campaign_run_child(p.pid)  # the fake srun is jam (exec)
    # Held (SIGSTOP) so that it cannot finish the campaign while the test looks.
    os.kill(jam, signal.SIGSTOP)
    # A SIGTERM to the batch shell is not passed on: srun would SIGKILL the ranks.
    p.send_signal(signal.SIGTERM)
    time.sleep(0.5)
    assert p.poll() is None
    assert not signal_pending(jam, signal.SIGTERM)
    # --signal=TERM@300 (no B:): Slurm signals the job step's tasks, here jam.
    os.kill(jam, signal.SIGTERM)
    os.kill(jam, signal.SIGCONT)
    (rc, log), = chain.finish([p])
    assert rc == 130, log
    assert "waiting for the job step" in log
    srun = chain.calls("srun")[-1]["argv"]
    assert srun[:1] == ["--cpus-per-task=2"]
    assert srun[2:] == ["campaign", "run", chain.file, "--jobs", "2"]
    assert chain.status() == 4
    before = len(chain.calls("sbatch"))
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]})
    assert rc == 0, log
    work1, finish1, step1 = submitted(chain, before)
    assert script_of(work1["argv"]) == "campaign-mpi.sbatch"
    assert option(work1["argv"], "dependency") == f"afterany:{work['job']}"
    assert option(work1["argv"], "array") is None
    rc, log = chain.run_job(work1, {"SLURM_JOB_ID": work1["job"], "SLURM_CPUS_PER_TASK": 2})
    assert rc == 0, log
    assert chain.status() == 0
    assert_nothing_more(chain, step1)


def test_chain_decisions_on_planted_states(cluster):
    chain = Chain(cluster, "planted")
    chain.submit("array", "ci.toml", "--array=0-1")
    work, finish, step = submitted(chain, 0)
    job = {"SLURM_JOB_ID": step["job"]}
    chain.state("array", "2 0 1\n")

    # A run failed (status 1), the other share done: nothing to resubmit, it stops.
    chain.state("share-1", f"{work['job']} 0\n")
    chain.state("share-2", f"{work['job']} 1\n")
    rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "1"})
    assert rc == 1, log
    assert "a run failed" in log
    assert len(chain.calls("sbatch")) == 3, log
    assert chain.calls("scancel")[-1]["argv"] == [str(finish["job"])]

    # Complete, every task succeeded: nothing more, the finishing job is left to run.
    chain.state("share-2", f"{work['job']} 0\n")
    rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "0"})
    assert rc == 0, log
    assert len(chain.calls("sbatch")) == 3, log
    assert len(chain.calls("scancel")) == 1, log

    # A record of another job (an earlier round) is no record: that share goes again.
    chain.state("share-2", f"{work['job'] - 1} 0\n")
    rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "4"})
    assert rc == 0, log
    resubmitted, _, _ = submitted(chain, 3)
    assert option(resubmitted["argv"], "array") == "1"
    assert resubmitted["env"]["JAM_SLURM_SHARES"] == "2"

    # Every task done, yet runs missing: every share again.
    chain.state("share-2", f"{work['job']} 0\n")
    rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "4"})
    assert rc == 0, log
    resubmitted, _, _ = submitted(chain, 6)
    assert option(resubmitted["argv"], "array") == "0,1"

    # Not a campaign directory: an error, nothing submitted.
    rc, log = chain.run_job(step, job, env={"FAKE_JAM_STATUS": "2"})
    assert rc == 2, log
    assert len(chain.calls("sbatch")) == 9, log


def test_output_hidden_in_a_multi_line_string_is_not_taken(cluster):
    chain = Chain(cluster, "hidden")
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
    assert f'\noutput = "{decoy}" # \\\n' in text
    plan = subprocess.run([cluster.jam, "campaign", "plan", chain.file], cwd=chain.dir,
                          capture_output=True, text=True, timeout=120)
    assert plan.returncode == 0, "jam reads it as a campaign: " + plan.stderr

    r = chain.submit("array", "ci.toml", "--array=0-1")
    for name in planted:
        assert os.path.exists(os.path.join(decoy, "slurm", name)), \
            f"submit.sh removed the decoy's {name}: {r.stdout}{r.stderr}"
    assert os.path.exists(os.path.join(chain.campaign_dir, "slurm", "chain.log"))
    work, finish, step = submitted(chain, 0)
    for call in (work, finish, step):
        assert call["env"]["JAM_CAMPAIGN_DIR"] == chain.campaign_dir

    # The finishing job judges the real directory (incomplete: it stops there).
    jam_before = len(chain.calls("jam"))
    rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]})
    assert rc == 1, log
    assert "campaign not complete" in log
    assert [c["argv"] for c in chain.calls("jam")[jam_before:]] == \
        [["campaign", "output", chain.file], ["campaign", "status", chain.campaign_dir]], log

    # A job told another directory than jam's refuses before doing anything.
    jam_before = len(chain.calls("jam"))
    rc, log = chain.run_job(finish, {"SLURM_JOB_ID": finish["job"]},
                            env={"JAM_CAMPAIGN_DIR": decoy})
    assert rc == 2, log
    assert f"JAM_CAMPAIGN_DIR '{decoy}' is not the output of" in log
    assert [c["argv"][:2] for c in chain.calls("jam")[jam_before:]] == [["campaign", "output"]], \
        log


def read(scripts, name):
    with open(scripts / name) as f:
        return f.read()


def test_signal_lines(scripts):
    # jam runs in the array task's batch step: only B: reaches it (through the script).
    assert re.search(r"(?m)^#SBATCH --signal=B:TERM@\d+$",
                     read(scripts, "campaign-array.sbatch"))
    # srun turns a SIGTERM of its own into SIGKILL of the ranks: the job step is signalled.
    assert re.search(r"(?m)^#SBATCH --signal=TERM@\d+$", read(scripts, "campaign-mpi.sbatch"))


def test_strict_mode_and_no_eval(scripts):
    for name in sorted(os.listdir(scripts)):
        text = read(scripts, name)
        # common.sh and resources.sh are sourced by scripts that set it, never run
        if name.endswith((".sh", ".sbatch")) and name not in ("common.sh", "resources.sh"):
            assert "\nset -euo pipefail\n" in text, name
        assert not re.search(r"(?m)^[^#]*\beval\b", text), name


@pytest.mark.skipif(not shutil.which("shellcheck"), reason="shellcheck is not installed")
def test_scripts_are_shellcheck_clean(scripts):
    names = sorted(n for n in os.listdir(scripts) if n.endswith((".sh", ".sbatch")))
    assert "submit.sh" in names
    r = subprocess.run(["shellcheck", "-x", "-s", "bash", *names], cwd=scripts,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
