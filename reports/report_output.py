"""Where the report is written: the checks on the output path before any work, the temporary
directory next to it, the move into place, and the cleanup when something fails.

The report is built in `<out>.partial-*` next to `<out>` and renamed to `<out>` when complete.
On failure the temporary directory is removed, and so is every parent directory this run
created for it that is still empty; a directory that existed before is never removed.
"""

import contextlib
import os
import shutil
import stat
import tempfile

from report_data import cause

# What a path that is not a directory is, in words, by its stat mode.
KINDS = [(stat.S_ISREG, "a regular file"), (stat.S_ISFIFO, "a FIFO"),
         (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
         (stat.S_ISSOCK, "a socket")]

# What a previous report holds: a directory holding one of these may be replaced.
REPORT_FILES = ("index.html", "summary.txt")


class ReportOutputError(Exception):
    """An output path the report cannot be written to; the message names it."""


def _kind(mode):
    for test, words in KINDS:
        if test(mode):
            return words
    return "not a directory"


def check_target(out):
    """Refuses, before any work, an output path that exists and is not a directory, or is a
    directory that is neither empty nor a report (replacing it would delete its contents).
    Returns the path to write: `out`, or for a symbolic link to a directory the directory it
    points to (links are written through, as everywhere in jam: the link stays)."""
    try:
        mode = os.stat(out).st_mode  # a link to a directory counts as the directory
    except FileNotFoundError:
        if os.path.islink(out):
            raise ReportOutputError(f"{out}: a symbolic link to nothing, not a directory")
        return out
    if not stat.S_ISDIR(mode):
        raise ReportOutputError(f"{out}: exists and is {_kind(mode)}, not a directory")
    entries = os.listdir(out)
    if entries and not any(name in entries for name in REPORT_FILES):
        raise ReportOutputError(
            f"{out}: exists and is not a report (no {REPORT_FILES[0]}); not replaced")
    return os.path.realpath(out) if os.path.islink(out) else out


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
            temporary = tempfile.mkdtemp(prefix=os.path.basename(out) + ".partial-", dir=parent)
        except OSError as e:
            raise ReportOutputError(f"{parent}: {cause(e)}") from e
        yield temporary
    except OSError as e:
        where = _in_place(e.filename, temporary, out) if temporary else e.filename or parent
        raise ReportOutputError(f"{where}: {cause(e)}") from e
    finally:
        failed = temporary is None or os.path.lexists(temporary)
        if temporary and failed:
            shutil.rmtree(temporary, ignore_errors=True)
        if failed:
            _remove_empty(created)


def _discard(path):
    """Removes the replaced report (a link to one: the link only)."""
    if os.path.islink(path):
        os.unlink(path)
    else:
        shutil.rmtree(path, ignore_errors=True)


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
    """Writes `text` to `path`; an error on write or close names the file."""
    try:
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
    except OSError as e:
        if e.filename is None:
            e.filename = path
        raise
