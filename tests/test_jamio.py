#!/usr/bin/python3
"""jamio (python/) installed the documented way and read back against h5py.

In a temporary directory: a venv with --system-site-packages, `pip install --no-index
--no-build-isolation` of a copy of python/ (offline: nothing is fetched), then the files jam
writes: a run file (`jam sim`), a small campaign run, averaged (`jam stats`) and checked (`jam
check all --no-lmp`), a schema 1 checks.json (the bare array), a run file without the schema 2
attributes, files set aside in runs/, and broken files. The venv's Python then runs the cases
of tests/jamio_in_venv.py with pytest: every value jamio returns must equal what h5py and json
read (strings decoded, numbers as int and float), nothing in a file may be left out, and every
broken file must raise JamioError naming it.

Usage (ctest runs it): python3 -m pytest tests/test_jamio.py --jam build/jam --source .
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py
import pytest

from jamio_hostile import make_broken
from jamio_in_venv import DECOYS

CAMPAIGN = """name = "jamio"
dim = 2
sizes = [64, 128]
phi_init = [0.70]
log10_rates = [-2.5, -3.0]
samples = 3
phi_stop = 0.8
phi_step = 0.002
dt = 0.02
seed = 5
output = "campaign"
jamming_point = true
rattlers = true
stress = true
"""
TIMEOUT = 600


def run(cmd, cwd=None, expect=(0,), env=None):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT, env=env)
    assert r.returncode in expect, \
        f"{' '.join(map(str, cmd))} exited {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


# ---- outside the venv: install jamio, make the files ------------------------------------------


def install(work, source):
    """A venv with the system's packages and jamio installed offline; its python."""
    venv = os.path.join(work, "venv")
    run([sys.executable, "-m", "venv", "--system-site-packages", venv])
    copy = os.path.join(work, "jamio-source")  # pip builds in the tree: not in the source's
    shutil.copytree(os.path.join(source, "python"), copy,
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    python = os.path.join(venv, "bin", "python")
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    run([python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-cache-dir",
         "--root-user-action=ignore", copy], env=env)
    return python


def strip_schema_2(path):
    """The run file as schema 1 wrote it: no units, campaign, sample or schema_version."""
    with h5py.File(path, "r+") as f:
        for name in ("units", "campaign", "sample", "schema_version"):
            if name in f.attrs:
                del f.attrs[name]
        for d in f.values():
            if "units" in d.attrs:
                del d.attrs["units"]


def make_old_campaign(data, runs):
    """data/old/runs: a run file stripped to schema 1, an intact one and files set aside."""
    old = os.path.join(data, "old", "runs")
    os.makedirs(old)
    names = sorted(n for n in os.listdir(runs) if n.endswith(".h5"))
    shutil.copy(os.path.join(runs, names[0]), os.path.join(old, names[0]))
    strip_schema_2(os.path.join(old, names[0]))
    shutil.copy(os.path.join(data, "old", "runs", names[0]), os.path.join(data, "old.h5"))
    shutil.copy(os.path.join(runs, names[-1]), old)
    for decoy in DECOYS:
        with open(os.path.join(old, decoy), "wb") as f:
            f.write(b"not a run file\n")


def make_schema_1(data):
    """data/schema1: checks.json as the bare array of verdicts, with the campaign's checks.h5."""
    out = os.path.join(data, "schema1")
    os.mkdir(out)
    with open(os.path.join(data, "campaign", "checks.json")) as f:
        verdicts = json.load(f)["verdicts"]
    with open(os.path.join(out, "checks.json"), "w") as f:
        json.dump(verdicts, f, indent=2)
    shutil.copy(os.path.join(data, "campaign", "checks.h5"), out)


def make_data(work, jam, source):
    data = os.path.join(work, "data")
    os.mkdir(data)
    run([jam, "sim", "--n", "64", "--phi-init", "0.7", "--phi-stop", "0.72", "--rate", "1e-2",
         "--phi-step", "0.005", "--quiet", "--out", os.path.join(data, "run.h5")])
    with open(os.path.join(data, "campaign.toml"), "w") as f:
        f.write(CAMPAIGN)
    run([jam, "campaign", "run", "campaign.toml", "--quiet"], cwd=data)
    run([jam, "stats", "campaign"], cwd=data)
    run([jam, "check", "all", "campaign", "--no-lmp", "--reference-dir",
         os.path.join(source, "reference")], cwd=data, expect=(0, 1, 3))
    make_old_campaign(data, os.path.join(data, "campaign", "runs"))
    make_schema_1(data)
    make_broken(data)
    return data


@pytest.fixture(scope="module")
def work():
    """The venv and the files (a short path as before: the refusals checked in the venv shorten
    long paths they quote)."""
    work = tempfile.mkdtemp(prefix="jam-jamio-test-")
    yield work
    shutil.rmtree(work, ignore_errors=True)


@pytest.fixture(scope="module")
def venv(work, source):
    """The venv's python, jamio installed in it."""
    return install(work, source)


@pytest.fixture(scope="module")
def data(work, jam, source):
    return make_data(work, jam, source)


def test_jamio_in_the_venv(venv, data, work, source):
    """The cases of jamio_in_venv.py, in the venv's Python (pytest without tests/conftest.py:
    that would put the source tree's jamio first)."""
    cases = os.path.join(os.path.dirname(os.path.abspath(__file__)), "jamio_in_venv.py")
    env = dict(os.environ, JAMIO_TEST_DATA=data, JAMIO_TEST_SOURCE=str(source))
    r = subprocess.run([venv, "-m", "pytest", "-q", "-rs", "-p", "no:cacheprovider",
                        "--noconftest", cases], capture_output=True, text=True,
                       timeout=TIMEOUT, cwd=work, env=env)
    print(r.stdout)  # pytest shows it when the test fails: which cases, and why
    assert r.returncode == 0, f"the cases in the venv failed (exit {r.returncode}):\n" \
        f"{r.stdout[-4000:]}{r.stderr[-2000:]}"
