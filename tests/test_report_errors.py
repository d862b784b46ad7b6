#!/usr/bin/python3
"""`jam report` (reports/jam_report.py) on inputs it cannot read and outputs it cannot write:
each case must fail in one line on stderr, `jam report: error: <file>: <cause>`, with exit
status 2, naming the cause, and leave nothing behind: no temporary directory, no directory the
report created on the way, the output path as it was.

The campaign is the stored reduced-scale 2D result (reference/results/reduced-2d) with a
checks.h5 written here, so no `jam` binary is needed. The read-only file system and the full
disk are small tmpfs mounts; where mounting is not allowed the full disk is skipped, and the
read-only case uses a mode-0555 directory instead (which only a user other than root feels).

Usage (ctest runs it): test_report_errors.py --source .
Prints one line per case and a last line `N passed, M failed`; exit status 1 if any failed.
"""

import argparse
import contextlib
import errno
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile

import h5py
import numpy as np

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CAMPAIGN = os.path.join("reference", "results", "reduced-2d")
TIMEOUT = 300  # seconds for one report (about 25 s of CPU; more on a loaded machine): a hang fails its case


class Skip(Exception):
    """A case that cannot run here; the message says why."""


def report(directory, out, cwd=None, timeout=TIMEOUT):
    """reports/jam_report.py DIR [--out OUT] --quiet, run in cwd; the completed process."""
    script = os.path.join(SOURCE, "reports", "jam_report.py")
    args = [sys.executable, script, directory, "--quiet"] + (["--out", out] if out else [])
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


def write_checks_h5(path, checks_json):
    """A checks.h5 for checks.json (reference/schema.md): one group per verdict, finite-size
    curves on the ones that were tested."""
    with open(checks_json) as f:
        verdicts = json.load(f)
    if isinstance(verdicts, dict):
        verdicts = verdicts["verdicts"]
    grid = np.linspace(0.80, 0.86, 400)
    with h5py.File(path, "w") as f:
        f.attrs["version"] = "test"
        f.attrs["wall_time"] = 1.0
        for k, v in enumerate(verdicts):
            g = f.create_group(f"verdicts/{k:03d}_{v['check']}")
            for key in ("check", "case", "status"):
                g.attrs[key] = v[key]
            if v["check"] == "finite_size" and v["status"] != "skipped":
                g["grid"] = grid
                g["delta"] = 0.01 * np.sin(40 * grid)
                g["sigma"] = np.full_like(grid, 0.005)


def campaign(work):
    """A copy of the stored campaign in work/campaign, with a checks.h5."""
    out = os.path.join(work, "campaign")
    os.mkdir(out)
    for name in ("stats.h5", "checks.json", "campaign.toml"):
        shutil.copy(os.path.join(SOURCE, CAMPAIGN, name), out)
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


def case_random_stats(work):
    """stats.h5 is random bytes: fails before anything is drawn or created."""
    camp = campaign(work)
    with open(os.path.join(camp, "stats.h5"), "wb") as f:
        f.write(np.random.default_rng(1).bytes(65536))
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["stats.h5", "not a readable stats file"], before, work)


def case_missing_dataset(work):
    """stats.h5 is HDF5 but an ensemble lacks the pressure the figures draw."""
    camp = campaign(work)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        first = sorted(f["ensembles"])[0]
        del f[f"ensembles/{first}/constant_phi/pressure_mean"]
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["stats.h5", "pressure_mean", "missing"], before, work)


def case_truncated_checks(work):
    """checks.h5 cut to half its length, as a full disk or a crash leaves it."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.h5")
    os.truncate(path, os.path.getsize(path) // 2)
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["checks.h5", "not a readable checks file"], before, work)


def case_read_only(work):
    """The output's parent is on a read-only file system (root) or mode 0555 (other users)."""
    camp = campaign(work)
    target = os.path.join(work, "ro")
    if os.geteuid() != 0:
        os.mkdir(target, 0o555)
        try:
            read_only_report(camp, work, target, "permission denied")
        finally:
            os.chmod(target, 0o755)
        return
    with tmpfs(target, "ro,size=1m"):
        read_only_report(camp, work, target, "read-only file system")


