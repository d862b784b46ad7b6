#!/usr/bin/env python3
"""Re-judge a stored result: `jam check all` on its stored stats.h5 (nothing rerun), the new
checks.json copied back, and provenance.json told when and by which jam. A stats.h5 without
the per-size fits (fit/families) is first refitted from its own tables (`jam stats --refit`
at the stored fit's order: the tables, jamming points and representative fit stay as they
were) and copied back with them.

  scripts/rejudge.py reduced-2d [--jam build/jam] [--refit] [--reports]

--refit refits every stored fit with the current rules from the stored tables (`jam stats
--refit` at the stored order; the fits that hold the paper's values too, where stored:
fit-q-fixed.json, fit-held.json) before judging, and stores stats.h5 and the fit-*.json files
with checks.json. The runs and the averaged tables stay as they were. A refit reads the verdicts
it consults (stats/fit_verdicts.hpp: the finite_size verdicts that let the paper's protocol pool
sizes, the phi_init verdicts that clear a start's rates) from the stored checks.json, as `jam
pipeline` gives them; when judging anew changes those verdicts, it refits and judges again
until they hold (at most three rounds). --reports then writes
the stored reports anew from the judged copy: reports/NAME/ and, where it exists,
reports/NAME-q-fixed/ (the paper's q held, as scripts/reproduce.sh makes it).

The stored LAMMPS reference (reference/lammps) serves the lammps check (--no-lmp), so the
result does not depend on whether lmp is installed; --with-lammps keeps those verdicts in
checks.json (`check all` judges them only when asked). Works in a temporary copy; the stored
directory changes only when the check ran (exit 0, 1 or 3), by rename.
"""
import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile

from script_files import Staged, fail, open_input

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STORED_UNDER = os.path.join("reference", "results")


def families_missing(stats):
    """The stored fit's polynomial order when stats.h5 has a fit but no fit/families, else 0."""
    import h5py
    with h5py.File(stats, "r") as f:
        if "fit/representative" not in f or "fit/families" in f:
            return 0
        return int(f["fit/representative"].attrs["order"])


def stored_order(stats):
    """The polynomial order of the stored representative fit (the fit is redone at it)."""
    import h5py
    with h5py.File(stats, "r") as f:
        if "fit/representative" not in f:
            fail(f"rejudge: {stats}: no stored fit to redo")
        return int(f["fit/representative"].attrs["order"])


# The fits stored beside the result that hold the paper's values: file -> jam stats options.
# What a refit reads: the tables, the campaign file, and the verdicts it consults.
FIT_INPUTS = ("stats.h5", "campaign.toml", "checks.json")
ROUNDS = 3
HELD_FITS = {"fit-q-fixed.json": ("--fix-paper-q",),
             "fit-held.json": ("--fix-paper-exponents",)}


def to_json(source_dir, out_dir, name, order, options):
    """fit_to_json.py on SOURCE_DIR/stats.h5 into OUT_DIR/NAME, saying how it was made."""
    command = " ".join(("jam stats", "--order", str(order)) + tuple(options))
    subprocess.run([sys.executable, os.path.join(SOURCE, "scripts", "fit_to_json.py"),
                    os.path.join(source_dir, "stats.h5"), os.path.join(out_dir, name), command],
                   check=True, stdout=subprocess.DEVNULL)
    return name


def copy_fit_inputs(source, target):
    """The files a refit of SOURCE reads, copied into TARGET (checks.json where there is one)."""
    for f in FIT_INPUTS:
        if f != "checks.json" or os.path.isfile(os.path.join(source, f)):
            shutil.copy2(os.path.join(source, f), target)


def consulted_verdicts(directory):
    """The statuses of the verdicts in DIRECTORY/checks.json that a fit consults: finite_size's
    and phi_init's pooled ones (None without checks.json)."""
    path = os.path.join(directory, "checks.json")
    if not os.path.isfile(path):
        return None
    try:
        with open(path) as f:
            verdicts = json.load(f)["verdicts"]
        return sorted((v["check"], v["case"], v["status"]) for v in verdicts
                      if v["check"] in ("finite_size", "phi_init") and v["region"] == "pooled")
    except (ValueError, KeyError, TypeError):
        return "unreadable"  # jam's own refit refuses it, or judges it anew


def refit_stored_fits(jam, stored, work, tmp, order):
    """Each stored held fit redone from a copy of the stored tables; returns the file names
    written into WORK."""
    names = ()
    for name, options in HELD_FITS.items():
        if not os.path.isfile(os.path.join(stored, name)):
            continue
        held = os.path.join(tmp, "held-" + name)
        os.mkdir(held)
        copy_fit_inputs(work, held)
        subprocess.run([jam, "stats", held, "--refit", "--order", str(order), *options],
                       check=True, stdout=subprocess.DEVNULL)
        names += (to_json(held, work, name, order, options),)
    return names


def stored_copy(root, name):
    """An empty directory ROOT/reference/results/NAME for a working copy of a stored result:
    a report drawn from it, run from ROOT, names the campaign by the stored result's path, not
    by a temporary directory that is gone once the report is read."""
    path = os.path.join(root, STORED_UNDER, name)
    os.makedirs(path)
    return path


