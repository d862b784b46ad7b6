"""What the jamio writer tests share (tests/test_jamio_write.py, tests/test_jamio_gsd.py): a small
valid run, and the refusal and leftover checks."""


import os

import numpy as np

KEY = "log/md/compute/ThermodynamicQuantities/pressure"
N, DIM, RATE, DT, PHI_INIT, RATIO = 64, 2, 1e-2, 0.005, 0.8, 1.4
STEPS = (1000, 1100, 1200, 1400, 1600, 2000)


def jamio():
    import jamio as module  # from --source's python/ (tests/conftest.py)
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
