#!/usr/bin/python3
"""jam report: a campaign directory (runs, stats.h5, checks) -> an HTML report with figures
and a plain-text summary. Called by `jam report DIR`; usable directly:

    python3 reports/jam_report.py runs/default --out reports/default

The report only draws: every number comes from stats.h5, checks.json and checks.h5. It is
built in a temporary directory next to the output and moved into place when complete, so a
failed or interrupted report never leaves a half-written page behind (an older complete report
stays until the new one replaces it).
"""

import argparse
import datetime
import os
import platform
import shutil
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from report_data import ReportInputError, load_campaign  # noqa: E402

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


def publish(temporary, out):
    """Replaces `out` by the complete directory `temporary`."""
    old = None
    if os.path.exists(out):
        old = tempfile.mkdtemp(prefix=os.path.basename(out) + ".old-", dir=os.path.dirname(out))
        os.rmdir(old)
        os.rename(out, old)
    os.rename(temporary, out)
    if old:
        shutil.rmtree(old, ignore_errors=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", help="campaign directory (after `jam stats` and `jam check`)")
    parser.add_argument("--out", help="report directory (default reports/<campaign name>)")
    parser.add_argument("--quiet", action="store_true", help="no summary on stdout")
    a = parser.parse_args(argv)
    started = time.monotonic()
    try:
        c = load_campaign(a.directory)
    except ReportInputError as e:
        print(f"jam report: error: {e}", file=sys.stderr)
        return 1
    out = os.path.abspath(a.out or os.path.join("reports", c.name))
    os.makedirs(os.path.dirname(out), exist_ok=True)
    temporary = tempfile.mkdtemp(prefix=os.path.basename(out) + ".partial-",
                                 dir=os.path.dirname(out))
    try:
        import report_figures
        import report_html
        figures = [f for f in (draw(c, temporary) for draw in report_figures.ALL) if f]
        page = report_html.page(c, figures, provenance(c, time.monotonic() - started))
        with open(os.path.join(temporary, "index.html"), "w") as f:
            f.write(page)
        summary = report_html.text_summary(c, os.path.join(out, "index.html"))
        with open(os.path.join(temporary, "summary.txt"), "w") as f:
            f.write(summary)
        os.chmod(temporary, 0o755)
        publish(temporary, out)
    except BaseException:
        shutil.rmtree(temporary, ignore_errors=True)
        raise
    if not a.quiet:
        sys.stdout.write(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
