"""Files written whole: a file is written under a temporary name of its own beside its target
and renamed to the target only when complete, so a failure part-way, an interrupt or a full
disk leaves no half-written file under the target's name, and the temporary file is removed.
jamio's writers, the report (reports/), the scripts (scripts/) and the benchmark figures (bench/)
all write through this module.

    check_target(path, overwrite, kind)   Unwritable unless `path` can take a new file
    claim_temporary(path, directory)      a new empty file (or directory) beside `path`, created
                                          exclusively: `<path>.<pid>.partial`
    publish(partial, path, overwrite)     the finished temporary file renamed to `path`
    remove(partial)                       a temporary file or directory removed, quietly
    staged(path, overwrite)               the three above around a `with` block
    write_text(path, text)                text written whole

Unwritable says why in words without the path (the caller's error names it). An OSError while
a file is written names the target, not the temporary name.
"""

import contextlib
import os
import shutil
import stat

from .errors import cause, shown


class Unwritable(ValueError):
    """Why a path cannot take the file, in words (`exists; not overwritten ...`)."""


def check_target(path, overwrite, kind="file"):
    """Refuses a path that cannot take a new `kind` (a run, a frames file): a directory or a
    special file (by its stat: a FIFO would block), an existing file unless overwrite, a
    directory that does not exist."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        parent = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(parent):
            raise Unwritable(f"directory {shown(parent)} does not exist") from None
        if os.path.lexists(path) and not overwrite:  # a symbolic link to nothing
            raise Unwritable("exists (a symbolic link); not overwritten (overwrite=True "
                             "replaces it)")
        return
    except OSError as e:
        raise Unwritable(f"cannot be written ({cause(e)})") from e
    if stat.S_ISDIR(mode):
        raise Unwritable(f"is a directory; a {kind} is written to a file")
    if not stat.S_ISREG(mode):
        raise Unwritable("is not a regular file (a FIFO, device or socket); not written")
    if not overwrite:
        raise Unwritable("exists; not overwritten (overwrite=True replaces it)")


# The most temporary names tried beside one target (`<path>.<pid>.partial`, then with a
# count): as many taken means something else is wrong.
MOST_TEMPORARY_NAMES = 100


def claim_temporary(path, directory=False):
    """A new empty file (or directory) beside `path`, created here and exclusively (O_EXCL,
    mkdir: a name that exists, a symbolic link included, is never opened or written through):
    `<path>.<pid>.partial`, else with a count k (`<path>.<pid>.<k>.partial`) when that name is
    taken, by a file an earlier process of the same id left or by another thread's write. Its
    mode is a new file's (0666 or 0777 less the umask). Returns its name: only that file is
    written, and removed on an error."""
    base = f"{os.fspath(path)}.{os.getpid()}"
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for k in range(MOST_TEMPORARY_NAMES):
        partial = f"{base}.partial" if k == 0 else f"{base}.{k}.partial"
        try:
            if directory:
                os.mkdir(partial)
            else:
                os.close(os.open(partial, flags, 0o666))
            return partial
        except FileExistsError:
            continue
    raise Unwritable(f"cannot be written: {MOST_TEMPORARY_NAMES} temporary names "
                     f"{shown(base + '.*partial')} are taken")


def publish(partial, path, overwrite):
    """Gives the finished `partial` the name `path`: with overwrite by a rename (atomic: the
    old file or the new, never neither); without, by a hard link, which fails if path appeared
    meanwhile (then, where links are not supported, by a rename after a last look)."""
    if overwrite:
        os.replace(partial, path)
        return
    try:
        os.link(partial, path)
    except FileExistsError:
        raise Unwritable("exists; not overwritten (overwrite=True replaces it)") from None
    except OSError:
        if os.path.lexists(path):
            raise Unwritable("exists; not overwritten (overwrite=True replaces it)") from None
        os.rename(partial, path)
        return
    os.unlink(partial)


def remove(partial):
    """Removes a temporary file or directory of this process; one already gone is no error."""
    with contextlib.suppress(OSError):
        if os.path.isdir(partial) and not os.path.islink(partial):
            shutil.rmtree(partial)
        else:
            os.unlink(partial)


@contextlib.contextmanager
def staged(path, overwrite=True, kind="file"):
    """Yields a temporary name beside `path` (claim_temporary) for the block to write; when the
    block ends, the file is published as `path`, and on any error removed. Unwritable when
    `path` cannot take it (check_target, before the block), OSError naming `path` when the
    write or the rename fails."""
    path = os.fspath(path)
    check_target(path, overwrite, kind)
    partial = None
    try:
        partial = claim_temporary(path)
        yield partial
        publish(partial, path, overwrite)
        partial = None  # renamed: the name is no longer this call's to remove
    except OSError as e:
        if _is_temporary_of(e.filename, path):
            e.filename = path
        raise
    finally:
        if partial is not None:
            remove(partial)


def _is_temporary_of(name, path):
    """Whether `name` is one of claim_temporary's names for `path`."""
    return (isinstance(name, str) and name.startswith(f"{path}.{os.getpid()}.")
            and name.endswith(".partial"))


def write_text(path, text, overwrite=True, kind="text file"):
    """Writes `text` (UTF-8) to `path` whole (staged); an OSError names `path`."""
    try:
        with staged(path, overwrite, kind) as partial, open(partial, "w", encoding="utf-8") as f:
            f.write(text)
    except OSError as e:
        if e.filename is None:  # a full disk on write() or close() names no file
            e.filename = os.fspath(path)
        raise
