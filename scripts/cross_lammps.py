#!/usr/bin/env python3
"""The cross-simulator demonstration, end to end, stored in reference/results/cross-lammps/:

  1. LAMMPS compresses its own relaxed random starts (reference/lammps/compress_random.in via
     scripts/cross_lammps_runs.py; resumable): `right` (the model, 32 samples), and two planted
     wrong simulators with 10 samples, `d135` (big contact diameter 1.35) and `k110` (contact
     stiffness 1.1), planted in the input, not in the data;
  2. each ensemble's logs imported through the generic route (jam import lammps with its
     columns named, jam campaign import: scripts/import_lammps_ensemble.py) into
     runs/lammps-<name>, built beside it and renamed into place (an existing one is replaced
     only if this script made it, else refused);
  3. `jam pipeline reference/campaigns/cross-jam.toml --report reports/cross-lammps`: jam's own
     ensemble of the design, its statistics, those of the three imported campaigns
     (compare_with), every check with `compare` among them, and the report;
  4. the products copied into reference/results/cross-lammps/ (each written whole, then all
     renamed into place), with provenance.json (the cost
     of each part: LAMMPS wall seconds from its ensemble.json, jam's core seconds from its
     run records).

    scripts/cross_lammps.py [--logs /work/runs/cross-lammps] [--jam build/jam]

Every program is started from an argument vector. Run from the project root.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib

from script_files import Staged, fail

ENSEMBLES = {"right": (1.4, 1.0, 32), "d135": (1.35, 1.0, 10), "k110": (1.4, 1.1, 10)}
DESIGN = ["--n", "1024", "--dim", "2", "--phi-init", "0.75", "--phi-stop", "0.87",
          "--rates", "-4", "-5", "--first-seed", "1000", "--q", "0.2", "--dt", "0.064"]
STORED = "reference/results/cross-lammps"
# Written into each runs/lammps-<name> this script makes: only a directory holding it is
# replaced when the script runs again (one without it may be a campaign imported by hand).
MARKER = ".made-by-cross-lammps"


def run(argv):
    print("+", " ".join(argv), flush=True)
    status = subprocess.run(argv).returncode
    if status not in (0, 1, 3):  # jam check: 1 a verdict failed, 3 one inconclusive
        sys.exit(f"cross_lammps: {argv[0]} exited {status}")
    return status


def lammps_seconds(logs, name):
    with open(os.path.join(logs, name, "ensemble.json")) as f:
        e = json.load(f)
    runs = e.get("runs", []) + e.get("starts", [])
    return sum(r.get("wall_seconds", 0.0) for r in runs), e["parameters"]


def jam_core_seconds(directory):
    total = 0.0
    for record in glob.glob(os.path.join(directory, "runs", "*.record")):
        with open(record, "rb") as f:
            r = tomllib.load(f)
        total += r.get("cpu_seconds") or r.get("wall_seconds", 0.0)
    return total


def refuse_unless_ours(target):
    """Fails unless `target` is absent or a directory (not a link) this script made."""
    if not os.path.lexists(target):
        return
    if (os.path.islink(target) or not os.path.isdir(target)
            or not os.path.isfile(os.path.join(target, MARKER))
            or os.path.islink(os.path.join(target, MARKER))):
        fail(f"{target}: exists and was not made by this script (no {MARKER}); "
             f"move it away to have it made anew")


def import_ensemble(logs, name, jam):
    """runs/lammps-<name> imported anew: built beside it, marked, and renamed into place;
    the one it replaces was made by this script."""
    target = f"runs/lammps-{name}"
    os.makedirs("runs", exist_ok=True)
    work = tempfile.mkdtemp(prefix=f".lammps-{name}-", dir="runs")
    try:
        # Its own name: jam campaign import names the campaign after its directory.
        built = os.path.join(work, f"lammps-{name}")
        run([sys.executable, "scripts/import_lammps_ensemble.py", os.path.join(logs, name),
             built, "--jam", jam, "--q", "0.2"])
        if not os.path.isdir(built):
            fail(f"{os.path.join(logs, name)}: nothing imported")
        with open(os.path.join(built, MARKER), "w") as f:
            f.write("made by scripts/cross_lammps.py, which replaces this directory\n")
        refuse_unless_ours(target)
        if os.path.lexists(target):
            os.rename(target, os.path.join(work, "replaced"))
        os.rename(built, target)
    finally:
        shutil.rmtree(work)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--logs", default="/work/runs/cross-lammps")
    parser.add_argument("--jam", default="build/jam")
    args = parser.parse_args()
    started = time.time()
    for name in ENSEMBLES:  # refused before hours of LAMMPS, not after
        refuse_unless_ours(f"runs/lammps-{name}")
    for name, (d_big, stiffness, samples) in ENSEMBLES.items():
        run([sys.executable, "scripts/cross_lammps_runs.py", "--out",
             os.path.join(args.logs, name), *DESIGN, "--samples", str(samples),
             "--d-big", repr(d_big), "--stiffness", repr(stiffness)])
        import_ensemble(args.logs, name, args.jam)
    run([args.jam, "pipeline", "reference/campaigns/cross-jam.toml", "--report",
         "reports/cross-lammps"])
    # Everything is read first and the stored files are renamed into place together at the
    # end: a failure leaves them as they were, not some new and some old.
    copies = [(os.path.join("runs/cross-jam", f), os.path.join(STORED, f))
              for f in ("campaign.toml", "stats.h5", "checks.json")]
    cost = {"jam_campaign_core_seconds": jam_core_seconds("runs/cross-jam")}
    for name in ENSEMBLES:
        copies += [(os.path.join(f"runs/lammps-{name}", f),
                    os.path.join(STORED, f"lammps-{name}", f))
                   for f in ("external.toml", "stats.h5")]
        seconds, parameters = lammps_seconds(args.logs, name)
        cost[f"lammps_{name}_wall_seconds"] = round(seconds, 1)
        cost[f"lammps_{name}_parameters"] = parameters
    version = subprocess.run([args.jam, "--version"], capture_output=True, text=True).stdout
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    provenance = {"name": "cross-lammps", "command": "scripts/cross_lammps.py",
                  "code_version": version.splitlines()[0] if version else "", "git_commit": commit,
                  "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                  "wall_seconds_of_this_invocation": round(time.time() - started, 1), **cost}
    for name in ENSEMBLES:
        os.makedirs(os.path.join(STORED, f"lammps-{name}"), exist_ok=True)
    with Staged() as staged:
        for source, target in copies:
            staged.copy(source, target)
        staged.text(os.path.join(STORED, "provenance.json"),
                    json.dumps(provenance, indent=2) + "\n")
        staged.commit()
    print(f"stored in {STORED}")


if __name__ == "__main__":
    main()
