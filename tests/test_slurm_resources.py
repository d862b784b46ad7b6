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

Usage (ctest runs it): python3 -m pytest tests/test_slurm_resources.py --jam build/jam --source .
"""

import os

import pytest

import slurm_fixture as fx
from slurm_fixture import Chain, option, script_of, submitted

# One partition "debug" (the default) of one 2-CPU node with 1900 MB and a 1 h limit, and a
# partition "big" of a 64-CPU node without a time limit.
SMALL_NODE = "debug* 2 1900 1:00:00"
TWO_PARTITIONS = SMALL_NODE + "\nbig 64 256000 infinite"


@pytest.fixture(scope="module")
def cluster(jam, source, tmp_path_factory):
    cluster = fx.Cluster(jam, source, tmp_path_factory.mktemp("slurm"))
    yield cluster
    cluster.close()


# The finishing job's resources.


def finish_call(chain):
    work, finish, step = submitted(chain, 0)
    assert script_of(finish["argv"]) == "campaign-finish.sbatch"
    return work, finish, step


def test_default_fits_any_node(cluster):
    chain = Chain(cluster, "default")
    r = chain.submit("array", "ci.toml", "--array=0-1")
    work, finish, step = finish_call(chain)
    assert option(finish["argv"], "cpus-per-task") == "1"
    assert option(finish["argv"], "time") == "04:00:00"
    assert option(finish["argv"], "mem") is None
    assert "not checked against the partition (no answer from sinfo)" in r.stdout
    with open(os.path.join(cluster.scripts, "campaign-finish.sbatch")) as f:
        header = f.read()
    assert "\n#SBATCH --cpus-per-task=1\n" in header
    assert "\n#SBATCH --mem" not in header


def test_work_job_request_is_taken(cluster):
    chain = Chain(cluster, "derived")
    chain.submit("array", "ci.toml", "--array=0-1", "-c", "2", "--mem=1500M")
    work, finish, step = finish_call(chain)
    assert option(finish["argv"], "cpus-per-task") == "2"
    assert option(finish["argv"], "mem") == "1500M"


def test_given_resources_are_kept_by_the_chain(cluster):
    chain = Chain(cluster, "given")
    chain.submit("array", "ci.toml", "--finish-cpus", "3", "--array=0-1",
                 "--finish-mem=2G", "--finish-time", "00:30:00")
    work, finish, step = finish_call(chain)
    assert [a for a in work["argv"] if "finish" in a] == [], work["argv"]
    wanted = {"cpus-per-task": "3", "mem": "2G", "time": "00:30:00"}
    assert {k: option(finish["argv"], k) for k in wanted} == wanted
    with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
        assert (f"finishing job {finish['job']} (afterok; --cpus-per-task=3 "
                "--time=00:30:00 --mem=2G)") in f.read()

    # Share 2 never ran: the chain step's next round keeps the finishing job's resources.
    chain.state("array", "2 0 1\n")
    chain.state("share-1", f"{work['job']} 0\n")
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]}, env={"FAKE_JAM_STATUS": "4"})
    assert rc == 0, log
    _, finish1, step1 = submitted(chain, 3)
    assert {k: option(finish1["argv"], k) for k in wanted} == wanted

    # Every run done, yet a task recorded nothing: the replacement keeps them as well, and
    # the chain log says which job finishes and how to see its state.
    rc, log = chain.run_job(step1, {"SLURM_JOB_ID": step1["job"]},
                            env={"FAKE_JAM_STATUS": "0"})
    assert rc == 0, log
    replacement = chain.calls("sbatch")[-1]
    assert script_of(replacement["argv"]) == "campaign-finish.sbatch"
    assert option(replacement["argv"], "dependency") is None
    assert {k: option(replacement["argv"], k) for k in wanted} == wanted
    with open(os.path.join(chain.campaign_dir, "slurm", "chain.log")) as f:
        last = f.read().splitlines()[-1]
    job = replacement["job"]
    assert f"finishing job {job} submitted in place of {finish1['job']}" in last
    assert (f"its state: squeue -j {job} (if it stays pending with reason PartitionConfig, "
            "it can never start as asked:") in last
    assert f"sacct -j {job} once it ended" in last


def test_complete_campaign_names_the_finishing_job_state(cluster):
    chain = Chain(cluster, "complete")
    chain.submit("array", "ci.toml", "--array=0-1")
    work, finish, step = finish_call(chain)
    chain.state("array", "2 0 1\n")
    for k in (1, 2):
        chain.state(f"share-{k}", f"{work['job']} 0\n")
    rc, log = chain.run_job(step, {"SLURM_JOB_ID": step["job"]}, env={"FAKE_JAM_STATUS": "0"})
    assert rc == 0, log
    assert (f"finishing job {finish['job']} makes the statistics, checks and report; "
            f"its state: squeue -j {finish['job']}") in log


# Requests no node meets.


def refused(chain, args, message, env=None):
    """submit.sh refuses in one line with message; nothing submitted, nothing written."""
    chain.env.update(env or {})
    r = chain.submit("array", "ci.toml", "--array=0-1", *args, expect=2)
    assert r.stderr == f"jam-slurm: error: {message}\n", args
    assert chain.calls("sbatch") == [], args
    assert not os.path.exists(os.path.join(chain.campaign_dir, "slurm")), args

NEVER = "the job could never start"
WHERE = "partition debug (sinfo)"
IMPOSSIBLE = [
    (["--finish-cpus", "4"], f"--finish-cpus 4: no node of {WHERE} has more than 2 CPUs: {NEVER}"),
    (["--finish-mem=16G"], f"--finish-mem 16G: no node of {WHERE} has more than 1900 MB of "
                           f"memory: {NEVER}"),
    (["--finish-time", "02:00:00"], f"--finish-time 02:00:00: the time limit of {WHERE} is 60 "
                                    f"minutes: {NEVER}"),
    (["-c", "4"], f"--cpus-per-task 4: no node of {WHERE} has more than 2 CPUs: {NEVER}"),
    (["--mem", "2G"], f"--mem 2G: no node of {WHERE} has more than 1900 MB of memory: {NEVER}"),
    (["--time=1-0"], f"--time 1-0: the time limit of {WHERE} is 60 minutes: {NEVER}"),
    (["--finish-mem", "16GB"], "--finish-mem '16GB' must be a whole number with an optional K, "
                               "M, G or T suffix"),
    (["--finish-cpus=0"], "--finish-cpus '0' must be a whole number >= 1"),
    (["--finish-time", "1h"], "--finish-time '1h' is not a Slurm time (minutes, H:M:S or "
                              "D-H:M:S)"),
    (["--finish-gpus", "1"], "--finish-gpus: unknown (--finish-cpus, --finish-mem, "
                             "--finish-time)"),
]


@pytest.mark.parametrize("k", range(len(IMPOSSIBLE)), ids=[" ".join(a) for a, _ in IMPOSSIBLE])
def test_each_impossible_request_is_named(cluster, k):
    args, message = IMPOSSIBLE[k]
    chain = Chain(cluster, f"impossible-{k}")
    chain.env["FAKE_SINFO"] = SMALL_NODE
    refused(chain, args, message)


def test_fitting_request_goes_with_the_partition_limit(cluster):
    chain = Chain(cluster, "fits")
    chain.env["FAKE_SINFO"] = SMALL_NODE
    r = chain.submit("array", "ci.toml", "--array=0-1", "-c", "2", "--finish-mem", "1900M")
    assert "checked against partition debug (sinfo)" in r.stdout
    work, finish, step = submitted(chain, 0)
    # the default 04:00:00 is longer than the partition allows: its limit, in minutes
    assert option(finish["argv"], "time") == "60"
    assert option(finish["argv"], "cpus-per-task") == "2"
    assert option(finish["argv"], "mem") == "1900M"


def test_each_job_is_judged_in_its_partition(cluster):
    # The work job's --partition is its own; the finishing job goes to SBATCH_PARTITION or
    # the default, so the work job's 32 CPUs, its default, cannot follow it there.
    chain = Chain(cluster, "partitions")
    chain.env["FAKE_SINFO"] = TWO_PARTITIONS
    refused(chain, ["--partition=big", "-c", "32"],
                 "--finish-cpus (by default the work job's -c) 32: no node of partition "
                 "debug (sinfo) has more than 2 CPUs: the job could never start")
    chain.submit("array", "ci.toml", "--array=0-1", "--partition=big", "-c", "32",
                 "--finish-cpus", "1")
    assert option(submitted(chain, 0)[1]["argv"], "cpus-per-task") == "1"
    other = Chain(cluster, "partitions-env")
    other.env.update({"FAKE_SINFO": TWO_PARTITIONS, "SBATCH_PARTITION": "big"})
    other.submit("array", "ci.toml", "--array=0-1", "-c", "32")
    work, finish, step = submitted(other, 0)
    assert option(finish["argv"], "cpus-per-task") == "32"
    assert option(finish["argv"], "time") == "04:00:00"
