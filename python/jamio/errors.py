"""JamioError, the one error jamio raises for a file it cannot read, and the helpers that turn
low-level failures (h5py, json, the operating system) into it."""

import contextlib
import importlib
import os
import stat

# What a malformed input raises while it is read: h5py's OSError, RuntimeError and KeyError
# (garbled internals, missing objects), ValueError and TypeError from values of the wrong kind,
# MemoryError and OverflowError from sizes a damaged file declares, RecursionError from JSON
# nested deeper than the interpreter's stack.
MALFORMED = (OSError, RuntimeError, KeyError, ValueError, TypeError, IndexError, AttributeError,
             MemoryError, OverflowError, RecursionError)

# The longest message a JamioError carries: names and values come from the file, and a 50 MB
# name must not become a 50 MB error line.
LONGEST_MESSAGE = 1000


def visible(text, longest=LONGEST_MESSAGE):
    """`text` for a terminal: control and other unprintable characters as escapes (\\x1b,
    \\x00, \\u202e), so a name from a file cannot move the cursor or recolour the terminal;
    cut to `longest` characters with the full length said."""
    s = text if isinstance(text, str) else str(text)
    if len(s) > longest:
        s = f"{s[:longest]}... ({len(s)} characters)"
    return "".join(ch if ch.isprintable() else ascii(ch)[1:-1] for ch in s)


def shown(value, longest=60):
    """A value from a file, as an error message shows it: its repr (quotes say it is text),
    shortened, made visible."""
    r = repr(value)
    return visible(r if len(r) <= longest else r[:longest - 3] + "...")


class JamioError(ValueError):
    """A file jamio cannot read. `path` names it; `missing` is True when it does not exist.
    The message is one line: `<path>: <what is wrong>`, control characters shown as escapes
    and at most about LONGEST_MESSAGE characters (`problem` keeps the words as they were)."""

    def __init__(self, path, problem, missing=False):
        super().__init__(visible(" ".join(f"{os.fspath(path)}: {problem}".split())))
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
    elif isinstance(e, RecursionError):
        text = "nested too deeply"
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


def _refuse_special(path, mode):
    for test, kind in _KINDS:
        if test(mode):
            raise JamioError(path, f"is {kind}; only a regular file can be read")
    if not stat.S_ISREG(mode):
        raise JamioError(path, "is not a regular file; only a regular file can be read")


def open_regular(path, what, most_bytes=None):
    """A binary file object reading `path`, which must be a regular file (a symbolic link is
    followed to one): JamioError(missing=True) when it does not exist; a FIFO, device, socket
    or directory refused by its stat before it is opened (opening a FIFO would wait for a
    writer for ever), and again by the open file's own stat, opened without waiting
    (O_NONBLOCK), in case the path was swapped in between; a file larger than `most_bytes`
    refused before anything is read."""
    with reading(path, what):
        try:
            _refuse_special(path, os.stat(path).st_mode)
        except FileNotFoundError:
            raise JamioError(path, "missing", missing=True) from None
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
        try:
            info = os.fstat(fd)
            _refuse_special(path, info.st_mode)
            if most_bytes is not None and info.st_size > most_bytes:
                raise JamioError(path, f"is {info.st_size} bytes, more than a {what} can be "
                                       f"({most_bytes}); not read")
            os.set_blocking(fd, True)
            return os.fdopen(fd, "rb")
        except BaseException:
            os.close(fd)
            raise


def require_file(path, what):
    """Checks `path` before HDF5 is tried on it (open_regular, closed again at once): HDF5 opens
    the path itself."""
    with open_regular(path, what):
        pass


def optional_module(module):
    """The optional `module` (pandas, xarray) imported, or an ImportError of one line naming it
    and its Debian package: jamio's readers need neither, only its tables do."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(f"jamio: this table needs {module}, which cannot be imported; install "
                          f"python3-{module} (Debian) or pip install 'jamio[{module}]'") from None
