"""Where the report is written: the checks on the output path before any work, the temporary
directory next to it, the move into place, and the cleanup when something fails.

The report is built in `<out>.<pid>.partial` next to `<out>` and renamed to `<out>` when
complete. On failure the temporary directory is removed, and so is every parent directory this
run created for it that is still empty; a directory that existed before is never removed. The
temporary names, the cleanup and the writing of each text file whole are jamio's
(python/jamio/output.py), as for jamio's writers and the scripts.

A report directory is jam's own: it holds `.jam-report`, the list of the files the report
wrote. A report replaces only such a directory, or an empty one, and when it does it deletes
only the files listed. The marker names only files a report writes (`index.html`,
`summary.txt`, figures as .png, .svg, .csv), so a hand-made marker cannot claim anything else.
A report written before the marker existed is replaced when it is recognisably jam's: its
`index.html` is jam's page, its `summary.txt` jam's summary, every other entry a figure file;
any other directory without the marker (a site with an `index.html`, say) is refused. A
directory holding anything else, entries that are not regular files, the working directory,
the campaign and their parents are refused before any work: publishing a report never deletes
a user's file.
"""

import contextlib
import os
import stat
import sys
import tempfile

from report_data import cause, shown as _shown  # report_data puts jamio on the path
from jamio import output

# What a path that is not a directory is, in words, by its stat mode.
KINDS = [(stat.S_ISREG, "a regular file"), (stat.S_ISFIFO, "a FIFO"),
         (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
         (stat.S_ISSOCK, "a socket")]

# The files a report writes, by name: the page and the summary; each figure as PNG and SVG
# with the CSV of its numbers. MARKER lists the files of one report, one name a line.
REPORT_FILES = ("index.html", "summary.txt")
FIGURE_SUFFIXES = (".png", ".svg", ".csv")
MARKER = ".jam-report"


class ReportOutputError(Exception):
    """An output path the report cannot be written to; the message names it."""


def _kind(mode):
    for test, words in KINDS:
        if test(mode):
            return words
    return "not a directory"


def _is_report_file(name):
    return name in REPORT_FILES or (name.endswith(FIGURE_SUFFIXES) and "/" not in name
                                    and not name.startswith("."))


# How the page and the summary of every jam report begin (report_html.page, text_summary): what
# identifies a report written before the marker existed.
PAGE_START = b'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
PAGE_TITLE = b"<title>jam report: "
SUMMARY_START = b"jam report: campaign "
# The longest marker read: one name a line, a few dozen files.
MOST_MARKER_BYTES = 1 << 16


def _regular(path):
    """Whether `path` is a regular file itself (a symbolic link is not)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _starts(path, *prefixes):
    """Whether the regular file `path` begins with prefixes[0] and holds the others in its
    first kilobyte (opened without waiting: it was checked to be a regular file)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOFOLLOW)
    except OSError:
        return False
    with os.fdopen(fd, "rb") as f:
        head = f.read(1024)
    return head.startswith(prefixes[0]) and all(p in head for p in prefixes[1:])


def _jam_wrote_before_the_marker(directory, entries):
    """A report of a jam before the marker: its page and summary jam's, the rest figures."""
    if not all(_is_report_file(n) and _regular(os.path.join(directory, n)) for n in entries):
        return False
    return (_starts(os.path.join(directory, "index.html"), PAGE_START, PAGE_TITLE)
            and _starts(os.path.join(directory, "summary.txt"), SUMMARY_START))


def owned_files(directory):
    """The names of the files jam wrote in a report directory: those its MARKER lists that a
    report writes, or all the files of a report written before the marker existed. None when
    the directory is not a report jam wrote."""
    entries = set(os.listdir(directory))
    marker = os.path.join(directory, MARKER)
    if MARKER in entries:
        if not _regular(marker):
            return None
        with open(marker, "rb") as f:
            text = f.read(MOST_MARKER_BYTES).decode("utf-8", errors="replace")
        listed = {line for line in text.splitlines() if line}
        return {n for n in listed if _is_report_file(n)} | {MARKER}
    if _jam_wrote_before_the_marker(directory, entries):
        return entries
    return None


def _contains(outer, inner):
    """Whether `inner` is `outer` or lies below it (both real paths)."""
    return os.path.commonpath([outer, inner]) == outer