def read_only_report(camp, work, target, cause):
    before = tree(work)
    r = report(camp, os.path.join(target, "reports", "r"))
    expect_error(r, [target, cause], before, work)


def case_full_disk(work):
    """The output goes to a full 1 MB file system: no report, and no reports/ left there."""
    camp = campaign(work)
    with tmpfs(os.path.join(work, "full"), "size=1m") as full:
        fill(full)
        before = tree(work)
        r = report(camp, os.path.join(full, "reports", "r"))
        expect_error(r, [os.path.join(full, "reports", "r"), "no space left on device"],
                     before, work)


def case_fifo(work):
    """--out is a FIFO: refused before any work, the FIFO left as it was."""
    camp = campaign(work)
    fifo = os.path.join(work, "fifo")
    os.mkfifo(fifo)
    before = tree(work)
    r = report(camp, fifo)
    expect_error(r, [fifo, "FIFO", "not a directory"], before, work)
    if not stat.S_ISFIFO(os.lstat(fifo).st_mode):
        raise AssertionError(f"{fifo} is no longer a FIFO")


def case_regular_file(work):
    """--out is a regular file: refused, the file unchanged."""
    camp = campaign(work)
    path = os.path.join(work, "notes.txt")
    with open(path, "w") as f:
        f.write("notes\n")
    before = tree(work)
    r = report(camp, path)
    expect_error(r, [path, "regular file", "not a directory"], before, work)
    with open(path) as f:
        if f.read() != "notes\n":
            raise AssertionError(f"{path} was changed")


def case_not_a_report(work):
    """--out is a directory of other files: refused, not replaced (which would delete them)."""
    camp = campaign(work)
    path = os.path.join(work, "data")
    os.mkdir(path)
    with open(os.path.join(path, "results.csv"), "w") as f:
        f.write("1,2\n")
    before = tree(work)
    r = report(camp, path)
    expect_error(r, [path, "not a report"], before, work)


def case_symbolic_link(work):
    """--out is a symbolic link to a directory: written through, the link kept."""
    camp = campaign(work)
    target = os.path.join(work, "real")
    os.mkdir(target)
    link = os.path.join(work, "link")
    os.symlink(target, link)
    r = report(camp, link)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    if not os.path.islink(link) or os.path.realpath(link) != os.path.realpath(target):
        raise AssertionError(f"{link} is no longer the same symbolic link")
    if not os.path.isfile(os.path.join(target, "index.html")):
        raise AssertionError(f"no report in the link's target {target}")


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


def case_site_with_thesis_and_data_survives(work):
    """--out site holding index.html, thesis.tex and data/ (the attack that deleted them): a
    directory jam did not write is refused, whatever it holds."""
    camp = campaign(work)
    site = os.path.join(work, "site")
    os.makedirs(os.path.join(site, "data"))
    for name, text in (("index.html", "x\n"), ("thesis.tex", "t\n")):
        with open(os.path.join(site, name), "w") as f:
            f.write(text)
    before = contents(work)
    expect_untouched(report(camp, site), [site, "not a report jam wrote"], work, before)


def case_out_dot_is_the_working_directory(work):
    """`--out .` in a directory holding an index.html and the campaign: refused, the campaign
    kept (it once deleted the campaign)."""
    camp = campaign(work)
    with open(os.path.join(work, "index.html"), "w") as f:
        f.write("x\n")
    before = contents(work)
    r = report(os.path.relpath(camp, work), ".", cwd=work)
    expect_untouched(r, ["the working directory"], work, before)


def case_out_is_the_campaign_or_its_parent(work):
    camp = campaign(work)
    before = contents(work)
    for out in (camp, work):
        expect_untouched(report(camp, out), [out, "the campaign"], work, before)


def case_campaign_named_dot_dot(work):
    """A stats.h5 whose campaign name is '..', no --out, a summary.txt in the working
    directory: refused (the default reports/.. once replaced the working directory)."""
    camp = campaign(work)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        f.attrs["campaign"] = ".."
    with open(os.path.join(work, "summary.txt"), "w") as f:
        f.write("mine\n")
    before = contents(work)
    r = report(os.path.relpath(camp, work), None, cwd=work)
    expect_untouched(r, ["campaign name '..'", "--out"], work, before)


