"""What the jamio writer tests share (tests/test_jamio_write.py, tests/test_jamio_gsd.py): the
command line (--jam, --source), a small valid run, the refusal and leftover checks, and the
runner that prints one line per case and `N passed, M failed`."""


import argparse
import contextlib
import os
import shutil
import sys
import tempfile

import numpy as np

ARGS = None  # the parsed command line, set by run()
KEY = "log/md/compute/ThermodynamicQuantities/pressure"
N, DIM, RATE, DT, PHI_INIT, RATIO = 64, 2, 1e-2, 0.005, 0.8, 1.4
STEPS = (1000, 1100, 1200, 1400, 1600, 2000)


def jamio():
    import jamio as module
    return module


def refused(call, *words):
    """call() must raise JamioError, one line containing every word; its message."""
    try:
        call()
    except jamio().JamioError as e:
        message = str(e)
        if "\n" in message:
            raise AssertionError(f"message of more than one line: {message!r}")
        missing = [w for w in words if w not in message]
        if missing:
            raise AssertionError(f"message lacks {missing}: {message}")
        return message
    raise AssertionError(f"not refused (expected a message with {words})")


def only(directory, names=()):
    """The directory holds exactly `names` (nothing left behind)."""
    found = sorted(os.listdir(directory))
    if found != sorted(names):
        raise AssertionError(f"{directory} holds {found}, expected {sorted(names)}")


def check(condition, what):
    if not condition:
        raise AssertionError(what)


def series(m=6, phi_init=PHI_INIT, rate=RATE, dim=DIM):
    t = np.linspace(0.0, 3.0, m)
    phi = phi_init * np.exp(dim * rate * t)
    return t, phi


def good_run(**change):
    """The arguments of a valid write_run call (with every optional series), changed."""
    t, phi = series()
    kw = dict(packing_fraction=phi, pressure=np.linspace(0.0, 2e-3, len(t)), dim=DIM, n=N,
              rate=RATE, phi_init=PHI_INIT, simulator="my-gpu-code", simulator_version="1.2",
              sample=3, contacts_per_particle=np.linspace(0.0, 4.1, len(t)),
              energy_per_particle=np.linspace(0.0, 1e-4, len(t)), time=t)
    kw.update(change)
    return kw


def write(path, **change):
    kw = good_run(**change)
    return jamio().write_run(path, kw.pop("packing_fraction"), kw.pop("pressure"), **kw)


# ---- write_run and validate_run ------------------------------------------------------------------


def run(cases, description, prefix):
    """Runs each case in a scratch directory of its own; the exit status (1 if any failed)."""
    global ARGS
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--jam", required=True, help="the jam binary (build/jam)")
    parser.add_argument("--source", required=True, help="the source tree (holds python/)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary directory")
    ARGS = parser.parse_args()
    ARGS.source = os.path.abspath(ARGS.source)
    if os.sep in ARGS.jam:
        ARGS.jam = os.path.abspath(ARGS.jam)
    sys.path.insert(0, os.path.join(ARGS.source, "python"))
    top = tempfile.mkdtemp(prefix=prefix)
    passed = failed = skipped = 0
    try:
        for case in cases:
            name = case.__name__.removeprefix("case_")
            work = os.path.join(top, name)
            os.mkdir(work)
            try:
                if case(work) == "skipped":
                    print(f"skipped {name}")
                    skipped += 1
                    continue
                print(f"passed  {name}")
                passed += 1
            except Exception as e:  # a case that crashes fails, the others still run
                print(f"FAILED  {name}: {type(e).__name__}: {e}")
                failed += 1
    finally:
        if ARGS.keep:
            print(f"kept {top}")
        else:
            with contextlib.suppress(OSError):
                shutil.rmtree(top)
    print(f"{passed} passed, {failed} failed" + (f", {skipped} skipped" if skipped else ""))
    return 1 if failed else 0
