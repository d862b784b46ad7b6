#!/usr/bin/python3
"""jam report: a campaign directory (runs, stats.h5, checks) -> an HTML report with figures
and a plain-text summary. Called by `jam report DIR`; usable directly:

    python3 reports/jam_report.py runs/default --out reports/default

The report only draws: every number comes from stats.h5, checks.json and checks.h5, read
through jamio (python/jamio). Each figure is written as PNG and SVG with the CSV of the numbers
it plots beside it (one stem). It is built in a temporary directory next to the output and
moved into place when complete, so a failed or interrupted report never leaves a half-written
page behind (an older complete report stays until the new one replaces it), nor any directory
it created on the way.

A failure is one line on stderr, `jam report: error: <file>: <cause>`, with exit status 2 (a
tool error, as in every jam subcommand): a campaign that is not ready for a report (stats.h5 or
checks.json missing: a step has not been run), an input that cannot be read (unreadable,
truncated, corrupt, malformed) or an output that cannot be written (no space left on device,
read-only file system, permission denied, an output path that is not a directory).
"""

import argparse
import datetime
import os
import platform
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from report_data import UNREADABLE, ReportInputError, cause, load_campaign, visible  # noqa: E402
from report_output import (ReportOutputError, check_target, mark, publish,  # noqa: E402
                           staging, write_text)

# Debian packages whose versions the provenance lists (the project's dependencies).
PACKAGES = ["lammps", "libhdf5-dev", "libgsl-dev", "libeigen3-dev", "libboost-test-dev",
            "libfmt-dev", "libcli11-dev", "libtomlplusplus-dev", "nlohmann-json3-dev",
            "libopenmpi-dev", "python3-matplotlib", "python3-h5py", "python3-numpy"]


def package_versions():
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f", "${Package} ${Version}\\n", *PACKAGES],
                             capture_output=True, text=True, timeout=20).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "dpkg-query not available"
    return ", ".join(line.strip() for line in out.splitlines() if line.strip())


def machine():
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    memory = ""
    try:
        with open("/proc/meminfo") as f:
            kib = int(f.readline().split()[1])
            memory = f", {kib / 2**20:.0f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    return (f"{socket.gethostname()}: {cpu}, {os.cpu_count()} cores{memory}; "
            f"{platform.system()} {platform.release()}")


def provenance(c, report_seconds):
    runs = c.run_wall_seconds
    stats_wall = c.stats_attrs.get("wall_time")
    checks_wall = c.checks_attrs.get("wall_time")
    import h5py
    import matplotlib
    import numpy
    return {
        "campaign": f"{c.name} ({c.directory})",
        "campaign file": c.manifest.get("campaign_file", "-"),
        "code version (runs)": c.manifest.get("code_version", "-"),
        "code version (stats, checks)":
            f"{c.stats_attrs.get('version', '-')}, {c.checks_attrs.get('version', '-')}",
        "runs": f"{c.stats_attrs.get('runs', 0)} averaged, "
                f"{c.stats_attrs.get('runs_skipped', 0)} not finished",
        "wall time: runs": (f"{sum(runs):.0f} core-seconds over {len(runs)} runs "
                            f"(longest {max(runs):.1f} s)") if runs else "-",
        "wall time: stats": f"{stats_wall:.1f} s" if stats_wall is not None else "-",
        "wall time: checks": f"{checks_wall:.1f} s" if checks_wall is not None else "-",
        "wall time: report": f"{report_seconds:.1f} s",
        "dependencies": package_versions(),
        "python": f"{platform.python_version()}, matplotlib {matplotlib.__version__}, "
                  f"h5py {h5py.__version__}, numpy {numpy.__version__}",
        "machine": machine(),
        "generated": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
    }


def report_name(name):
    """The campaign's name as the default report directory's name: a plain word, never '.',
    '..' or a path (the name comes from a file, and a report replaces its directory)."""
    if (not isinstance(name, str) or name in ("", ".", "..") or "/" in name
            or any(ord(ch) < 0x20 or ord(ch) == 0x7f for ch in name)):
        raise ReportOutputError(
            f"campaign name {name!r} cannot name a report directory; give --out DIR")
    return name


def write_report(c, out, started):
    """Draws the report into a temporary directory and moves it to `out`; returns the summary."""
    with staging(out) as temporary:
        import report_figures
        import report_html
        figures = [f for f in (draw(c, temporary) for draw in report_figures.page_order(c)) if f]
        page = report_html.page(c, figures, provenance(c, time.monotonic() - started))
        write_text(os.path.join(temporary, "index.html"), page)
        summary = report_html.text_summary(c, os.path.join(out, "index.html"))
        write_text(os.path.join(temporary, "summary.txt"), summary)
        mark(temporary)
        os.chmod(temporary, 0o755)
        publish(temporary, out)
    return summary


def print_summary(summary):
    try:
        sys.stdout.write(summary)
        sys.stdout.flush()
    except OSError as e:
        # Nothing more reaches stdout: without this, the flush at exit fails a second time.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        raise ReportOutputError(f"standard output: {cause(e)}") from e


def run(a):
    """The report of a.directory; the output path is checked before anything is drawn."""
    started = time.monotonic()
    out = os.path.abspath(a.out) if a.out else None
    if out:
        out = check_target(out, a.directory)
    c = load_campaign(a.directory)
    if not out:
        out = check_target(os.path.abspath(os.path.join("reports", report_name(c.name))),
                           a.directory)
    summary = write_report(c, out, started)
    if not a.quiet:
        print_summary(summary)
    return 0


def fail(message, status=UNREADABLE):
    """The one line on stderr: names and values in it come from files, so its control
    characters are made visible and its length bounded."""
    print("jam report: error: " + visible(" ".join(message.split()), 2000), file=sys.stderr)
    return status


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", help="campaign directory (after `jam stats` and `jam check`)")
    parser.add_argument("--out", help="report directory (default reports/<campaign name>)")
    parser.add_argument("--quiet", action="store_true", help="no summary on stdout")
    a = parser.parse_args(argv)
    try:
        return run(a)
    except ReportInputError as e:
        return fail(str(e), e.status)
    except ReportOutputError as e:
        return fail(str(e))
    except OSError as e:
        return fail(f"{e.filename}: {cause(e)}" if e.filename else cause(e))
    except KeyboardInterrupt:
        # SIGINT (a terminal's Ctrl-C, or `jam pipeline` passing a stop on): the temporary
        # directory is already removed (staging), the old report untouched.
        return fail(f"{a.directory}: interrupted; no report written", 130)
    except Exception as e:  # noqa: BLE001 - one line, not a traceback, whatever the input held
        if os.environ.get("JAM_REPORT_TRACEBACK"):
            raise
        what = f"{type(e).__name__}: {str(e)[:300]}"
        return fail(f"{a.directory}: cannot draw the report ({what}); "
                    "JAM_REPORT_TRACEBACK=1 shows where")


if __name__ == "__main__":
    sys.exit(main())
