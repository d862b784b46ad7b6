#!/usr/bin/python3
"""The files of the small scripts (scripts/), on tiny made-up inputs: each output is written
whole or not at all (a failure part-way leaves the old one; an output that is the input is
refused), a FIFO given as an input is refused rather than waited on, a table that cannot be
resampled with its ensemble is an error, a re-judged result is recorded or left alone, a
campaign directory the cross-simulator demonstration did not make is never deleted, and an
--out LAMMPS would split is refused at once. Refusals are one line on stderr, exit status 2.

LAMMPS, jam and the demonstration's own steps are small fakes written here; the scripts that
find files beside themselves (rejudge.py, cross_lammps.py) run from a copy of scripts/ in a
temporary tree.

Usage (ctest runs it): python3 -m pytest tests/test_scripts_io.py --source .
"""

import glob
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest


def fake_program(path, body):
    """An executable Python program at `path` (a stand-in for jam or a step of a script)."""
    with open(path, "w") as f:
        f.write(f"#!{sys.executable}\nimport json, os, sys\n{body}")
    os.chmod(path, 0o755)
    return path


def scratch_tree(source, root):
    """root/scripts: a copy of the scripts; root/python: the source's jamio."""
    os.makedirs(os.path.join(root, "scripts"))
    for path in glob.glob(os.path.join(source, "scripts", "*.py")):
        shutil.copy(path, os.path.join(root, "scripts"))
    os.symlink(os.path.join(source, "python"), os.path.join(root, "python"))


def slurp(path):
    with open(path, "rb") as f:
        return f.read()


def tree(directory):
    """Every file under `directory`, by relative path, with its bytes."""
    out = {}
    for parent, _, files in os.walk(directory):
        for name in files:
            path = os.path.join(parent, name)
            out[os.path.relpath(path, directory)] = slurp(path)
    return out


def write_fit(path, broken=False):
    with h5py.File(path, "w") as f:
        fit = f.create_group("fit")
        fit.attrs["phi_j"] = 0.84
        if broken:  # a compound value: bytes inside, which JSON cannot hold
            fit.attrs["odd"] = np.array((1, b"a"), dtype=[("a", "i4"), ("b", "S1")])
        rep = fit.create_group("representative")
        rep.attrs["order"] = 2
        rep.create_dataset("coefficients", data=[1.0, 2.0, 3.0])


def write_ensemble(path, sample_id_rows=4):
    """A stats.h5 of one ensemble of 4 samples; its sample_ids have `sample_id_rows` rows."""
    with h5py.File(path, "w") as f:
        g = f.create_group("ensembles/e0")
        g.attrs["samples"] = 4
        g.create_dataset("constant_phi/pressure_samples", data=np.ones((4, 3)))
        g.create_dataset("constant_phi/sample_ids", data=np.arange(sample_id_rows))


@pytest.fixture
def work(tmp_path):
    """The test's scratch directory, as a string."""
    return str(tmp_path)


def script(source, name, *args, cwd=None, env=None):
    """Runs scripts/NAME of the tree `source` with the test's interpreter."""
    path = os.path.join(source, "scripts", name)
    return subprocess.run([sys.executable, path, *args], capture_output=True, text=True,
                          timeout=60, cwd=cwd, env=env)


def refused(r, *words):
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.splitlines()) == 1, r.stderr
    for w in words:
        assert w in r.stderr


def fifo(work):
    path = os.path.join(work, "fifo.h5")
    os.mkfifo(path)
    return path


# fit_to_json.py


def test_fit_to_json_refuses_its_input_as_output(source, work):
    stats = os.path.join(work, "stats.h5")
    write_fit(stats)
    r = script(source, "fit_to_json.py", stats, stats)
    with h5py.File(stats, "r") as f:
        assert f["fit"].attrs["phi_j"] == 0.84
    refused(r, "OUT_JSON", stats)


def test_fit_to_json_failure_leaves_the_old_json(source, work):
    stats, out = os.path.join(work, "stats.h5"), os.path.join(work, "fit.json")
    write_fit(stats)
    r = script(source, "fit_to_json.py", stats, out, "how")
    assert r.returncode == 0, r.stderr
    old = slurp(out)
    assert json.loads(old)["representative"]["coefficients"] == [1.0, 2.0, 3.0]
    write_fit(stats, broken=True)
    r = script(source, "fit_to_json.py", stats, out)
    assert slurp(out) == old
    refused(r, stats)
    assert sorted(os.listdir(work)) == ["fit.json", "stats.h5"]


def test_fit_to_json_refuses_a_fifo(source, work):
    r = script(source, "fit_to_json.py", fifo(work), os.path.join(work, "fit.json"))
    refused(r, "STATS_H5", "FIFO")


# script_files.py


