#!/usr/bin/python3
"""scripts/reproduce.sh end to end, on a small study with every stage the paper-scale one has
(a phi_init campaign, a jamming-point campaign, a chained campaign and its chain control), in a
copy of the scripts with build/jam pointing at the jam under test:

- the stored result holds exactly the files the script documents, the fits are the stats.h5
  fits as stored, each campaign's core-seconds are its cost account, and the phi_init check is
  judged over the free fit's window;
- a second invocation keeps what the result directory holds beside the script's files, drops a
  file of its own it did not write again, and reruns no finished run;
- nothing of the result is touched, and no temporary directory is left, when a stage fails or
  when runs/NAME-q-fixed holds something the script did not write (or is a symbolic link).

Usage (ctest runs it): python3 -m pytest tests/test_reproduce.py --jam build/jam --source .
The tests run in the order written: the rerun (b_...) and the failures (c_...) start from the
first invocation's result.
"""

import glob
import json
import os
import shutil
import subprocess
import tomllib

import h5py
import pytest

# N = 64 and 128 compress in seconds; six rates with chained slow ones give a free fit that
# settles (the fit needs the crossover from p ~ rate to rate independence, which rates of 1e-4
# and faster do not reach at these sizes).
COMMON = """dim = 2
phi_init = [0.70]
phi_stop = 0.88
phi_step = 0.002
dt = 0.02
seed = 11
"""
CAMPAIGNS = {
    "tiny": """sizes = [64, 128]
log10_rates = [-4.0, -4.5, -5.0, -5.5, -6.0, -6.5]
chain_phi_init = [0, 0, 0.78, 0.79, 0.80, 0.81]
samples = 8
""",
    "tiny-chain-control": """sizes = [128]
log10_rates = [-5.0, -5.5]
samples = 8
""",
    "tiny-phi-init": """sizes = [64]
log10_rates = [-4.0]
samples = 4
""",
    "tiny-jamming": """sizes = [64, 128]
log10_rates = [-4.0]
samples = 3
jamming_point = true
""",
}
# What the script stores (its header comment): nothing more, nothing less.
STORED = {"stats.h5", "checks.json", "fit-free.json", "fit-held.json", "fit-q-fixed.json",
          "phi-init-checks.json", "chain-checks.json", "jamming-stats.h5", "campaign.toml",
          "cost.json", "provenance.json"}
# Each campaign's key in provenance.json and cost.json.
COST_KEYS = {"campaign": "tiny", "phi_init_campaign": "tiny-phi-init",
             "jamming_campaign": "tiny-jamming", "chain_control_campaign": "tiny-chain-control"}


def read_json(path):
    with open(path) as f:
        return json.load(f)


def contents(directory):
    """Every file under DIRECTORY -> its bytes."""
    out = {}
    for root, _, files in os.walk(directory):
        for name in files:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                out[os.path.relpath(path, directory)] = f.read()
    return out


class Study:
    """A copy of the scripts and python/ with build/jam -> the jam under test, the campaigns
    written, and reproduce.sh run once (`first`)."""

    def __init__(self, jam, source, root):
        self.root = str(root)
        ignore = shutil.ignore_patterns("__pycache__")
        for part in ("scripts", "python"):
            shutil.copytree(source / part, self.path(part), ignore=ignore)
        os.makedirs(self.path("build"))
        os.symlink(os.path.abspath(jam), self.path("build", "jam"))
        os.makedirs(self.path("reference", "campaigns"))
        for name, body in CAMPAIGNS.items():
            with open(self.path("reference", "campaigns", name + ".toml"), "w") as f:
                f.write(f'name = "{name}"\n{COMMON}{body}output = "runs/{name}"\n')
        self.result = self.path("reference", "results", "tiny")
        self.first = self.reproduce()

    def reproduce(self):
        return subprocess.run([self.path("scripts", "reproduce.sh"), "tiny"], cwd=self.root,
                              capture_output=True, text=True, timeout=600)

    def path(self, *parts):
        return os.path.join(self.root, *parts)

    def assert_no_temporaries(self):
        assert glob.glob(self.path("reference", "results", ".tiny.*")) == []


@pytest.fixture(scope="module")
def study(jam, source, tmp_path_factory):
    return Study(jam, source, tmp_path_factory.mktemp("reproduce"))


