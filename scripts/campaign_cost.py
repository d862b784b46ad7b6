#!/usr/bin/env python3
"""The measured cost of a campaign directory: CPU seconds per ensemble from the runs' records,
the chained starts left again (from the campaign's logs), and an estimate for records that
hold fewer CPU seconds than their runs took.

    scripts/campaign_cost.py RUN_DIR [--log FILE ...] [--json]

A record counts the CPU seconds of every attempt of its run since checkpoints carry them
(2026-11-27); a run stopped and resumed before that kept only its last attempt's. Such a
record is found by its cost per force evaluation (run files count evaluations across resumes,
the `force_evaluations` attribute): below SHORT times the median of its size, it is short, and
its estimate is its evaluations at the median cost per evaluation of its ensemble's other
runs (of its size's, when fewer than three are left). Only runs without a jamming-point
search are judged (its minimizations cost CPU that force_evaluations does not count), and
only at sizes whose runs take a minute or more (MIN_CPU). A chained start left again by a done
parent (docs/campaigns.md, chained starts) writes no record; its CPU seconds are in the log
line `... left its start at PHI again (S CPU seconds)`. Every such line counts (a start left
again twice, on two machines, cost twice); a log given twice, or an earlier copy of another
(the snapshot's copy of the run directory's log: its prefix), counts once.
Reads only; prints a table, or JSON with --json.
"""
import argparse
import glob
import json
import os
import re
import statistics
import sys
import tomllib
import typing

import h5py

SHORT = 0.75  # a record below 3/4 of its size's median cost per evaluation is short
# Below a median of a minute per run, a run's fixed costs (relaxation, set-up, output) weigh
# in its cost per evaluation and a short record cannot be told from a cheap one; a lost
# attempt of such runs is small anyway.
MIN_CPU = 60.0
NAME = re.compile(r"n(\d+)_phi([\d.]+)_r(-?[\d.]+)_s(\d+)$")
AGAIN = re.compile(r"campaign \S+: (\S+) left its start at \S+ again \((\d+) CPU seconds\)")


def fail(message):
    print(f"campaign_cost: {message}", file=sys.stderr)
    sys.exit(2)


class Run(typing.NamedTuple):
    name: str
    n: int
    phi_init: float
    log10_rate: float
    cpu: float  # the record's CPU seconds (its wall seconds where it has none)
    evaluations: float  # force evaluations of the dynamics, across resumes
    judged: bool  # whether a short record could be told from it (see MIN_CPU)


def done_runs(directory):
    """Every done run of the directory, in name order."""
    out = []
    for record in sorted(glob.glob(os.path.join(directory, "runs", "*.record"))):
        name = os.path.basename(record)[: -len(".record")]
        match = NAME.match(name)
        if not match:
            continue
        with open(record, "rb") as f:
            r = tomllib.load(f)
        if r.get("status") != "done":
            continue
        with h5py.File(os.path.join(directory, "runs", name + ".h5"), "r") as f:
            evaluations = f.attrs.get("force_evaluations")
            searched = float(f.attrs.get("jamming_minimizations", 0)) > 0
        if evaluations is None or not float(evaluations) > 0:
            fail(f"{name}.h5: no force_evaluations attribute")
        cpu = float(r.get("cpu_seconds") or r.get("wall_seconds", 0))
        out.append(Run(name, int(match[1]), float(match[2]), float(match[3]), cpu,
                       float(evaluations), not searched))
    return out


def starts_again(logs):
    """(run, CPU seconds) of every chained start left again, from the logs; a log that is a
    copy of another, or an earlier copy (its prefix), is left out."""
    texts = []
    for path in logs:
        if os.path.exists(path) and not os.path.isfile(path):
            fail(f"--log: {path}: not a regular file")  # a FIFO would block the read
        try:
            with open(path, "rb") as f:
                texts.append(f.read())
        except OSError as e:
            fail(f"--log: {path}: {e.strerror}")
    kept, out = [], []
    for text in sorted(texts, key=len, reverse=True):
        if any(k.startswith(text) for k in kept):
            continue
        kept.append(text)
        for line in text.decode(errors="replace").splitlines():
            m = AGAIN.search(line)
            if m:
                out.append((m[1], int(m[2])))
    return sorted(out)