def test_staged_copy_refuses_a_fifo_and_leaves_nothing(source, work):
    sys.path.insert(0, os.path.join(source, "scripts"))
    import script_files
    from jamio.errors import JamioError
    pipe, target = fifo(work), os.path.join(work, "copy.h5")
    with script_files.Staged() as staged:
        with pytest.raises(JamioError) as raised:
            staged.copy(pipe, target)  # a plain open would wait for a writer for ever
        staged.commit()
    assert "FIFO" in str(raised.value)
    with script_files.Staged() as staged:
        with pytest.raises(JamioError) as raised:
            staged.copy(os.path.join(work, "gone.h5"), target)
    assert raised.value.missing
    assert os.listdir(work) == ["fifo.h5"]


# variance_reduction.py


def test_variance_reduction_refuses_a_fifo(source, work):
    r = script(source, "variance_reduction.py", fifo(work))
    refused(r, "stats", "FIFO")


def test_variance_reduction_refuses_jamming_points_of_other_samples(source, work):
    stats = os.path.join(work, "stats.h5")

    def write(jamming_ids):
        with h5py.File(stats, "w") as f:
            f.create_group("fit/representative").attrs["phi_j"] = 0.84
            g = f.create_group("ensembles/e0")
            g.attrs.update({"n": 64, "phi_init": 0.4, "log10_rate": -5.0})
            g["jamming/packing_fraction_samples"] = [0.838, 0.840, 0.842, 0.844]
            g["jamming/sample_ids"] = jamming_ids
            grid = np.linspace(0.82, 0.86, 41)
            g["constant_phi/packing_fraction"] = grid
            g["constant_phi/pressure_samples"] = np.exp(40 * (grid - 0.84)) * np.ones((4, 1))
            g["constant_phi/sample_ids"] = [0, 1, 2, 3]

    write([0, 1, 2, 3])
    r = script(source, "variance_reduction.py", stats)
    assert r.returncode == 0, r.stderr
    write([1, 0, 2, 3])  # each point beside another sample's pressures
    refused(script(source, "variance_reduction.py", stats), "/ensembles/e0", "do not pair")


# samples_needed_stability.py


def stability(source, work, *extra):
    jam = fake_program(os.path.join(work, "jam"), (
        "with open(os.path.join(sys.argv[3], f'checks-{sys.argv[2]}.json'), 'w') as f:\n"
        "    json.dump({'verdicts': []}, f)\n"))
    return script(source, "samples_needed_stability.py", work, "--resamples", "1", "--keep", "2",
                  "--jam", jam, *extra)


def test_samples_needed_stability_refuses_its_input_as_output(source, work):
    stats = os.path.join(work, "stats.h5")
    write_ensemble(stats)
    r = stability(source, work, "--json", stats)
    with h5py.File(stats, "r") as f:
        assert f["ensembles/e0"].attrs["samples"] == 4
    refused(r, "--json", stats)


def test_samples_needed_stability_refuses_a_table_of_other_length(source, work):
    stats, out = os.path.join(work, "stats.h5"), os.path.join(work, "s.json")
    write_ensemble(stats)
    r = stability(source, work, "--json", out)
    assert r.returncode == 0, r.stderr
    assert json.loads(slurp(out))["keep"] == 2
    write_ensemble(stats, sample_id_rows=3)
    r = stability(source, work)
    refused(r, "ensembles/e0/constant_phi/sample_ids", "(3,)", "4 samples")


# rejudge.py


def test_rejudge_reads_provenance_before_replacing_anything(source, work):
    scratch_tree(source, work)
    stored = os.path.join(work, "reference", "results", "demo")
    os.makedirs(stored)
    with h5py.File(os.path.join(stored, "stats.h5"), "w") as f:
        f.attrs["made"] = "here"
    for name, text in (("campaign.toml", "name = 'demo'\n"), ("checks.json", "old\n")):
        with open(os.path.join(stored, name), "w") as f:
            f.write(text)
    jam = fake_program(os.path.join(work, "jam"), (
        "if sys.argv[1] == '--version':\n"
        "    print('jam version 9.9')\n"
        "else:\n"
        "    with open(os.path.join(sys.argv[3], 'checks.json'), 'w') as f:\n"
        "        f.write('new\\n')\n"))
    provenance = os.path.join(stored, "provenance.json")
    for content in (None, "[]", "{"):
        if content is not None:
            with open(provenance, "w") as f:
                f.write(content)
        r = script(work, "rejudge.py", "demo", "--jam", jam)
        assert slurp(os.path.join(stored, "checks.json")) == b"old\n"
        refused(r, provenance)
    with open(provenance, "w") as f:
        json.dump({"name": "demo"}, f)
    r = script(work, "rejudge.py", "demo", "--jam", jam)
    assert r.returncode == 0, r.stderr
    assert slurp(os.path.join(stored, "checks.json")) == b"new\n"
    with open(provenance) as f:
        assert json.load(f)["checks_rejudged"]["code_version"] == "9.9"
    assert sorted(os.listdir(stored)) == ["campaign.toml", "checks.json", "provenance.json",
                                          "stats.h5"]

