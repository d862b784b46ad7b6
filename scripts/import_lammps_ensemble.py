#!/usr/bin/env python3
"""Imports a directory of LAMMPS logs laid out as scripts/cross_lammps_runs.py writes them
(LOGDIR/r<log10 rate>/s<sample>.log, thermo `Step Time c_virial PotEng v_Z Volume` of
reference/lammps/compress_random.in) into an external campaign directory:

    scripts/import_lammps_ensemble.py LOGDIR CAMPAIGN_DIR [--jam build/jam] [--q 0.2]

Each log goes through `jam import lammps` with its columns named (the generic route of
docs/cross-simulator.md), then all of them through `jam campaign import`. The sample id is the
number in the log's name, so that sample k of every rate shares its start, as in the logs.
Programs are started from argument vectors (no shell). Exit status: jam's first non-zero one.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

COLUMNS = ["pressure=c_virial", "volume=Volume", "time=Time",
           "contacts_per_particle=v_Z", "energy_per_particle=PotEng"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("logdir")
    parser.add_argument("campaign_dir")
    parser.add_argument("--jam", default="jam")
    parser.add_argument("--q", type=float, help="Q of the LAMMPS runs (inertial); omit: overdamped")
    parser.add_argument("--diameter-ratio", type=float, default=1.4)
    args = parser.parse_args()
    logs = sorted(glob.glob(os.path.join(args.logdir, "r*", "s*.log")))
    if not logs:
        sys.exit(f"import_lammps_ensemble: {args.logdir}: no r*/s*.log")
    with tempfile.TemporaryDirectory() as work:
        runs = []
        for log in logs:
            rate_dir = os.path.basename(os.path.dirname(log))
            sample = re.fullmatch(r"s(\d+)\.log", os.path.basename(log))
            if not sample:
                continue
            out = os.path.join(work, f"{rate_dir}_{os.path.basename(log)[:-4]}.h5")
            argv = [args.jam, "import", "lammps", log, "--out", out,
                    "--diameter-ratio", repr(args.diameter_ratio), "--sample", sample.group(1)]
            for c in COLUMNS:
                argv += ["--column", c]
            if args.q is not None:
                argv += ["--q", repr(args.q)]
            status = subprocess.run(argv, stdout=subprocess.DEVNULL).returncode
            if status != 0:
                return status
            runs.append(out)
        return subprocess.run([args.jam, "campaign", "import", args.campaign_dir] + runs).returncode


if __name__ == "__main__":
    sys.exit(main())
