"""JamioError, the one error jamio raises for a file it cannot read, and the helpers that turn
low-level failures (h5py, json, the operating system) into it."""

import contextlib
import os
import stat

# What a malformed input raises while it is read: h5py's OSError, RuntimeError and KeyError
# (garbled internals, missing objects), ValueError and TypeError from values of the wrong kind,
# MemoryError and OverflowError from sizes a damaged file declares.
MALFORMED = (OSError, RuntimeError, KeyError, ValueError, TypeError, IndexError, AttributeError,
             MemoryError, OverflowError)


class JamioError(ValueError):
    """A file jamio cannot read. `path` names it; `missing` is True when it does not exist.
    The message is one line: `<path>: <what is wrong>`."""

    def __init__(self, path, problem, missing=False):
        super().__init__(f"{path}: {problem}")
        self.path = os.fspath(path)
        self.problem = problem
        self.missing = missing


def cause(e):
    """One line saying why, from a low-level exception: errno's words, else its message."""
    if isinstance(e, OSError) and e.errno is not None:
        words = os.strerror(e.errno)
        text = words[:1].lower() + words[1:]
    elif isinstance(e, KeyError) and e.args and isinstance(e.args[0], str):
        text = e.args[0] if " " in e.args[0] else f"'{e.args[0]}' missing"
    else:
        text = str(e) or type(e).__name__
    return " ".join(text.split())


@contextlib.contextmanager
def reading(path, what):
    """Turns a low-level failure while `path` is read into a JamioError naming it:
    `<path>: not a readable <what> (<cause>)`."""
    try:
        yield
    except JamioError:
        raise
    except MALFORMED as e:
        raise JamioError(path, f"not a readable {what} ({cause(e)})") from e


# What a path that is not a regular file is, in words, by its stat mode.
_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))


def require_file(path, what):
    """Checks `path` before HDF5 or JSON is tried: JamioError(missing=True) when it does not
    exist; a FIFO, device, socket or directory refused by its stat (opening a FIFO would wait
    for a writer for ever); permission denied said in plain words."""
    with reading(path, what):
        try:
            mode = os.stat(path).st_mode
        except FileNotFoundError:
            raise JamioError(path, "missing", missing=True) from None
        for test, kind in _KINDS:
            if test(mode):
                raise JamioError(path, f"is {kind}; only a regular file can be read")
        with open(path, "rb"):
            pass