def test_a_stored_result_as_documented(study):
    assert study.first.returncode == 0, study.first.stderr
    assert set(os.listdir(study.result)) == STORED
    study.assert_no_temporaries()
    assert os.path.isfile(study.path("reports", "tiny", "index.html"))
    assert os.path.isfile(study.path("reports", "tiny-q-fixed", "index.html"))
    assert os.path.isfile(study.path("reports", "tiny-jamming", "index.html"))

    # The stored stats.h5 is the free fit's (the last jam stats), and fit-free.json copies
    # its representative fit; the held fits say what they held.
    with open(os.path.join(study.result, "stats.h5"), "rb") as f:
        stored = f.read()
    with open(study.path("runs", "tiny", "stats.h5"), "rb") as f:
        assert stored == f.read()
    with h5py.File(os.path.join(study.result, "stats.h5"), "r") as f:
        fit = dict(f["fit/representative"].attrs)
    free = read_json(os.path.join(study.result, "fit-free.json"))["representative"]
    for key in ("phi_j", "phi_j_error", "beta", "y", "phi_min", "phi_max"):
        assert free[key] == float(fit[key]), key
    assert free["fixed"] == "none"
    for held in ("fit-q-fixed.json", "fit-held.json"):
        assert read_json(os.path.join(study.result, held))["representative"]["fixed"] != "none"

    # The phi_init campaign is judged over the free fit's window, not over its own range.
    options = read_json(os.path.join(study.result, "phi-init-checks.json"))["options"]
    assert (options["phi_min"], options["phi_max"]) == (free["phi_min"], free["phi_max"])
    # The chain check judged the campaign's chained rates against the control.
    # Two chained rates, each judged pooled and in the three regions around phi_J.
    chain = read_json(os.path.join(study.result, "chain-checks.json"))["verdicts"]
    assert len(chain) == 8, chain
    assert [v["region"] for v in chain].count("pooled") == 2, chain


def test_a_cost_of_every_campaign(study):
    provenance = read_json(os.path.join(study.result, "provenance.json"))
    cost = read_json(os.path.join(study.result, "cost.json"))
    assert set(cost) == set(COST_KEYS)
    total = 0.0
    for key, campaign in COST_KEYS.items():
        seconds = provenance[key + "_core_seconds"]
        assert seconds == cost[key]["cpu_seconds_total"], key
        # At least what the runs' own records hold (read here, not by the script).
        recorded = 0.0
        for record in glob.glob(study.path("runs", campaign, "runs", "*.record")):
            with open(record, "rb") as f:
                recorded += float(tomllib.load(f)["cpu_seconds"])
        assert recorded > 0.0, campaign
        assert seconds >= recorded * (1 - 1e-9), campaign
        total += seconds
    assert provenance["total_core_seconds"] == pytest.approx(total, abs=1e-3 * total)
    assert provenance["campaign_run_core_seconds"] == provenance["campaign_core_seconds"]


def test_b_a_rerun_keeps_what_it_did_not_write(study):
    runs = {p: os.stat(p).st_mtime_ns
            for p in glob.glob(study.path("runs", "*", "runs", "*.h5"))}
    assert len(runs) > 100
    notes = os.path.join(study.result, "notes.txt")
    with open(notes, "w") as f:
        f.write("the user's own notes\n")
    os.makedirs(os.path.join(study.result, "until-decided"))
    kept = os.path.join(study.result, "until-decided", "checks.json")
    with open(kept, "w") as f:
        f.write("{}\n")
    # Without its jamming campaign the script writes no jamming-stats.h5: the stale one of
    # the first invocation goes (it is the script's own file, not carried over).
    os.rename(study.path("reference", "campaigns", "tiny-jamming.toml"),
              study.path("tiny-jamming.toml.away"))
    try:
        result = study.reproduce()
    finally:
        os.rename(study.path("tiny-jamming.toml.away"),
                  study.path("reference", "campaigns", "tiny-jamming.toml"))
    assert result.returncode == 0, result.stderr
    assert set(os.listdir(study.result)) == (STORED - {"jamming-stats.h5"}
                                             | {"notes.txt", "until-decided"})
    with open(notes) as f:
        assert f.read() == "the user's own notes\n"
    with open(kept) as f:
        assert f.read() == "{}\n"
    # No finished run was computed again.
    assert {p: os.stat(p).st_mtime_ns for p in runs} == runs
    study.assert_no_temporaries()


def test_c_a_failed_stage_leaves_the_result_alone(study):
    before = contents(study.result)
    campaign = study.path("reference", "campaigns", "tiny.toml")
    with open(campaign) as f:
        text = f.read()
    with open(campaign, "w") as f:
        f.write(text.replace("samples = 8", "samples = -1"))
    try:
        result = study.reproduce()
    finally:
        with open(campaign, "w") as f:
            f.write(text)
    assert result.returncode != 0
    assert "samples" in result.stderr
    assert contents(study.result) == before
    study.assert_no_temporaries()


def test_c_a_foreign_q_fixed_directory_is_refused(study):
    before = contents(study.result)
    qfixed = study.path("runs", "tiny-q-fixed")
    foreign = os.path.join(qfixed, "my-analysis.h5")
    with open(foreign, "w") as f:
        f.write("not the script's\n")
    try:
        result = study.reproduce()
        assert result.returncode == 2, result.stderr
        assert "my-analysis.h5" in result.stderr
        with open(foreign) as f:
            assert f.read() == "not the script's\n"
    finally:
        os.unlink(foreign)
    # A symbolic link in its place: whatever it points at is not the script's to empty.
    elsewhere = study.path("elsewhere")
    shutil.move(qfixed, elsewhere)
    os.symlink(elsewhere, qfixed)
    try:
        result = study.reproduce()
        assert result.returncode == 2, result.stderr
        assert "tiny-q-fixed" in result.stderr
        assert "stats.h5" in os.listdir(elsewhere)
    finally:
        os.unlink(qfixed)
        shutil.move(elsewhere, qfixed)
    assert contents(study.result) == before