def case_own_report_replaced_foreign_file_refused(work):
    """A report jam wrote (it holds .jam-report) is replaced; once a file of someone else's is
    put into it, it is refused and the file kept; a report of an older version (no marker,
    only report files) is replaced too."""
    camp = campaign(work)
    out = os.path.join(work, "r")
    for attempt in range(2):
        r = report(camp, out)
        if r.returncode != 0 or not os.path.isfile(os.path.join(out, ".jam-report")):
            raise AssertionError(f"attempt {attempt}: exit {r.returncode}: {r.stderr}")
    with open(os.path.join(out, "notes.txt"), "w") as f:
        f.write("mine\n")
    before = contents(work)
    expect_untouched(report(camp, out), [out, "'notes.txt'"], work, before)
    os.remove(os.path.join(out, "notes.txt"))
    os.remove(os.path.join(out, ".jam-report"))
    r = report(camp, out)
    if r.returncode != 0 or not os.path.isfile(os.path.join(out, ".jam-report")):
        raise AssertionError(f"an older report was not replaced: exit {r.returncode}: {r.stderr}")


# Markup and terminal control sequences in every field the report shows.
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


def case_hostile_values_are_escaped(work):
    """Every string of checks.json, stats.h5, manifest.toml and campaign.toml that the page
    shows, and the numbers of the fit written as strings, reach the page escaped and the
    terminal with their control characters made visible (a <script> once ran in Chromium)."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    for v in checks["verdicts"]:
        v["case"] = v["case"] + HOSTILE + "\x00"
        v["reason"] = HOSTILE
        v["statistic_name"] = HOSTILE
    with open(path, "w") as f:
        json.dump(checks, f)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        f.attrs["campaign"] = HOSTILE
        f.attrs["version"] = HOSTILE
        rep = f["fit/representative"]
        for name in ("quality", "quality_reason", "fixed", "start", "chosen_because",
                     "error_method"):
            rep.attrs[name] = HOSTILE
    with open(os.path.join(camp, "manifest.toml"), "w") as f:
        f.write(f"campaign_file = {json.dumps(HOSTILE)}\ncode_version = {json.dumps(HOSTILE)}\n")
    with open(os.path.join(camp, "campaign.toml"), "a") as f:
        f.write("# " + HOSTILE + "\n")
    out = os.path.join(work, "r")
    script = os.path.join(SOURCE, "reports", "jam_report.py")
    r = subprocess.run([sys.executable, script, camp, "--out", out], capture_output=True,
                       text=True, timeout=TIMEOUT)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    page, summary = report_text(out)
    expect_inert(page, "index.html")
    expect_inert(summary, "summary.txt", markup=False)
    expect_inert(r.stdout, "standard output", markup=False)
    if "\\x1b[31m" not in summary:
        raise AssertionError("the escape sequence is not shown, visibly, in summary.txt")
    if "&lt;script&gt;" not in page:
        raise AssertionError("the hostile values are not on the page at all (nothing tested)")


def case_markup_in_a_number_of_the_fit_is_refused(work):
    """`iterations`, `points`, `samples` (and every other number of the fit) holding markup:
    one line naming the attribute, no report (they once reached the page unescaped)."""
    camp = campaign(work)
    stats = os.path.join(camp, "stats.h5")
    for name in ("iterations", "points", "samples", "phi_min", "chi2_diag_per_dof"):
        with h5py.File(stats, "r+") as f:
            rep = f["fit/representative"]
            kept = rep.attrs[name]
            rep.attrs[name] = HOSTILE
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r")),
                     [stats, f"attribute '{name}'", "not a number"], before, work)
        with h5py.File(stats, "r+") as f:
            f["fit/representative"].attrs[name] = kept


def case_a_huge_case_name_gives_a_small_summary(work):
    """A 20 MB case name: shown shortened with its length, not padded into every row (a 50 MB
    one once made a 2 GB summary.txt)."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    checks["verdicts"][0]["case"] = "x" * 20_000_000
    with open(path, "w") as f:
        json.dump(checks, f)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    for name in ("summary.txt", "index.html"):
        size = os.path.getsize(os.path.join(out, name))
        if size > 2_000_000:
            raise AssertionError(f"{name} is {size} bytes")
    if "(20000000 characters)" not in report_text(out)[1]:
        raise AssertionError("the shortened case does not say its length")


