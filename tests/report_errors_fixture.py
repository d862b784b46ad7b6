"""What the cases of tests/test_report_errors.py share: the campaign copy (the stored
reduced-2d result, cut to a few ensembles and verdicts, with a checks.h5 written here), running the report, and the expectations
(one error line, nothing left behind, inert output). SOURCE is set by the driver."""

import collections
import contextlib
import errno
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np


SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


CAMPAIGN = os.path.join("reference", "results", "reduced-2d")


TIMEOUT = 300  # seconds for one report (about 12 s of CPU; more on a loaded machine): a hang fails its case


# The intact campaign's report, made once by test_report_errors.py's `intact` fixture.
INTACT_REPORT = None


def written_report(out):
    """A report jam wrote, at out: a copy of INTACT_REPORT, marker included (a report costs
    about 12 s of CPU; the cases that replace one need one to exist, not to be made anew)."""
    if INTACT_REPORT is None:
        raise AssertionError("no intact report: the driver makes it first")
    shutil.copytree(INTACT_REPORT, out, symlinks=True)
    return out


class Skip(Exception):
    """A case that cannot run here; the message says why."""


def report(directory, out, cwd=None, timeout=TIMEOUT, quiet=True):
    """reports/jam_report.py DIR [--out OUT] [--quiet], run in cwd; the completed process."""
    script = os.path.join(SOURCE, "reports", "jam_report.py")
    args = ([sys.executable, script, directory] + (["--quiet"] if quiet else [])
            + (["--out", out] if out else []))
    try:
        return subprocess.run(args, capture_output=True, text=True, timeout=timeout, cwd=cwd)
    except subprocess.TimeoutExpired as e:
        raise AssertionError(f"the report did not finish in {timeout} s") from e


def tree(root):
    """Every path under root (not following links), relative to it."""
    out = set()
    for directory, dirs, files in os.walk(root):
        for name in dirs + files:
            out.add(os.path.relpath(os.path.join(directory, name), root))
    return out


def expect_error(r, words, before, root):
    """Exit status 2, exactly one line on stderr holding `words`, nothing new under root."""
    lines = r.stderr.splitlines()
    if r.returncode != 2:
        raise AssertionError(f"exit status {r.returncode}, expected 2; {len(lines)} lines "
                             f"on stderr:\n{r.stderr}")
    if len(lines) != 1:
        raise AssertionError(f"{len(lines)} lines on stderr, expected 1:\n{r.stderr}")
    if not lines[0].startswith("jam report: error: "):
        raise AssertionError(f"not a jam report error: {lines[0]}")
    missing = [w for w in words if w not in lines[0]]
    if missing:
        raise AssertionError(f"{missing} not in: {lines[0]}")
    left = sorted(tree(root) - before)
    if left:
        raise AssertionError(f"left behind: {left}")
    return lines[0]


def synthetic_checks_h5(path, verdicts, with_curves=("finite_size",), points=400):
    """A checks.h5 for the verdicts (reference/schema.md): one group per verdict,
    finite-size-like curves on the verdicts of the checks in `with_curves` that were tested."""
    grid = np.linspace(0.80, 0.86, points)
    with h5py.File(path, "w") as f:
        f.attrs["version"] = "test"
        f.attrs["wall_time"] = 1.0
        for k, v in enumerate(verdicts):
            g = f.create_group(f"verdicts/{k:03d}_{v['check']}")
            for key in ("check", "case", "status"):
                g.attrs[key] = v[key]
            if v["check"] in with_curves and v["status"] != "skipped":
                g["grid"] = grid
                g["delta"] = 0.01 * np.sin(40 * grid)
                g["sigma"] = np.full_like(grid, 0.005)


def write_checks_h5(path, checks_json):
    """synthetic_checks_h5 for the verdicts of checks.json (schema 1 or 2)."""
    with open(checks_json) as f:
        verdicts = json.load(f)
    synthetic_checks_h5(path, verdicts["verdicts"] if isinstance(verdicts, dict) else verdicts)


