"""What every Python test of tests/ shares: the command line and its two fixtures.

    /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/test_x.py --jam build/jam --source .

`jam` is the binary under test (a test that needs it is skipped, saying so, when --jam is not
given); `source` is the repository root (by default the one holding this file). jamio is
imported from the source tree's python/, never from an installed copy, so that a test checks
the code beside it. Scratch files go to pytest's `tmp_path`.
"""

import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent


def pytest_addoption(parser):
    parser.addoption("--jam", help="the jam binary under test (build/jam)")
    parser.addoption("--source", default=str(ROOT),
                     help="the repository root (holds python/, scripts/, reports/)")


def pytest_configure(config):
    # Before the test modules are imported: several import jamio at their top.
    python = str(pathlib.Path(config.getoption("--source")).resolve() / "python")
    if python not in sys.path:
        sys.path.insert(0, python)


@pytest.fixture(scope="session")
def source(request):
    """The repository root, a pathlib.Path."""
    return pathlib.Path(request.config.getoption("--source")).resolve()


@pytest.fixture(scope="session")
def jam(request):
    """The jam binary, a pathlib.Path (absolute when given as a path, else a name on PATH)."""
    given = request.config.getoption("--jam")
    if not given:
        pytest.skip("needs the jam binary: pass --jam build/jam")
    path = pathlib.Path(given)
    return path.resolve() if len(path.parts) > 1 else path