def rejudge_refit_tree(source, work, stored_status):
    """A scratch tree with a stored result whose checks.json holds one pooled finite_size
    verdict of status STORED_STATUS, and a fake jam: `stats --refit` logs the statuses it finds
    in its directory's checks.json (the verdicts a fit consults), `check all` writes the next
    status of FAKE_STATUSES (comma-separated, round by round)."""
    scratch_tree(source, work)
    stored = os.path.join(work, "reference", "results", "demo")
    os.makedirs(stored)
    write_fit(os.path.join(stored, "stats.h5"))
    with open(os.path.join(stored, "campaign.toml"), "w") as f:
        f.write("name = 'demo'\n")
    with open(os.path.join(stored, "provenance.json"), "w") as f:
        json.dump({"name": "demo"}, f)
    verdicts = ('{"verdicts": [{"check": "finite_size", "case": "n1 vs n2", '
                '"region": "pooled", "status": "%s"}]}')
    with open(os.path.join(stored, "checks.json"), "w") as f:
        f.write(verdicts % stored_status)
    log = os.path.join(work, "log")
    jam = fake_program(os.path.join(work, "jam"), (
        f"log = {log!r}\n"
        "if sys.argv[1] == '--version':\n"
        "    print('jam version 9.9')\n"
        "elif sys.argv[1] == 'stats':\n"
        "    d = sys.argv[2]\n"
        "    seen = [v['status'] for v in json.load(open(os.path.join(d, 'checks.json')))\n"
        "            ['verdicts']] if os.path.exists(os.path.join(d, 'checks.json')) else []\n"
        "    open(log, 'a').write('stats ' + ' '.join(sys.argv[3:]) + ': ' + ','.join(seen) + '\\n')\n"
        "else:\n"
        "    rounds = open(log).read().count('check')\n"
        "    open(log, 'a').write('check\\n')\n"
        "    status = os.environ['FAKE_STATUSES'].split(',')[rounds]\n"
        f"    open(os.path.join(sys.argv[3], 'checks.json'), 'w').write({verdicts!r} % status)\n"))
    return stored, jam, log


def test_rejudge_refits_with_the_stored_verdicts_until_they_hold(source, work):
    # The stored finite_size verdict (inconclusive) is what the first refit consults; judged
    # anew it passes, so the fit is redone with it and judged again, where it holds.
    stored, jam, log = rejudge_refit_tree(source, work, "inconclusive")
    env = dict(os.environ, FAKE_STATUSES="pass,pass,pass")
    r = script(work, "rejudge.py", "demo", "--jam", jam, "--refit", env=env)
    assert r.returncode == 0, r.stderr
    refits = [line for line in slurp(log).decode().splitlines()
              if line.startswith("stats --refit --order 2:")]
    assert refits == ["stats --refit --order 2: inconclusive", "stats --refit --order 2: pass"]
    with open(os.path.join(stored, "checks.json")) as f:
        assert json.load(f)["verdicts"][0]["status"] == "pass"


def test_rejudge_refuses_verdicts_that_never_settle(source, work):
    stored, jam, log = rejudge_refit_tree(source, work, "inconclusive")
    before = tree(stored)
    env = dict(os.environ, FAKE_STATUSES="pass,fail,pass,fail")
    r = script(work, "rejudge.py", "demo", "--jam", jam, "--refit", env=env)
    refused(r, "still change after 3 rounds")
    assert tree(stored) == before


# cross_lammps.py, its steps faked: LAMMPS's ensemble (ensemble.json only, removed for
# the ensemble named in FAKE_NO_ENSEMBLE), the import, and jam's pipeline; every file they
# write holds FAKE_TAG, which says which invocation wrote it.


