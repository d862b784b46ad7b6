#!/usr/bin/python3
"""What the chain check sees: plants a difference in the chained pressures of a chain test and
judges the copy against its control, as docs/statistics-and-checks.md#chain reports.

    scripts/chain_planted.py runs/reduced-2d-chain-test runs/reduced-2d-chain-control \
        --phi-min 0.8316 [--jam build/jam]

Plants, each in a fresh temporary copy of DIR's stats.h5 (DIR itself is only read):
  shift   every pressure of every chained rate times 1.15,
  edge-A  a memory at the window's lower edge: times 1 + A exp(-(phi - phi_min) / 0.002) above
          phi_min (1 + A below it), for A = 0.6 and 0.3,
and prints one line per planting with the verdicts' counts and statuses in rate order.
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np


def plant(stats, kind, phi_min):
    with h5py.File(stats, "r+") as f:
        for g in f["ensembles"].values():
            table = g["constant_phi/pressure_samples"]
            phi = g["constant_phi/packing_fraction"][:]
            if kind == "shift":
                factor = np.full_like(phi, 1.15)
            else:
                amplitude = float(kind.split("-")[1])
                factor = 1 + amplitude * np.exp(-np.clip(phi - phi_min, 0, None) / 0.002)
            table[...] = table[:] * factor[None, :]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("chained", type=Path)
    p.add_argument("control", type=Path)
    p.add_argument("--phi-min", type=float, required=True)
    p.add_argument("--jam", default="build/jam")
    a = p.parse_args()
    for d in (a.chained, a.control):
        if not (d / "stats.h5").is_file():
            sys.exit(f"chain_planted: {d}: no stats.h5 (run jam stats there first)")
    for kind in ("none", "shift", "edge-0.6", "edge-0.3"):
        with tempfile.TemporaryDirectory() as tmp:
            for name in ("stats.h5", "campaign.toml", "manifest.toml"):
                shutil.copy(a.chained / name, tmp)
            if kind != "none":
                plant(Path(tmp) / "stats.h5", kind, a.phi_min)
            command = [a.jam, "check", "chain", tmp, "--against", str(a.control),
                       "--phi-min", repr(a.phi_min)]
            try:
                done = subprocess.run(command, capture_output=True, text=True)
            except OSError as e:
                sys.exit(f"chain_planted: --jam {a.jam}: {e.strerror}")
            if done.returncode not in (0, 1, 3):
                sys.exit(f"chain_planted: {' '.join(command)}: {done.stderr.strip()}")
            verdicts = json.loads((Path(tmp) / "checks-chain.json").read_text())["verdicts"]
            statuses = [v["status"] for v in verdicts]
            bounds = [f"{v['excluded_above']:.3f}" for v in verdicts]
            print(f"{kind:9s} pass {statuses.count('pass')} fail {statuses.count('fail')} "
                  f"inconclusive {statuses.count('inconclusive')}: {' '.join(statuses)} "
                  f"(excluded above {' '.join(bounds)})")


if __name__ == "__main__":
    main()
