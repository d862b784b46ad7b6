"""The cases of tests/test_report_errors.py about where a report is written: file systems
that refuse it, special files and links at the output path, and directories that are not the
report's to replace."""

import os
import shutil
import stat
import sys

import h5py

import report_errors_fixture as fixture
from report_errors_fixture import (campaign, contents, expect_error, expect_untouched, fill,
                                   report, tmpfs, tree, written_report)


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
    out = written_report(os.path.join(work, "r"))
    r = report(camp, out)
    if r.returncode != 0 or not os.path.isfile(os.path.join(out, ".jam-report")):
        raise AssertionError(f"its own report was not replaced: exit {r.returncode}: {r.stderr}")
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
    out = written_report(os.path.join(work, "r"))
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
    sys.path.insert(0, os.path.join(fixture.SOURCE, "reports"))
    import report_output
    camp = campaign(work)
    stored = sorted(d for d in os.listdir(os.path.join(fixture.SOURCE, "reports"))
                    if d.startswith("reduced-"))
    if not stored:
        raise AssertionError("no stored reports in reports/")
    for name in stored:
        out = os.path.join(work, name)
        shutil.copytree(os.path.join(fixture.SOURCE, "reports", name), out)
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
                shutil.copytree(os.path.join(fixture.SOURCE, "reports", name), out)


# Hostile text for every string field: markup for the page, an attribute breaking out of its
# quotes, a NUL and an escape sequence for the terminal, TeX for matplotlib.


OUTPUT_CASES = [case_read_only, case_full_disk, case_fifo, case_regular_file, case_not_a_report, case_symbolic_link, case_site_with_thesis_and_data_survives, case_out_dot_is_the_working_directory, case_out_is_the_campaign_or_its_parent, case_campaign_named_dot_dot, case_own_report_replaced_foreign_file_refused, case_site_with_only_index_html_survives, case_marker_cannot_claim_a_users_file, case_directory_named_like_a_figure_is_not_owned, case_stored_reports_stay_republishable]