def check_target(out, campaign=None):
    """Refuses, before any work, an output path that exists and is not a directory, a directory
    that is not a report jam wrote (it would be replaced: MARKER), or one holding files the
    report did not write; and the working directory, the campaign directory and any of their
    parents, whatever they hold. Returns the path to write: `out`, or for a symbolic link to a
    directory the directory it points to (links are written through: the link stays)."""
    real = os.path.realpath(out)
    for what, path in (("the working directory", os.getcwd()), ("the campaign", campaign)):
        if path is not None and _contains(real, os.path.realpath(path)):
            raise ReportOutputError(
                f"{out}: is {what} or a parent of it; a report needs a directory of its own")
    try:
        mode = os.stat(out).st_mode  # a link to a directory counts as the directory
    except FileNotFoundError:
        if os.path.islink(out):
            raise ReportOutputError(f"{out}: a symbolic link to nothing, not a directory")
        return out
    if not stat.S_ISDIR(mode):
        raise ReportOutputError(f"{out}: exists and is {_kind(mode)}, not a directory")
    entries = os.listdir(out)
    if entries:
        owned = owned_files(out)
        if owned is None:
            raise ReportOutputError(
                f"{out}: exists and is not a report jam wrote (no {MARKER}); not replaced")
        # A listed name that is not a regular file here (a directory called x.png) is not jam's.
        foreign = sorted(n for n in entries
                         if n not in owned or not _regular(os.path.join(out, n)))
        if foreign:
            shown = ", ".join(_shown(n) for n in foreign[:5]) + (", ..." if len(foreign) > 5 else "")
            raise ReportOutputError(
                f"{out}: holds files the report did not write ({shown}); not replaced")
    return real if os.path.islink(out) else out


def _make_parents(directory, created):
    """os.makedirs(directory), appending each directory it creates to `created`, outermost
    first."""
    missing = []
    while not os.path.lexists(directory):
        missing.append(directory)
        parent = os.path.dirname(directory)
        if parent == directory:
            break
        directory = parent
    for d in reversed(missing):
        try:
            os.mkdir(d)
        except FileExistsError:
            continue
        created.append(d)


def _remove_empty(created):
    """Removes the directories this run created, innermost first, while they are empty."""
    for d in reversed(created):
        try:
            os.rmdir(d)
        except OSError:
            return


def _in_place(path, temporary, out):
    """The name a file of the temporary directory will have in the finished report."""
    if not isinstance(path, str) or not path:
        return out
    path = os.path.abspath(path)
    if os.path.commonpath([path, temporary]) != temporary:
        return path
    relative = os.path.relpath(path, temporary)
    return out if relative == "." else os.path.join(out, relative)


@contextlib.contextmanager
def staging(out):
    """A temporary directory next to `out` for the body to fill and publish. On failure: the
    temporary directory and the empty parents this created are removed, and an OSError becomes
    a ReportOutputError naming the file (as it would be named in `out`) and the cause."""
    created, temporary = [], None
    parent = os.path.dirname(out)
    try:
        _make_parents(parent, created)
        try:
            temporary = output.claim_temporary(out, directory=True)
        except (OSError, output.Unwritable) as e:
            raise ReportOutputError(f"{parent}: {cause(e)}") from e
        yield temporary
    except OSError as e:
        where = _in_place(e.filename, temporary, out) if temporary else e.filename or parent
        raise ReportOutputError(f"{where}: {cause(e)}") from e
    finally:
        failed = temporary is None or os.path.lexists(temporary)
        if temporary and failed:
            output.remove(temporary)
        if failed:
            _remove_empty(created)


def mark(temporary):
    """Writes MARKER into a finished report directory: the names of every file in it."""
    names = sorted(n for n in os.listdir(temporary) if n != MARKER)
    write_text(os.path.join(temporary, MARKER), "".join(n + "\n" for n in names))


def _discard(path):
    """Removes the replaced report: only the files it lists as its own, then the directory if
    that leaves it empty. Anything else (put there after the check) stays, and is said."""
    owned = owned_files(path) or set()
    for name in owned:
        target = os.path.join(path, name)
        if os.path.isfile(target) or os.path.islink(target):
            os.unlink(target)
    try:
        os.rmdir(path)
    except OSError:
        print(f"jam report: warning: kept {path}: it holds files the report did not write",
              file=sys.stderr)


def publish(temporary, out):
    """Replaces `out` by the complete directory `temporary`; `out` is back as it was if the
    rename fails."""
    old = None
    if os.path.lexists(out):
        old = tempfile.mkdtemp(prefix=os.path.basename(out) + ".old-", dir=os.path.dirname(out))
        os.rmdir(old)
        os.rename(out, old)
    try:
        os.rename(temporary, out)
    except BaseException:
        if old:
            os.rename(old, out)
        raise
    if old:
        _discard(old)


def write_text(path, text):
    """Writes `text` to `path` (whole: jamio's output.write_text); an error on write or close
    names the file."""
    output.write_text(path, text)
