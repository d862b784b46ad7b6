"""What every reader of a campaign directory's files for the report shares: jamio (the
project's reader of its files: python/jamio), the one error a report input raises with its
exit status, and the checks every input gets before a figure draws from it (a field of its type,
datasets that are one-dimensional arrays of numbers, equally long).

Nothing here computes physics: it only reads numbers that `jam stats` and `jam check` wrote.
"""

import contextlib
import os
import sys

import numpy as np


def _import_jamio():
    """jamio from python/ beside reports/ (the reader of the same source tree), else an
    installed one (reports/ copied elsewhere, JAM_REPORTS_DIR)."""
    beside = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python")
    if os.path.isfile(os.path.join(beside, "jamio", "__init__.py")) and beside not in sys.path:
        sys.path.insert(0, beside)
    try:
        import jamio
    except ImportError as e:
        raise ImportError(f"jamio not found in {beside} nor installed (docs/python.md): "
                          f"{e}") from e
    return jamio


jamio = _import_jamio()
cause = jamio.errors.cause
require = jamio.hdf5.require
shown = jamio.errors.shown
visible = jamio.errors.visible


# Exit status of a campaign that is not ready for a report (a step has not been run yet) and
# of an input that exists but cannot be read (unreadable, corrupt, malformed): both are tool
# errors, exit status 2 as in every jam subcommand.
NOT_READY = 2
UNREADABLE = 2


class ReportInputError(Exception):
    """A campaign directory that cannot be reported on; the message names the file."""

    def __init__(self, message, status=UNREADABLE):
        super().__init__(message)
        self.status = status


MALFORMED = jamio.errors.MALFORMED


@contextlib.contextmanager
def reading(path, what):
    """Turns a failure while `path` is read or checked into a ReportInputError naming it."""
    try:
        yield
    except ReportInputError:
        raise
    except jamio.JamioError as e:
        raise ReportInputError(str(e)) from e
    except MALFORMED as e:
        raise ReportInputError(f"{path}: not a readable {what} ({cause(e)})") from e


def _loaded(load, path, step):
    """load(path); a missing file says which step to run, any other failure names the file."""
    try:
        return load(path)
    except jamio.JamioError as e:
        if e.missing and e.path == path:
            raise ReportInputError(f"{path}: missing; run `{step}` on the campaign first",
                                   NOT_READY) from e
        raise ReportInputError(str(e)) from e


def _require(names, present, where, kind):
    for name in names:
        if name not in present:
            raise ValueError(f"{kind} '{name}' of {shown(where)} missing")


def _numbers(out, names, where):
    """Each of `names` present in `out` a one-dimensional array of numbers: what a figure draws
    must be one (a string dataset would be drawn as categories, its text in the SVG)."""
    for name in names:
        data = out.get(name)
        if data is not None and (np.ndim(data) != 1 or np.asarray(data).dtype.kind not in "biuf"):
            raise ValueError(f"dataset '{name}' of {shown(where)} is "
                             f"{np.ndim(data)}-dimensional of {np.asarray(data).dtype}, "
                             "expected one dimension of numbers")


def _datasets(group, required, where, optional=()):
    """The arrays of a jamio Group (None: {}); when it has any, `required` must be among them,
    one-dimensional arrays of numbers, equally long (and `optional`, where present, too)."""
    out = dict(group or {})
    if out and required:
        _require(required, out, where, "dataset")
        _numbers(out, tuple(required) + tuple(optional), where)
        lengths = {name: len(out[name]) for name in tuple(required) + tuple(optional)
                   if name in out}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"{where}: datasets of different lengths {lengths}")
    return out


def _shown(value):
    """A value in an error message: its repr, shortened, control characters made visible."""
    return shown(value)


class FieldError(ValueError):
    """A checks.json field of the wrong type; the message names the field and the value."""


def _number(x, key, field=None):
    """The number at x[key] (None when absent or null); a string, list or bool is refused."""
    v = x.get(key)
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise FieldError(f"field '{field or key}' is {_shown(v)}, not a number")
    return float(v)


def _string(x, key, default=None):
    """The string at x[key] (`default` when absent and one is given)."""
    v = x[key] if default is None else x.get(key, default)
    if not isinstance(v, str):
        raise FieldError(f"field '{key}' is {_shown(v)}, not a string")
    return v