def case_mistyped_checks_fields(work):
    """A checks.json field of the wrong type: one line naming the file, the verdict, the field
    and the value, exit 2, no report (these once gave tracebacks)."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        original = json.load(f)
    for field, value, says in (("statistic", "abc", "field 'statistic' is 'abc', not a number"),
                               ("case", 42, "field 'case' is 42, not a string"),
                               ("margin", [1, 2], "field 'margin' is [1, 2], not a number"),
                               ("status", "maybe", "field 'status' is 'maybe'"),
                               ("expected_failure", "yes",
                                "field 'expected_failure' is 'yes', not true or false"),
                               ("values", "none", "field 'values' is 'none', not an object")):
        checks = json.loads(json.dumps(original))
        checks["verdicts"][3][field] = value
        with open(path, "w") as f:
            json.dump(checks, f)
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r")), [path, "verdict 3", says], before,
                     work)


def case_site_with_only_index_html_survives(work):
    """--out site holding only a user's index.html (no .jam-report): refused, the file kept (a
    directory of an index.html and figure-like names once passed for an older report)."""
    camp = campaign(work)
    site = os.path.join(work, "site")
    os.mkdir(site)
    for name in ("index.html", "photo.png"):
        with open(os.path.join(site, name), "w") as f:
            f.write("x\n")
    before = contents(work)
    expect_untouched(report(camp, site), [site, "not a report jam wrote"], work, before)


def case_marker_cannot_claim_a_users_file(work):
    """A .jam-report (hand-made or damaged) listing thesis.tex beside index.html: thesis.tex is
    not a file a report writes, so the directory is refused and thesis.tex kept (it was
    deleted as the report's own)."""
    camp = campaign(work)
    site = os.path.join(work, "site")
    os.mkdir(site)
    for name, text in (("index.html", "x\n"), ("thesis.tex", "t\n"),
                       (".jam-report", "index.html\nthesis.tex\n")):
        with open(os.path.join(site, name), "w") as f:
            f.write(text)
    before = contents(work)
    expect_untouched(report(camp, site), [site, "'thesis.tex'", "not replaced"], work, before)


def case_directory_named_like_a_figure_is_not_owned(work):
    """A report jam wrote, then a directory extra.png/ with a file in it, listed in the marker:
    refused and kept in place (the directory was moved aside into `r.old-*` with a warning)."""
    camp = campaign(work)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    os.mkdir(os.path.join(out, "extra.png"))
    with open(os.path.join(out, "extra.png", "mine.txt"), "w") as f:
        f.write("mine\n")
    with open(os.path.join(out, ".jam-report"), "a") as f:
        f.write("extra.png\n")
    before = contents(work)
    expect_untouched(report(camp, out), [out, "'extra.png'", "not replaced"], work, before)


def case_stored_reports_stay_republishable(work):
    """Each stored report (reports/reduced-*) carries .jam-report and is taken as jam's with it
    and, as an older jam left it, without it (report_output.check_target); one of them is
    replaced by a new report, marked and unmarked, without a word on stderr."""
    sys.path.insert(0, os.path.join(SOURCE, "reports"))
    import report_output
    camp = campaign(work)
    stored = sorted(d for d in os.listdir(os.path.join(SOURCE, "reports"))
                    if d.startswith("reduced-"))
    if not stored:
        raise AssertionError("no stored reports in reports/")
    for name in stored:
        out = os.path.join(work, name)
        shutil.copytree(os.path.join(SOURCE, "reports", name), out)
        if not os.path.isfile(os.path.join(out, ".jam-report")):
            raise AssertionError(f"reports/{name} has no .jam-report")
        for marked in (True, False):
            if not marked:
                os.remove(os.path.join(out, ".jam-report"))
            try:
                report_output.check_target(out, camp)
            except report_output.ReportOutputError as e:
                raise AssertionError(f"reports/{name} (marker {marked}) refused: {e}") from e
            if name == stored[0]:
                r = report(camp, out)
                if r.returncode != 0 or r.stderr.strip():
                    raise AssertionError(f"reports/{name} (marker {marked}) not replaced: "
                                         f"exit {r.returncode}: {r.stderr}")
                shutil.rmtree(out)
                shutil.copytree(os.path.join(SOURCE, "reports", name), out)


# Hostile text for every string field: markup for the page, an attribute breaking out of its
# quotes, a NUL and an escape sequence for the terminal, TeX for matplotlib.
HOSTILE_ALL = '<script>alert(1)</script>"onerror=alert(2) \x00\x1b[31m $\\frac{1}$'


def hostile_bytes(text):
    """text as a fixed-length HDF5 string (a variable-length one cannot hold a NUL)."""
    return np.bytes_(text.encode("utf-8"))


def write_lammps_curves(camp):
    """Curves for the LAMMPS verdicts in checks.h5, so the LAMMPS figure (whose panels are
    titled with the case) is drawn."""
    grid = np.linspace(0.80, 0.86, 20)
    with h5py.File(os.path.join(camp, "checks.h5"), "r+") as f:
        for g in f["verdicts"].values():
            if g.attrs["check"] == "lammps":
                for key in ("grid", "pressure_jam", "pressure_lammps", "delta", "sigma"):
                    g[key] = 0.01 * grid + 0.001


def make_every_field_hostile(camp):
    """HOSTILE_ALL in every string of checks.json, checks.h5, stats.h5, manifest.toml and
    campaign.toml that the report reads; check names changed alike in checks.json, its
    registry and checks.h5, so every figure is still drawn."""
    write_lammps_curves(camp)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    for key in ("campaign", "code_version", "created"):
        checks[key] = HOSTILE_ALL
    for entry in checks["checks"]:
        entry["name"] += HOSTILE_ALL
        entry["margin_reason"] = HOSTILE_ALL
    for v in checks["verdicts"]:
        v["check"] += HOSTILE_ALL
        for key in ("case", "reason", "statistic_name"):
            v[key] = v[key] + HOSTILE_ALL
        v.setdefault("values", {})["note"] = HOSTILE_ALL
    with open(path, "w") as f:
        json.dump(checks, f)
    with h5py.File(os.path.join(camp, "checks.h5"), "r+") as f:
        f.attrs["version"] = hostile_bytes(HOSTILE_ALL)
        for g in f["verdicts"].values():
            for key in ("check", "case"):
                g.attrs[key] = hostile_bytes(g.attrs[key] + HOSTILE_ALL)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        for key in ("campaign", "version"):
            f.attrs[key] = hostile_bytes(HOSTILE_ALL)
        for key in ("rates_note", "failure"):
            f["fit"].attrs[key] = hostile_bytes(HOSTILE_ALL)
        for key in ("quality", "quality_reason", "fixed", "start", "chosen_because",
                    "error_method"):
            f["fit/representative"].attrs[key] = hostile_bytes(HOSTILE_ALL)
        f["fit/scan"].attrs["failures"] = hostile_bytes("row 1: " + HOSTILE_ALL)
    with open(os.path.join(camp, "manifest.toml"), "w") as f:
        f.write(f"campaign_file = {json.dumps(HOSTILE_ALL)}\n"
                f"code_version = {json.dumps(HOSTILE_ALL)}\n")
    with open(os.path.join(camp, "campaign.toml"), "a") as f:
        f.write("# " + HOSTILE_ALL + "\n")


def expect_inert_svg(path):
    """An SVG that is well-formed XML, with no script element, no on* attribute and no
    control character."""
    import xml.etree.ElementTree as ET
    with open(path, "rb") as f:
        data = f.read()
    if b"\x00" in data or b"\x1b" in data:
        raise AssertionError(f"{path}: a control character reached it raw")
    try:
        root = ET.fromstring(data)
    except ET.ParseError as e:
        raise AssertionError(f"{path}: not well-formed XML ({e})") from e
    for element in root.iter():
        if element.tag.rsplit("}", 1)[-1] == "script":
            raise AssertionError(f"{path}: holds a script element")
        handlers = [a for a in element.attrib if a.lower().startswith("on")]
        if handlers:
            raise AssertionError(f"{path}: an element has the handlers {handlers}")


def case_hostile_values_in_every_field(work):
    """<script>, "onerror=, NUL, ESC[31m and TeX in every string of stats.h5, checks.json,
    checks.h5, manifest.toml and campaign.toml, with the LAMMPS figure drawn: the page holds
    them escaped, every SVG is well-formed XML without scripts or handlers, the summary, the
    CSV files, stdout and stderr hold no raw control character (the LAMMPS figure's SVG held a
    raw NUL and ESC, matplotlib's warnings printed the ESC raw)."""
    camp = campaign(work)
    make_every_field_hostile(camp)
    out = os.path.join(work, "r")
    script = os.path.join(SOURCE, "reports", "jam_report.py")
    r = subprocess.run([sys.executable, script, camp, "--out", out], capture_output=True,
                       text=True, timeout=TIMEOUT)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    page, summary = report_text(out)
    expect_inert(page, "index.html")
    if '"onerror' in page:
        raise AssertionError("index.html: a quote from a file reached it unescaped")
    for name, text in (("summary.txt", summary), ("standard output", r.stdout),
                       ("standard error", r.stderr)):
        expect_inert(text, name, markup=False)
    if "lammps.svg" not in os.listdir(out):
        raise AssertionError("the LAMMPS figure was not drawn (nothing tested)")
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name)
        if name.endswith(".svg"):
            expect_inert_svg(path)
        elif name.endswith(".csv"):
            with open(path, encoding="utf-8") as f:
                expect_inert(f.read(), name, markup=False)
    if page.count("&lt;script&gt;") < 10 or "\\x1b[31m" not in summary:
        raise AssertionError("the hostile values are not shown (nothing tested)")