def draw_report(jam, root, name, out):
    """jam report of ROOT/reference/results/NAME into OUT, run from ROOT (see stored_copy)."""
    subprocess.run([jam, "report", os.path.join(STORED_UNDER, name), "--out", out, "--quiet"],
                   check=True, cwd=root)


def write_reports(jam, root, name):
    """reports/NAME from the judged copy under ROOT (its checks.h5 holds the figures' curves,
    which the stored result does not keep); reports/NAME-q-fixed from a copy refitted with the
    paper's q held, with the same verdicts (as scripts/reproduce.sh makes it)."""
    work = os.path.join(root, STORED_UNDER, name)
    reports = os.path.join(SOURCE, "reports")
    draw_report(jam, root, name, os.path.join(reports, name))
    q_fixed = os.path.join(reports, name + "-q-fixed")
    if not os.path.isdir(q_fixed):
        return
    with tempfile.TemporaryDirectory() as tmp:
        held = stored_copy(tmp, name)
        copy_fit_inputs(work, held)
        subprocess.run([jam, "stats", held, "--refit", "--order",
                        str(stored_order(os.path.join(held, "stats.h5"))), "--fix-paper-q"],
                       check=True, stdout=subprocess.DEVNULL)
        shutil.copy2(os.path.join(work, "checks.h5"), held)
        draw_report(jam, tmp, name, q_fixed)


def judge(jam, work):
    """jam check all on WORK. --with-lammps: the stored results keep their LAMMPS self-checks,
    which `check all` judges only when asked."""
    done = subprocess.run([jam, "check", "all", work, "--no-lmp", "--with-lammps",
                           "--reference-dir", os.path.join(SOURCE, "reference")])
    if done.returncode not in (0, 1, 3):
        sys.exit(f"rejudge: jam check exited {done.returncode}; nothing changed")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("name", help="a stored result under reference/results/")
    ap.add_argument("--jam", default=os.path.join(SOURCE, "build", "jam"))
    ap.add_argument("--refit", action="store_true",
                    help="refit the stored fits with the current rules before judging")
    ap.add_argument("--reports", action="store_true",
                    help="write reports/NAME (and NAME-q-fixed) anew afterwards")
    args = ap.parse_args()
    if os.sep in args.jam:  # a path, not a name on PATH: the reports are drawn elsewhere
        args.jam = os.path.abspath(args.jam)
    stored = os.path.join(SOURCE, STORED_UNDER, args.name)
    if not os.path.isfile(os.path.join(stored, "stats.h5")):
        sys.exit(f"rejudge: {stored}: no stored stats.h5")
    # Read before anything is replaced: a result re-judged must be recorded as such.
    path = os.path.join(stored, "provenance.json")
    with open_input(path, "provenance") as f:
        try:
            provenance = json.load(f)
        except ValueError as e:
            fail(f"provenance {path}: not JSON ({e})")
    if not isinstance(provenance, dict):
        fail(f"provenance {path}: not a JSON object")
    version = subprocess.run([args.jam, "--version"], capture_output=True, text=True,
                             check=True).stdout.splitlines()[0].split()[-1]
    with tempfile.TemporaryDirectory() as tmp:
        work = stored_copy(tmp, args.name)
        copy_fit_inputs(stored, work)
        refit = families_missing(os.path.join(work, "stats.h5"))
        if args.refit:
            refit = stored_order(os.path.join(work, "stats.h5"))
        for _ in range(ROUNDS):
            consulted = consulted_verdicts(work) if refit else None
            if refit:
                subprocess.run([args.jam, "stats", work, "--refit", "--order", str(refit)],
                               check=True, stdout=subprocess.DEVNULL)
            judge(args.jam, work)
            if not refit or consulted_verdicts(work) == consulted:
                break
        else:
            fail(f"rejudge: the verdicts the fit consults still change after {ROUNDS} rounds "
                 "of refit and judgement; nothing changed")
        fits = ()
        if args.refit:
            fits = refit_stored_fits(args.jam, stored, work, tmp, refit)
            fits += (to_json(work, work, "fit-free.json", refit, ()),)
        provenance["checks_rejudged"] = {
            "command": f"scripts/rejudge.py {args.name}",
            "code_version": version,
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "note": "checks.json judged anew from the stored stats.h5; the runs, the averages "
                    "and the representative fits are those of the stored result (per-size fits "
                    "added by jam stats --refit where missing)",
        }
        if args.refit:
            provenance["checks_rejudged"]["note"] = (
                "every stored fit refitted with the current rules from the stored tables "
                f"(jam stats --refit --order {refit}: stats.h5, {', '.join(fits)}), then "
                "checks.json judged anew; the runs and the averages are those of the stored "
                "result")
        with Staged() as staged:
            for name in ("checks.json",) + (("stats.h5",) if refit else ()) + fits:
                staged.copy(os.path.join(work, name), os.path.join(stored, name))
            staged.text(path, json.dumps(provenance, indent=2) + "\n")
            staged.commit()
        if args.reports:
            write_reports(args.jam, tmp, args.name)


if __name__ == "__main__":
    main()
