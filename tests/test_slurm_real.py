"""scripts/slurm/ against a real single-node Slurm (slurm_real_cluster.py: Debian's slurmctld,
slurmd and munge, configured and ended by the test; skipped, saying why, when they are not
installed or the test is not root).

Three chains of submit.sh run side by side, each in a directory of its own:
  - the array job (2 tasks) on the CI campaign, its finishing job and chain step: the campaign
    completes and its statistics, checks and report exist; the header's 24 h is cut to the
    partition's limit, never left to pend;
  - the MPI job (srun, PMIx, OpenMPI) on the CI campaign: one campaign shared by the node's
    ranks, none refused by another's lock;
  - a task with the shortest limit Slurm has (--time=1, one minute) on a larger copy of the CI
    campaign: its time limit stops it (jam checkpoints), the chain step resubmits it, and the
    campaign completes without a run done before being written again.
And requests that can never be met are refused by submit.sh, naming the option (sbatch
--test-only), with nothing submitted.
"""

import os
import re
import subprocess
import time

import pytest

import slurm_real_cluster

PARTITION_MINUTES = 30  # the partition's MaxTime: the headers' 24:00:00 cannot go there


@pytest.fixture(scope="module")
def cluster():
    missing = slurm_real_cluster.missing_tools()
    if missing:
        pytest.skip(f"needs Slurm and munge ({' '.join(missing)} missing): setup.sh --tests")
    if os.geteuid() != 0:
        pytest.skip("needs root: slurmd starts each job as its user")
    c = slurm_real_cluster.start(PARTITION_MINUTES)
    yield c
    c.stop()