def case_dollar_in_a_case_name_is_text(work):
    """A case name holding `$\\frac{1}$` (TeX matplotlib cannot parse) titles the LAMMPS panel
    as text: the report is drawn (it stopped with a mathtext ValueError)."""
    camp = campaign(work)
    write_lammps_curves(camp)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    for v in checks["verdicts"]:
        v["case"] += " $\\frac{1}$"
    with open(path, "w") as f:
        json.dump(checks, f)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0 or not os.path.isfile(os.path.join(out, "lammps.png")):
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")


def edit_json(key, value, where="verdict"):
    """An edit of checks.json: `key` of every verdict's values (where 'values'), of every
    registry entry (where 'checks') set to `value`."""
    def edit(camp):
        path = os.path.join(camp, "checks.json")
        with open(path) as f:
            checks = json.load(f)
        for x in (checks["checks"] if where == "checks" else checks["verdicts"]):
            (x.setdefault("values", {}) if where == "values" else x)[key] = value
        with open(path, "w") as f:
            json.dump(checks, f)
    return edit


def edit_h5(name, obj, key, value):
    """An edit of the HDF5 file `name`: attribute `key` of `obj` set to `value` (obj '*' for
    every ensemble)."""
    def edit(camp):
        with h5py.File(os.path.join(camp, name), "r+") as f:
            targets = list(f["ensembles"].values()) if obj == "*" else [f[obj]]
            for t in targets:
                t.attrs[key] = hostile_bytes(value) if isinstance(value, str) else value
    return edit