# The cases test what the report does with its inputs and outputs, not a full campaign's
# figures: the stored campaign cut to two sizes and three rates (of 3 x 9 per phi_init) and the
# first few verdicts of each check still draws every figure, at about half the cost.
SIZES = (256, 1024)
RATES = (-4.0, -6.0, -8.0)
VERDICTS_PER_CHECK = 4


def small_campaign(out):
    """The stored campaign's stats.h5, checks.json and campaign.toml, cut to SIZES, RATES and
    VERDICTS_PER_CHECK, copied into out (created); returns checks.json's object."""
    os.mkdir(out)
    for name in ("stats.h5", "checks.json", "campaign.toml"):
        shutil.copy(os.path.join(SOURCE, CAMPAIGN, name), out)
    with h5py.File(os.path.join(out, "stats.h5"), "r+") as f:
        # Trimmed here, so no longer what `jam stats` sealed: the cases plant their own faults.
        f.attrs.pop("checksum", None)
        for name in list(f["ensembles"]):
            g = f["ensembles"][name]
            if int(g.attrs["n"]) not in SIZES or float(g.attrs["log10_rate"]) not in RATES:
                del f["ensembles"][name]
        if len(f["ensembles"]) != 2 * len(SIZES) * len(RATES):
            raise AssertionError(f"{CAMPAIGN}: {len(f['ensembles'])} ensembles of "
                                 f"{SIZES} x {RATES}, expected both phi_init")
    path = os.path.join(out, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    seen = collections.Counter()
    kept = []
    for v in checks["verdicts"]:
        seen[v["check"]] += 1
        if seen[v["check"]] <= VERDICTS_PER_CHECK:
            kept.append(v)
    checks["verdicts"] = kept
    with open(path, "w") as f:
        json.dump(checks, f, indent=1)
    return checks


def campaign(work):
    """small_campaign in work/campaign, with a checks.h5."""
    out = os.path.join(work, "campaign")
    small_campaign(out)
    write_checks_h5(os.path.join(out, "checks.h5"), os.path.join(out, "checks.json"))
    return out


@contextlib.contextmanager
def tmpfs(path, options):
    """A tmpfs mounted at path (created) for the body; Skip when mounting is not allowed."""
    os.mkdir(path)
    try:
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", path],
                           capture_output=True, text=True, timeout=30)
        why = r.stderr.strip() if r.returncode else ""
    except (OSError, subprocess.TimeoutExpired) as e:
        why = str(e)
    if why:
        raise Skip(f"mounting a tmpfs is not allowed here ({why})")
    try:
        yield path
    finally:
        r = subprocess.run(["umount", path], capture_output=True, text=True, timeout=30)
        if r.returncode:
            print(f"  could not unmount {path}: {r.stderr.strip()}")


def fill(directory):
    """Writes directory/filler until the file system is full."""
    block = b"\0" * 65536
    with open(os.path.join(directory, "filler"), "wb", buffering=0) as f:
        while True:
            try:
                f.write(block)
            except OSError as e:
                if e.errno == errno.ENOSPC:
                    return
                raise


def contents(root):
    """Every path under root with the bytes of each file, for a before/after comparison."""
    out = {}
    for path in sorted(tree(root)):
        full = os.path.join(root, path)
        out[path] = None if os.path.isdir(full) else open(full, "rb").read()
    return out


def expect_untouched(r, words, root, before):
    """Refused in one line holding `words`, and every file under root as it was."""
    expect_error(r, words, set(before), root)
    if contents(root) != before:
        raise AssertionError("files under the work directory were changed or removed")


HOSTILE = '<script>alert(1)</script><img src=x onerror="alert(2)">\x1b[31m'


def report_text(out):
    """index.html and summary.txt of a finished report, as text."""
    with open(os.path.join(out, "index.html"), encoding="utf-8") as f:
        page = f.read()
    with open(os.path.join(out, "summary.txt"), encoding="utf-8") as f:
        return page, f.read()


def expect_inert(page, where, markup=True):
    """No control character, and (in HTML: `markup`) no markup from a file left unescaped."""
    for raw in (("<script", "<img src=x", 'onerror="') if markup else ()) + ("\x1b", "\x00"):
        if raw in page:
            raise AssertionError(f"{where}: {raw!r} reached it unescaped")
