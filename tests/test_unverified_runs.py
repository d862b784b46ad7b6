"""Run files of schema 1 (written before run files checksummed their attributes: no
`checksum`, a `data_checksum` over the datasets only) still count as done, flagged
unverified: `jam campaign status` says how many in its text and names each in --json; a value
changed in such a file is caught by its data checksum. The schema-1 file is made here from a
run jam wrote, its data checksum computed independently (FNV-1a 64 over each dataset's name
and little-endian doubles, in the schema's order).

Usage (ctest runs it): python3 -m pytest tests/test_unverified_runs.py --jam build/jam --source .
"""

import json
import subprocess

import h5py
import numpy as np

SCHEMA_1_DATASETS = ("packing_fraction", "pressure", "contacts_per_particle",
                     "energy_per_particle", "time", "contacts_per_particle_no_rattlers",
                     "rattler_fraction", "stress")


def fnv1a(parts):
    h = 0xcbf29ce484222325
    for part in parts:
        for byte in part:
            h = ((h ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def to_schema_1(path):
    with h5py.File(path, "r+") as f:
        del f.attrs["checksum"]
        del f.attrs["schema_version"]
        parts = []
        for name in SCHEMA_1_DATASETS:
            if name in f:
                parts += [name.encode(), np.asarray(f[name][...], dtype="<f8").tobytes()]
        f.attrs["data_checksum"] = np.bytes_(fnv1a(parts))


def status(jam, directory, *options):
    return subprocess.run([str(jam), "campaign", "status", str(directory), *options],
                          capture_output=True, text=True, timeout=60)


def test_schema_1_runs_are_done_and_flagged_unverified(jam, tmp_path):
    campaign = tmp_path / "s1.toml"
    campaign.write_text('name = "s1"\ndim = 2\nsizes = [64]\nphi_init = [0.70]\n'
                        'log10_rates = [-2]\nsamples = 2\nphi_stop = 0.72\nphi_step = 0.005\n'
                        f'seed = 1\noutput = "{tmp_path / "c"}"\n')
    r = subprocess.run([str(jam), "campaign", "run", "--quiet", str(campaign)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    old = tmp_path / "c" / "runs" / "n64_phi0.7000_r-2.00_s001.h5"
    to_schema_1(old)

    text = status(jam, tmp_path / "c")
    assert text.returncode == 0, text.stdout + text.stderr
    assert "done     2" in text.stdout, text.stdout
    assert "unverified: 1 of the done runs (written before run files checksummed" in text.stdout
    listed = json.loads(status(jam, tmp_path / "c", "--json").stdout)["run"]
    assert listed["n64_phi0.7000_r-2.00_s001"]["detail"].startswith("unverified"), listed
    assert listed["n64_phi0.7000_r-2.00_s000"]["detail"] == "", listed

    with h5py.File(old, "r+") as f:
        f["pressure"][2] = f["pressure"][2] * (1 + 1e-12)
    text = status(jam, tmp_path / "c")
    assert text.returncode != 0, text.stdout
    assert "corrupt n64_phi0.7000_r-2.00_s001: data checksum" in text.stdout, text.stdout
    assert "unverified" not in text.stdout, text.stdout