def edit_dataset(path, value):
    def edit(camp):
        with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
            first = sorted(f["ensembles"])[0]
            full = f"ensembles/{first}/{path}"
            del f[full]
            f[full] = value
    return edit


def case_mistyped_stats_and_values_fields(work):
    """A field of stats.h5, checks.h5, checks.json's values and registry, or manifest.toml of
    the wrong type: one line naming the file, the field and the value, exit 2, no report
    (these gave 'cannot draw the report (ValueError: Unknown format code ...)', or were shown)."""
    camp = campaign(work)
    stats, checks_h5 = os.path.join(camp, "stats.h5"), os.path.join(camp, "checks.h5")
    checks_json = os.path.join(camp, "checks.json")
    manifest = os.path.join(camp, "manifest.toml")
    cases = [
        (edit_json("phi_init", "0.4", "values"), [checks_json, "verdict 0",
                                                  "field 'values.phi_init' is '0.4'"]),
        (edit_json("log10_rate", [1], "values"), [checks_json, "'values.log10_rate' is [1]"]),
        (edit_json("margin_unit", "percent", "checks"),
         [checks_json, "checks 0", "field 'margin_unit' is 'percent'"]),
        (edit_json("name", 7, "checks"), [checks_json, "checks 0", "field 'name' is 7"]),
        (edit_json("unit", 5), [checks_json, "verdict 0", "field 'unit' is 5"]),
        (edit_h5("stats.h5", "/", "wall_time", "1 s"),
         [stats, "attribute 'wall_time'", "'1 s'", "not a number"]),
        (edit_h5("stats.h5", "/", "runs", 2.5), [stats, "attribute 'runs'", "2.5"]),
        (edit_h5("stats.h5", "/", "dim", 7), [stats, "attribute 'dim'", "7", "not 2 or 3"]),
        (edit_h5("stats.h5", "/paper", "phi_j", "0.84"),
         [stats, "attribute 'phi_j' of '/paper'", "'0.84'"]),
        (edit_h5("stats.h5", "/fit", "phi_init", "0.4"),
         [stats, "attribute 'phi_init' of '/fit'", "'0.4'"]),
        (edit_h5("stats.h5", "*", "n", "1024"), [stats, "attribute 'n' of '/ensembles/",
                                                 "'1024'", "not a whole number"]),
        (edit_h5("stats.h5", "/fit/representative", "iterations", np.arange(3)),
         [stats, "attribute 'iterations'", "(3,) values, expected one"]),
        (edit_dataset("constant_phi/pressure_mean", np.array([b"a", b"b"])),
         [stats, "pressure_mean", "expected one dimension of numbers"]),
        (edit_h5("checks.h5", "/", "wall_time", "1 s"),
         [checks_h5, "attribute 'wall_time'", "'1 s'"]),
        (lambda c: open(manifest, "w").write('[runs.a]\nstatus = "done"\n'
                                             'wall_seconds = "9 s"\n'),
         [manifest, "field 'runs.a.wall_seconds' is '9 s', not a number"]),
    ]
    for edit, words in cases:
        shutil.rmtree(camp)
        camp = campaign(work)
        edit(camp)
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r")), words, before, work)


