"""What the tests of a shared schema (test_checks_schema.py, test_stats_schema.py) ask of both
readers of one file: jam's `validate` and jamio's loader each say (ok, message), the message
without the file's path, which both must put first."""

import subprocess


def jam_says(jam, kind, path):
    """(ok, message) of `jam validate --<kind> path` (kind: "checks" or "stats")."""
    r = subprocess.run([str(jam), "validate", f"--{kind}", str(path)], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode in (0, 1), r.stderr
    line = r.stdout.strip()
    assert line.startswith(str(path) + ": "), line
    return r.returncode == 0, line[len(str(path)) + 2:]


def jamio_says(load, error, path):
    """(ok, message) of jamio's `load(path)`, `error` its exception type."""
    try:
        load(str(path))
        return True, "ok"
    except error as e:
        assert str(e).startswith(str(path) + ": "), str(e)
        return False, str(e)[len(str(path)) + 2:]