def short_records(runs):
    """The runs whose records are short, each with its estimate."""
    per_size = {}
    for r in runs:
        if r.judged:
            per_size.setdefault(r.n, []).append(r)
    out = {}
    for n, sized in per_size.items():
        if statistics.median(r.cpu for r in sized) < MIN_CPU:
            continue
        median = statistics.median(r.cpu / r.evaluations for r in sized)
        short = {r.name for r in sized if r.cpu / r.evaluations < SHORT * median}
        for r in sized:
            if r.name not in short:
                continue
            siblings = [x.cpu / x.evaluations for x in sized if x.name not in short
                        and (x.phi_init, x.log10_rate) == (r.phi_init, r.log10_rate)]
            per_ev = statistics.median(siblings) if len(siblings) >= 3 else median
            out[r.name] = {"run": r.name, "cpu_seconds": r.cpu,
                           "force_evaluations": r.evaluations,
                           "estimated_cpu_seconds": r.evaluations * per_ev,
                           "missing_cpu_seconds": r.evaluations * per_ev - r.cpu}
    return out


def account(runs, again):
    short = short_records(runs)
    ensembles = {}
    for r in runs:
        e = ensembles.setdefault((r.n, r.phi_init, r.log10_rate),
                                 {"runs": 0, "cpu": 0.0, "short": 0})
        e["runs"] += 1
        e["cpu"] += r.cpu
        e["short"] += r.name in short
    rows = [{"n": n, "phi_init": phi, "log10_rate": rate, "runs": e["runs"],
             "cpu_seconds": e["cpu"], "short_records": e["short"]}
            for (n, phi, rate), e in sorted(ensembles.items())]
    estimated = [short[name] for name in sorted(short)]
    recorded = sum(r["cpu_seconds"] for r in rows)
    missing = sum(x["missing_cpu_seconds"] for x in estimated)
    again_cpu = sum(s for _, s in again)
    return {"ensembles": rows, "short_records": estimated,
            "starts_again": [{"run": r, "cpu_seconds": s} for r, s in again],
            "cpu_seconds_recorded": recorded, "cpu_seconds_missing_estimate": missing,
            "cpu_seconds_starts_again": again_cpu,
            "cpu_seconds_total": recorded + missing + again_cpu}


def print_table(a):
    print(f"{'N':>7} {'phi_init':>8} {'log10 rate':>10} {'runs':>5} {'CPU h':>8} {'short':>6}")
    for r in a["ensembles"]:
        print(f"{r['n']:>7} {r['phi_init']:>8.4f} {r['log10_rate']:>10.2f} {r['runs']:>5} "
              f"{r['cpu_seconds'] / 3600:>8.3f} {r['short_records']:>6}")
    for x in a["short_records"]:
        print(f"short record {x['run']}: {x['cpu_seconds']:.0f} CPU s for "
              f"{x['force_evaluations']:.0f} evaluations, "
              f"estimated {x['estimated_cpu_seconds']:.0f}")
    print(f"recorded {a['cpu_seconds_recorded'] / 3600:.2f} CPU h, short records' estimated "
          f"rest {a['cpu_seconds_missing_estimate'] / 3600:.2f}, {len(a['starts_again'])} starts "
          f"left again {a['cpu_seconds_starts_again'] / 3600:.2f}: "
          f"{a['cpu_seconds_total'] / 3600:.2f} CPU h in all")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", help="campaign directory (its 'output')")
    parser.add_argument("--log", nargs="*", default=[], help="the campaign's logs")
    parser.add_argument("--json", action="store_true", help="JSON instead of a table")
    a = parser.parse_args()
    if not os.path.isdir(os.path.join(a.directory, "runs")):
        fail(f"{a.directory}: no runs/ directory (not a campaign directory)")
    runs = done_runs(a.directory)
    if not runs:
        fail(f"{a.directory}: no done runs")
    result = account(runs, starts_again(a.log))
    if a.json:
        json.dump(result, sys.stdout, indent=1)
        print()
    else:
        print_table(result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