def case_fifo_and_device_inputs_refused(work):
    """A FIFO at campaign.toml, manifest.toml, stats.h5, checks.json or checks.h5 (directly or
    through a symbolic link), /dev/zero at manifest.toml: one line naming it, at once (a FIFO
    campaign.toml hung the report). Each report is stopped after 30 s."""
    for name, make in (("campaign.toml", "fifo"), ("manifest.toml", "fifo"),
                       ("stats.h5", "link to fifo"), ("checks.json", "fifo"),
                       ("checks.h5", "fifo"), ("manifest.toml", "/dev/zero"),
                       ("campaign.toml", "/dev/zero")):
        shutil.rmtree(os.path.join(work, "campaign"), ignore_errors=True)
        camp = campaign(work)
        path = os.path.join(camp, name)
        if os.path.lexists(path):
            os.remove(path)
        if make == "fifo":
            os.mkfifo(path)
        elif make == "link to fifo":
            os.mkfifo(os.path.join(work, "elsewhere"))
            os.symlink(os.path.join(work, "elsewhere"), path)
        else:
            os.symlink(make, path)
        kind = "a character device" if make == "/dev/zero" else "a FIFO"
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r"), timeout=30),
                     [path, f"is {kind}"], before, work)
        if os.path.lexists(os.path.join(work, "elsewhere")):
            os.remove(os.path.join(work, "elsewhere"))