class Chain:
    """One submit.sh chain in a directory of its own, on a copy of the CI campaign."""

    def __init__(self, cluster, jam, source, root, name, *options, keys=None):
        self.cluster = cluster
        self.dir = root / name
        self.dir.mkdir()
        text = (source / "reference" / "campaigns" / "ci.toml").read_text()
        text = re.sub(r"(?m)^output = .*$", 'output = "runs/ci"', text)
        for key, value in (keys or {}).items():  # the CI campaign's keys replaced
            text = re.sub(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
        (self.dir / "ci.toml").write_text(text)
        self.campaign = self.dir / "runs" / "ci"
        self.jam = jam
        self.started = time.time()
        r = cluster.run(str(source / "scripts" / "slurm" / "submit.sh"), *options, cwd=self.dir,
                        env={"JAM": str(jam), "JAM_REPORT_DIR": str(self.dir / "report")})
        self.submitted = r.stdout
        self.work_job = re.search(r"work job +(\d+)", r.stdout)[1]

    def log(self):
        path = self.campaign / "slurm" / "chain.log"
        return path.read_text() if path.exists() else ""

    def job_logs(self):
        return "\n".join(f"--- {p.name}\n{p.read_text(errors='replace')}"
                         for p in sorted(self.dir.glob("slurm-*.out")))

    def wait(self, seconds, until=None):
        """Waits until `until` (default: the chain has ended, its finishing job done or a
        stop logged, and no job of its directory is left); returns the seconds taken."""
        done = until or (lambda: ("statistics, checks" in self.log() or "stopped" in self.log())
                         and all(d != str(self.dir) for _, d in self.cluster.jobs().values()))
        deadline = time.time() + seconds
        while not done():
            assert time.time() < deadline, (f"not done in {seconds} s\n{self.log()}\n"
                                            f"{self.job_logs()}\n{self.cluster.logs()}")
            time.sleep(1)
        return time.time() - self.started

    def assert_complete(self):
        status = subprocess.run([str(self.jam), "campaign", "status", str(self.campaign)],
                                capture_output=True, text=True, timeout=60)
        assert status.returncode == 0, status.stdout + self.log() + self.job_logs()
        assert "campaign complete" in self.log(), self.log() + self.job_logs()
        assert "statistics, checks (jam check exit" in self.log(), self.log() + self.job_logs()
        for made in ("stats.h5", "checks.json"):
            assert (self.campaign / made).is_file(), made
        assert (self.dir / "report" / "index.html").is_file(), self.job_logs()


@pytest.fixture(scope="module")
def chains(cluster, jam, source, tmp_path_factory):
    """The three chains, submitted at once so that they share the wall time; the one with the
    time limit first, as it waits on the clock."""
    root = tmp_path_factory.mktemp("chains")
    # With --time=1 the header's warning (300 s before the limit) would come at once: 30 s
    # before it, so a round computes for 30 to 60 s (the controller looks every 30 s) before
    # jam checkpoints and stops. Work that outlasts a round on any machine, in runs short enough
    # that every round finishes some: 48 runs of N 512 and 1024 at 1e-4 and 10^-4.5, about
    # 2.6 CPU-seconds each (2026-11-29, 123 CPU-seconds in all; the CI campaign's 8 samples
    # took 8, finished inside the first round on a quiet machine and never met the limit).
    limited = Chain(cluster, jam, source, root, "time-limit", "array", "ci.toml", "--array=0",
                    "--cpus-per-task=1", "--time=1", "--signal=B:TERM@30",
                    keys={"sizes": "[512, 1024]", "log10_rates": "[-4.0, -4.5]", "samples": 6})
    array = Chain(cluster, jam, source, root, "array", "array", "ci.toml", "--array=0-1",
                  "--cpus-per-task=1")
    mpi = Chain(cluster, jam, source, root, "mpi", "mpi", "ci.toml")
    return {"time-limit": limited, "array": array, "mpi": mpi}


def time_limit(cluster, job):
    out = cluster.run("scontrol", "show", "job", job).stdout
    return re.search(r"TimeLimit=(\S+)", out)[1]


def test_array_chain_completes_within_the_partition(cluster, chains):
    chain = chains["array"]
    assert f"cut to the partition: --time={PARTITION_MINUTES}" in chain.submitted
    assert "and by Slurm (sbatch --test-only)" in chain.submitted
    assert time_limit(cluster, chain.work_job) == f"00:{PARTITION_MINUTES}:00"
    print(f"array chain: {chain.wait(300):.0f} s")
    chain.assert_complete()
    logs = chain.job_logs()
    assert "share 1 of 2 done" in logs and "share 2 of 2 done" in logs, logs


def test_mpi_chain_shares_one_campaign_between_ranks(cluster, chains):
    chain = chains["mpi"]
    # the header's 64 ranks are cut to the node's cores
    assert f"--ntasks={cluster.cpus}" in chain.submitted, chain.submitted
    print(f"MPI chain: {chain.wait(300):.0f} s")
    chain.assert_complete()
    logs = chain.job_logs()
    assert f"{cluster.cpus} ranks" in logs and "campaign run done" in logs, logs
    assert "in use by pid" not in logs, logs
    mpi = (chain.campaign / "slurm" / "mpi").read_text().split()
    assert mpi == [chain.work_job, "0"], logs


def done_runs(campaign):
    """{record name: (its text, mtime of its run file)} of the runs recorded done."""
    out = {}
    for record in (campaign / "runs").glob("*.record"):
        text = record.read_text()
        if "status = 'done'" in text:
            out[record.name] = (text, record.with_suffix(".h5").stat().st_mtime_ns)
    return out


def test_task_stopped_by_its_time_limit_is_resubmitted(cluster, chains):
    chain = chains["time-limit"]
    chain.wait(240, until=lambda: "round 1:" in chain.log())
    before = done_runs(chain.campaign)
    assert before, "round 0 finished no run before its time limit"
    print(f"time-limit chain: {chain.wait(720):.0f} s, {len(before)} runs done in round 0")
    chain.assert_complete()
    logs = chain.job_logs()
    assert "share 1 of 1 interrupted (checkpoints written)" in logs, logs
    assert "resubmission 1 of at most 10" in logs, logs
    after = done_runs(chain.campaign)
    assert {k: after.get(k) for k in before} == before, "a run done before was written again"


def refused(cluster, jam, source, tmp_path, mode, *options, env=None):
    """submit.sh's one-line refusal; nothing submitted and nothing written."""
    (tmp_path / "ci.toml").write_text((source / "reference" / "campaigns" / "ci.toml")
                                      .read_text().replace('output = "runs/ci"', 'output = "out"'))
    r = cluster.run(str(source / "scripts" / "slurm" / "submit.sh"), mode, "ci.toml", *options,
                    check=False, cwd=tmp_path, env={"JAM": str(jam), **(env or {})})
    assert r.returncode == 2, r.stdout + r.stderr
    assert all(d != str(tmp_path) for _, d in cluster.jobs().values()), r.stderr
    assert not (tmp_path / "out" / "slurm").exists()
    assert r.stdout == "" and r.stderr.count("\n") == 1, r.stderr
    return r.stderr


@pytest.mark.parametrize("mode,options,message", [
    # more tasks than the node has cores: sinfo's CPU count does not judge -n
    ("array", ["--array=0-1", "-n", "{too_many}"],
     "the work job: -n {too_many}: Slurm says 'Requested node configuration is not available'"),
    ("mpi", ["--ntasks={too_many}"],
     "the work job: --ntasks={too_many}: Slurm says 'Requested node configuration is not "
     "available'"),
    ("array", ["--array=0-1", "--gres=gpu:1"],
     "the work job: --gres=gpu:1: Slurm says 'Invalid generic resource (gres) specification'"),
    ("array", ["--array=0-1", "--partition=nosuch"],
     "--partition 'nosuch': sinfo lists no node of it"),
    ("array", ["--array=0-1", "--finish-cpus={too_many}"],
     "--finish-cpus {too_many}: no node of partition jam (sinfo) has more than {cpus} CPUs"),
])
def test_request_that_can_never_start_is_refused(cluster, jam, source, tmp_path, mode, options,
                                                 message):
    n = {"too_many": cluster.cpus + 1, "cpus": cluster.cpus}
    error = refused(cluster, jam, source, tmp_path, mode, *[o.format(**n) for o in options])
    assert error.startswith(f"jam-slurm: error: {message.format(**n)}"), error
    assert error.rstrip().endswith("the job could never start"), error


def test_mpi_job_without_an_mpi_plugin_is_refused(cluster, jam, source, tmp_path):
    # srun would start separate jams, all but one refused by the directory's lock
    error = refused(cluster, jam, source, tmp_path, "mpi", env={"SLURM_MPI_TYPE": "none"})
    assert error.startswith("jam-slurm: error: srun would start separate jam processes, not "
                            "MPI ranks: srun's MPI plugin is none (SLURM_MPI_TYPE, else the "
                            "cluster's MpiDefault); set SLURM_MPI_TYPE"), error