@pytest.fixture
def cross_lammps(source, work):
    """A scratch tree with the fakes; runs its cross_lammps.py with FAKE_TAG=tag."""
    scratch_tree(source, work)
    scripts = os.path.join(work, "scripts")
    fake_program(os.path.join(scripts, "cross_lammps_runs.py"), (
        "out = sys.argv[sys.argv.index('--out') + 1]\n"
        "os.makedirs(out, exist_ok=True)\n"
        "path = os.path.join(out, 'ensemble.json')\n"
        "if os.environ.get('FAKE_NO_ENSEMBLE') != os.path.basename(out):\n"
        "    with open(path, 'w') as f:\n"
        "        json.dump({'runs': [{'wall_seconds': 2.0}], 'parameters': {}}, f)\n"
        "elif os.path.exists(path):\n"
        "    os.remove(path)\n"))
    fake_program(os.path.join(scripts, "import_lammps_ensemble.py"), (
        "os.makedirs(sys.argv[2])\n"
        "with open(os.path.join(sys.argv[2], 'external.toml'), 'w') as f:\n"
        "    f.write(os.environ['FAKE_TAG'])\n"))
    jam = fake_program(os.path.join(work, "jam"), (
        "if sys.argv[1] == '--version':\n"
        "    print('jam 0.0')\n"
        "    sys.exit(0)\n"
        "for d, files in (('cross-jam', ('campaign.toml', 'stats.h5', 'checks.json')),\n"
        "                 ('lammps-right', ('stats.h5',)), ('lammps-d135', ('stats.h5',)),\n"
        "                 ('lammps-k110', ('stats.h5',))):\n"
        "    os.makedirs(os.path.join('runs', d), exist_ok=True)\n"
        "    for name in files:\n"
        "        with open(os.path.join('runs', d, name), 'w') as f:\n"
        "            f.write(os.environ['FAKE_TAG'])\n"))


    def run(tag, **env):
        return script(work, "cross_lammps.py", "--logs", os.path.join(work, "logs"), "--jam", jam,
                      cwd=work, env={**os.environ, "FAKE_TAG": tag, **env})
    return run


def test_cross_lammps_replaces_only_its_own_campaigns(cross_lammps, work):
    external = os.path.join(work, "runs", "lammps-right", "external.toml")
    for tag in ("first", "second"):
        r = cross_lammps(tag)
        assert r.returncode == 0, r.stderr
        assert slurp(external) == tag.encode()
    assert sorted(os.listdir(os.path.join(work, "runs"))) == ["cross-jam", "lammps-d135",
                                                              "lammps-k110", "lammps-right"]
    # A campaign of the same name imported by hand is kept, and nothing is run.
    hand = os.path.join(work, "runs", "lammps-d135")
    shutil.rmtree(hand)
    os.makedirs(os.path.join(hand, "runs"))
    with open(os.path.join(hand, "runs", "mine.h5"), "w") as f:
        f.write("mine")
    r = cross_lammps("third")
    assert os.path.isfile(os.path.join(hand, "runs", "mine.h5")), r.stderr
    refused(r, "runs/lammps-d135")
    assert slurp(external) == b"second"


def test_cross_lammps_failure_leaves_the_stored_result_whole(cross_lammps, work):
    r = cross_lammps("first")
    assert r.returncode == 0, r.stderr
    stored = os.path.join(work, "reference", "results", "cross-lammps")
    before = tree(stored)
    assert len(before) == 10
    assert before["lammps-k110/external.toml"] == b"first"
    # The last ensemble's ensemble.json is missing: read only after the others are copied.
    r = cross_lammps("second", FAKE_NO_ENSEMBLE="k110")
    assert r.returncode != 0
    assert tree(stored) == before


# cross_lammps_runs.py


@pytest.mark.parametrize("name", ["a b", "a\tb", "a$b", "a#b", "a'b", 'a"b'])
def test_cross_lammps_runs_refuses_an_out_lammps_would_split(source, work, name):
    out = os.path.join(work, name)
    r = script(source, "cross_lammps_runs.py", "--out", out, "--rates", "-4", "--q", "0.2",
               "--dt", "0.01", "--lmp", os.path.join(work, "no-lmp"))
    assert not os.path.lexists(out), name
    refused(r, "--out")


# bench/plot_benchmarks.py (jam bench's figures): written whole through jamio.output.


def test_benchmark_figure_written_whole_and_never_beside_a_directory(source, work):
    table = os.path.join(work, "throughput.csv")
    with open(table, "w") as f:
        f.write("dim,mode,n,jam_particle_steps_per_s,lammps_particle_steps_per_s\n"
                "2,1 core,64,1e6,2e6\n2,1 core,256,1.1e6,2e6\n")
    plot = [sys.executable, os.path.join(source, "bench", "plot_benchmarks.py"), "throughput",
            table]
    png = os.path.join(work, "throughput.png")
    r = subprocess.run(plot + [png], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert slurp(png)[:8] == b"\x89PNG\r\n\x1a\n"
    # A directory where the figure goes: refused before drawing, nothing left beside it (the
    # figure's temporary file was left there).
    taken = os.path.join(work, "taken.png")
    os.mkdir(taken)
    r = subprocess.run(plot + [taken], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0
    assert "is a directory" in r.stderr
    assert sorted(os.listdir(work)) == ["taken.png", "throughput.csv", "throughput.png"]
    assert os.listdir(taken) == []