def case_error_line_is_visible_and_short(work):
    """An ensemble named with an escape sequence and 5000 characters, lacking what the figures
    draw: the error line shows the escape as text and stays short (the name reached the
    terminal raw)."""
    camp = campaign(work)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        first = sorted(f["ensembles"])[0]
        name = "\x1b[31m\x1b]0;pwned\x07" + "x" * 5000
        f.move(f"ensembles/{first}", f"ensembles/{name}")
        del f[f"ensembles/{name}/constant_phi/pressure_mean"]
    before = tree(work)
    line = expect_error(report(camp, os.path.join(work, "r")),
                        ["stats.h5", "\\x1b[31m", "pressure_mean"], before, work)
    if "\x1b" in line or "\x07" in line:
        raise AssertionError(f"a control character reached the terminal raw: {line!r}")
    if len(line) > 2200:
        raise AssertionError(f"the error line is {len(line)} characters")


def case_verdicts_beyond_what_a_report_shows(work):
    """25,000 verdicts (a campaign's checks give hundreds): refused in one line before anything
    is drawn, so no page or summary of gigabytes; 3,000 give a summary that lists 2,000 and
    says how many more the page has."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        original = json.load(f)
    checks = dict(original, verdicts=(original["verdicts"] * 25_000)[:25_000])
    with open(path, "w") as f:
        json.dump(checks, f)
    os.remove(os.path.join(camp, "checks.h5"))
    before = tree(work)
    expect_error(report(camp, os.path.join(work, "r")),
                 [path, "25000 verdicts", "more than a report shows"], before, work)
    checks = dict(original, verdicts=(original["verdicts"] * 3_000)[:3_000])
    with open(path, "w") as f:
        json.dump(checks, f)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    summary = report_text(out)[1]
    if "... and 1000 more verdicts" not in summary or len(summary.splitlines()) > 2200:
        raise AssertionError(f"the summary of 3000 verdicts has {len(summary.splitlines())} "
                             "lines")


CASES = [case_symbolic_link, case_random_stats, case_missing_dataset, case_truncated_checks, case_read_only,
         case_full_disk, case_fifo, case_regular_file, case_not_a_report,
         case_site_with_thesis_and_data_survives, case_out_dot_is_the_working_directory,
         case_out_is_the_campaign_or_its_parent, case_campaign_named_dot_dot,
         case_own_report_replaced_foreign_file_refused, case_hostile_values_are_escaped,
         case_markup_in_a_number_of_the_fit_is_refused,
         case_a_huge_case_name_gives_a_small_summary, case_mistyped_checks_fields,
         case_site_with_only_index_html_survives, case_marker_cannot_claim_a_users_file,
         case_directory_named_like_a_figure_is_not_owned, case_stored_reports_stay_republishable,
         case_hostile_values_in_every_field, case_dollar_in_a_case_name_is_text,
         case_mistyped_stats_and_values_fields, case_fifo_and_device_inputs_refused,
         case_error_line_is_visible_and_short, case_verdicts_beyond_what_a_report_shows]


def check_fixture():
    """The unmodified campaign copy makes a report, so the failures below are the planted ones;
    None, or why not."""
    work = tempfile.mkdtemp(prefix="jam-report-errors-")
    try:
        r = report(campaign(work), os.path.join(work, "reports", "r"))
        if r.returncode != 0 or not os.path.isfile(os.path.join(work, "reports", "r",
                                                                "index.html")):
            return f"the intact campaign makes no report (exit {r.returncode}):\n{r.stderr}"
        return None
    except AssertionError as e:
        return str(e)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def run_case(case):
    """Runs one case in its own scratch directory: 'passed', 'failed' or 'skipped'."""
    name = case.__name__.removeprefix("case_")
    work = tempfile.mkdtemp(prefix="jam-report-errors-")
    try:
        case(work)
        print(f"passed  {name}")
        return "passed"
    except Skip as e:
        print(f"skipped {name}: {e}")
        return "skipped"
    except AssertionError as e:
        print(f"FAILED  {name}: {e}")
        return "failed"
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main():
    global SOURCE
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", default=SOURCE, help="the source tree (holds reports/)")
    SOURCE = os.path.abspath(parser.parse_args().source)
    broken = check_fixture()
    if broken:
        print(f"FAILED  fixture: {broken}")
        print("0 passed, 1 failed")
        return 1
    results = [run_case(case) for case in CASES]
    passed, failed = results.count("passed"), results.count("failed")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
