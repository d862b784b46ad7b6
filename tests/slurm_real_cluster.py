"""A private single-node Slurm for tests/test_slurm_real.py: munged, slurmctld and slurmd of the
Debian packages, started as root with a configuration, key, state, spool, logs, pid files and
ports of their own in a temporary directory (the system's /etc/slurm and /etc/munge are never
read: SLURM_CONF names the test's file, every daemon is given its paths). `start` returns a
Cluster; `Cluster.stop` cancels what is left in its queue and ends every daemon it started.
"""

import os
import pathlib
import shutil
import socket
import subprocess
import tempfile
import time

TOOLS = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo", "scontrol", "scancel",
         "srun")
PATH = os.environ.get("PATH", "/usr/bin:/bin") + ":/usr/sbin:/sbin"


def missing_tools():
    """The Slurm and munge programs not installed (setup.sh --tests installs them)."""
    return [t for t in TOOLS if shutil.which(t, path=PATH) is None]


def free_ports(n):
    """n TCP ports nobody listens on now (held open together, so they differ)."""
    held = []
    for _ in range(n):
        s = socket.socket()
        s.bind(("127.0.0.1", 0))
        held.append(s)
    ports = [s.getsockname()[1] for s in held]
    for s in held:
        s.close()
    return ports


def this_node():
    """(name, "NodeName=... CPUs=... RealMemory=..." line of slurmd -C, CPUs, MB)."""
    line = subprocess.run(["slurmd", "-C"], capture_output=True, text=True, check=True,
                          timeout=30).stdout.splitlines()[0]
    fields = dict(f.split("=", 1) for f in line.split())
    return fields["NodeName"], line, int(fields["CPUs"]), int(fields["RealMemory"])


CONF = """\
ClusterName=jamtest
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={dir}/munge/socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/run/slurmctld.pid
SlurmdPidFile={dir}/run/slurmd.pid
SlurmctldLogFile={dir}/log/slurmctld.log
SlurmdLogFile={dir}/log/slurmd.log
MailProg=/bin/true
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=pmix
ReturnToService=2
KillWait=10
MinJobAge=600
{node} NodeAddr=127.0.0.1
PartitionName=jam Nodes={host} Default=YES MaxTime={max_minutes} DefMemPerCPU={mem_per_cpu} State=UP
"""


class Cluster:
    def __init__(self, root, max_minutes):
        self.dir = pathlib.Path(root)
        self.host, node, self.cpus, self.memory = this_node()
        self.max_minutes = max_minutes
        self.conf = self.dir / "slurm.conf"
        self.env = {"PATH": PATH, "HOME": str(self.dir), "LANG": "C.UTF-8",
                    "SLURM_CONF": str(self.conf)}
        self.daemons = []
        for d in ("munge", "state", "spool", "log", "run"):
            (self.dir / d).mkdir(mode=0o755)
        ctld_port, d_port = free_ports(2)
        self.conf.write_text(CONF.format(host=self.host, node=node, dir=self.dir,
                                         ctld_port=ctld_port, d_port=d_port,
                                         max_minutes=max_minutes,
                                         mem_per_cpu=self.memory // self.cpus))

    def run(self, *argv, check=True, cwd=None, env=None):
        r = subprocess.run(list(argv), capture_output=True, text=True, timeout=60,
                           env={**self.env, **(env or {})}, cwd=cwd)
        assert not check or r.returncode == 0, f"{argv}: {r.stdout}{r.stderr}"
        return r

    def _daemon(self, name, *argv):
        log = open(self.dir / "log" / f"{name}.out", "w")
        self.daemons.append(subprocess.Popen(list(argv), env=self.env, stdout=log,
                                             stderr=subprocess.STDOUT))
        log.close()

    def _wait(self, what, ready, seconds=60):
        deadline = time.time() + seconds
        while not ready():
            for p in self.daemons:
                assert p.poll() is None, f"{p.args[0]} exited {p.returncode}: {self.logs()}"
            assert time.time() < deadline, f"{what} not ready in {seconds} s: {self.logs()}"
            time.sleep(0.2)

    def start(self):
        key = self.dir / "munge" / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        m = self.dir / "munge"
        self._daemon("munged", "munged", "--foreground", f"--socket={m}/socket",
                     f"--key-file={key}", f"--pid-file={m}/munged.pid",
                     f"--log-file={m}/munged.log", f"--seed-file={m}/munged.seed")
        self._wait("munged", (m / "socket").exists)
        self._daemon("slurmctld", "slurmctld", "-D", "-i")
        self._daemon("slurmd", "slurmd", "-D", "-N", self.host)
        self._wait("the node", lambda: self.run("sinfo", "-h", "-N", "-o", "%t",
                                                check=False).stdout.strip() == "idle")
        return self

    def jobs(self):
        """{job id: (state, work directory)} of the jobs the controller still lists."""
        out = self.run("squeue", "-h", "-o", "%i|%T|%Z").stdout
        return {i: (s, d) for i, s, d in (line.split("|") for line in out.splitlines())}

    def logs(self):
        out = []
        for f in sorted((self.dir / "log").iterdir()):
            out.append(f"--- {f.name}\n" + "\n".join(f.read_text(errors="replace")
                                                     .splitlines()[-15:]))
        return "\n".join(out)

    def stop(self):
        """Cancels every job, waits for the queue to empty (so no job step outlives the
        daemons), then ends slurmd, slurmctld and munged, in that order."""
        if self.daemons and all(p.poll() is None for p in self.daemons):
            self.run("scancel", "--user", "root", check=False)
            deadline = time.time() + 40
            while time.time() < deadline:
                r = self.run("squeue", "-h", check=False)  # pending, running, completing
                if r.returncode != 0 or not r.stdout.strip():
                    break
                time.sleep(0.5)
        for p in reversed(self.daemons):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait(timeout=20)
        shutil.rmtree(self.dir, ignore_errors=True)


def start(max_minutes):
    """A running Cluster in a new temporary directory (world-searchable: munged refuses a
    socket directory that others cannot enter)."""
    root = tempfile.mkdtemp(prefix="jam-slurm-real-")
    os.chmod(root, 0o755)
    cluster = Cluster(root, max_minutes)
    try:
        return cluster.start()
    except BaseException:
        cluster.stop()
        raise
