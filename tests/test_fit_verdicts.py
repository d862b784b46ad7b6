"""The verdicts the scaling fit uses are a declared input (stats/fit_verdicts.hpp): `jam stats`
gives the same stats.h5 whether or not `jam check` ran before it, unless the fit consults
verdicts (a fitted phi_init above the lowest, whose rates the phi_init check clears; the
paper's protocol pooling sizes), and then stats.h5 says which (`fit_verdicts`) and `jam
pipeline` averages again when they change. `--fit-verdicts none` declares none.

    /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/test_fit_verdicts.py \
        --jam build/jam --source .
"""

import shutil
import subprocess

import h5py
import numpy as np
import pytest

# Three rates: with fewer no scaling fit is attempted, and the fit consults no verdict.
CAMPAIGN = """name = "fv"
dim = 2
sizes = [64]
phi_init = [0.6, 0.7]
log10_rates = [-2.0, -2.5, -3.0]
samples = 3
phi_stop = 0.86
phi_step = 0.002
dt = 0.02
seed = 7
output = "{output}"
"""

# Differ between any two runs of `jam stats`: the time it took, and the seal over it.
VOLATILE = {("/", "wall_time"), ("/", "checksum")}


def run(jam, *args):
    r = subprocess.run([str(jam), *map(str, args)], capture_output=True, text=True, timeout=600)
    assert r.returncode in (0, 3), f"jam {' '.join(map(str, args))}: {r.stdout}{r.stderr}"
    return r.stdout


def content(path):
    """Every attribute and dataset of an HDF5 file, by path, the volatile ones left out."""
    out = {}
    with h5py.File(path, "r") as f:
        def attrs(name, obj):
            for k, v in obj.attrs.items():
                if (name, k) not in VOLATILE:
                    out[(name, k)] = v.tobytes() if isinstance(v, np.ndarray) else v
            if isinstance(obj, h5py.Dataset):
                out[(name, "")] = obj[()].tobytes()
        attrs("/", f)
        f.visititems(lambda n, o: attrs("/" + n, o))
    return out


def root_attr(path, name):
    with h5py.File(path, "r") as f:
        v = f.attrs[name]
        return v.decode() if isinstance(v, bytes) else v


@pytest.fixture(scope="module")
def campaign(jam, tmp_path_factory):
    work = tmp_path_factory.mktemp("fit-verdicts")
    out = work / "fv"
    (work / "fv.toml").write_text(CAMPAIGN.format(output=out))
    run(jam, "campaign", "run", work / "fv.toml", "--jobs", "2")
    return out


def stats(jam, directory, *options):
    run(jam, "stats", directory, *options)
    return content(directory / "stats.h5")


def test_stats_is_the_same_whether_or_not_check_ran(jam, campaign):
    for f in campaign.glob("checks*"):
        f.unlink()
    before = stats(jam, campaign)
    assert root_attr(campaign / "stats.h5", "fit_verdicts") == "none"
    run(jam, "check", "all", campaign, "--no-lmp")
    run(jam, "check", "phi_init", campaign, "--no-lmp")
    assert (campaign / "checks.json").exists() and (campaign / "checks-phi_init.json").exists()
    # The lowest phi_init is fitted: no verdict bears on it, none is consulted.
    after = stats(jam, campaign)
    assert after == before, sorted(k for k in after.keys() | before.keys()
                                   if after.get(k) != before.get(k))


def test_a_fit_that_consults_verdicts_says_so_and_none_declares_none(jam, campaign):
    for f in campaign.glob("checks*"):
        f.unlink()
    alone = stats(jam, campaign, "--fit-phi-init", "0.7")
    assert root_attr(campaign / "stats.h5", "fit_verdicts") == "none"
    run(jam, "check", "phi_init", campaign, "--no-lmp")
    judged = stats(jam, campaign, "--fit-phi-init", "0.7")
    assert root_attr(campaign / "stats.h5", "fit_verdicts") == "checks-phi_init.json"
    assert root_attr(campaign / "stats.h5", "fit_verdicts_checksum") != "none"
    with h5py.File(campaign / "stats.h5", "r") as f:
        note = f["fit"].attrs["rates_note"]
        note = note.decode() if isinstance(note, bytes) else note
    assert "rates cleared by the phi_init check (checks-phi_init.json)" in note, note
    assert judged != alone
    # Declared none: as if no check had run.
    assert stats(jam, campaign, "--fit-phi-init", "0.7", "--fit-verdicts", "none") == alone


def test_pipeline_averages_again_when_the_consulted_verdicts_change(jam, campaign, tmp_path):
    # stats.h5 of a fit that consulted the phi_init verdicts, then those verdicts gone: the
    # pipeline's definition of out of date (design/pipeline_stages.cpp) says so.
    run(jam, "check", "phi_init", campaign, "--no-lmp")
    stats(jam, campaign, "--fit-phi-init", "0.7")
    saved = tmp_path / "checks-phi_init.json"
    shutil.move(campaign / "checks-phi_init.json", saved)
    toml = campaign.parent / "fv.toml"
    out = run(jam, "pipeline", toml, "--jobs", "2", "--no-lmp", "--report", tmp_path / "r")
    assert "the verdicts its fit consults" in out, out
    # Averaged again with the lowest phi_init (the pipeline's default): nothing consulted, so
    # the verdicts written by its own check stage leave it current on the next run.
    again = run(jam, "pipeline", toml, "--jobs", "2", "--no-lmp", "--report", tmp_path / "r")
    assert "stats: " in again and "is up to date" in again, again
    assert "the verdicts its fit consults" not in again, again
