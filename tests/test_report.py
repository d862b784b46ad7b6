#!/usr/bin/python3
"""The report end to end: the tiny CI campaign -> stats -> checks -> `jam report`, then the page
is checked the way a reader would meet it: every figure it references exists and is a non-empty
PNG with something drawn on it, the verdicts are folded per check with one row per verdict of
checks.json, and the page opens in headless Chromium without console errors, renders non-blank,
and shows a figure, loaded, within the first screen (1280 x 800) with the verdict tables folded.

The detectors this relies on (console errors, a blank screenshot, the layout probe) are
themselves tested on pages with a planted fault, so a detector that can never fire would fail
here.

The report's sections on made-up campaigns: tests/test_report_sections.py.

Usage (ctest runs it): python3 -m pytest tests/test_report.py --jam build/jam --source .
"""

import html.parser
import json
import os
import re
import shutil
import subprocess
import tempfile

import h5py
import matplotlib.image
import numpy as np
import pytest

CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--enable-logging=stderr",
                  "--v=0", "--hide-scrollbars"]


def run(cmd, cwd, expect=(0,)):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=900)
    assert r.returncode in expect, \
        f"{' '.join(map(str, cmd))} exited {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    raise AssertionError("headless Chromium not found (scripts/setup.sh installs Debian's "
                         "chromium package)")


def render(url, screenshot, workdir):
    """Opens url in headless Chromium; returns the console messages it logged."""
    profile = tempfile.mkdtemp(dir=workdir, prefix="chromium-profile-")
    r = subprocess.run([chromium(), *CHROMIUM_FLAGS, f"--user-data-dir={profile}",
                        "--window-size=1280,2400", f"--screenshot={screenshot}", url],
                       capture_output=True, text=True, timeout=120)
    if not os.path.exists(screenshot):
        raise AssertionError(f"Chromium wrote no screenshot (exit {r.returncode}):\n{r.stderr}")
    return [line for line in r.stderr.splitlines() if ":CONSOLE" in line]


# The layout probe: a copy of the page with this script added reports, once everything has
# loaded, where the first figure's image lies, whether it loaded, and how tall the visible rows
# of the verdict tables are, into the body's attributes, which --dump-dom prints. The report
# itself has no script; only the probe's copy does.
PROBE = """<script>
window.addEventListener('load', () => {
  const img = document.querySelector('figure img');
  const r = img ? img.getBoundingClientRect() : null;
  let rows = 0;
  for (const tr of document.querySelectorAll('table.verdicts tr'))
    if (tr.checkVisibility()) rows += tr.getBoundingClientRect().height;
  document.body.setAttribute('data-figure-top', r ? r.top : -1);
  document.body.setAttribute('data-figure-height', r ? r.height : -1);
  document.body.setAttribute('data-figure-loaded', img && img.complete && img.naturalWidth > 0 ? 1 : 0);
  document.body.setAttribute('data-verdict-rows-height', rows);
  document.body.setAttribute('data-screen', window.innerHeight);
});
</script>"""


def layout(page_path, workdir):
    """The probe's numbers for the page at page_path, rendered 1280 x 800 by Chromium."""
    with open(page_path) as f:
        page = f.read()
    probe = os.path.join(os.path.dirname(page_path), "probe-copy.html")
    with open(probe, "w") as f:
        f.write(page.replace("</body>", PROBE + "</body>"))
    profile = tempfile.mkdtemp(dir=workdir, prefix="chromium-profile-")
    try:
        r = subprocess.run([chromium(), *CHROMIUM_FLAGS, f"--user-data-dir={profile}",
                            "--window-size=1280,800", "--virtual-time-budget=10000",
                            "--dump-dom", "file://" + probe],
                           capture_output=True, text=True, timeout=120)
    finally:
        os.remove(probe)
    found = dict(re.findall(r'data-([a-z-]+)="([-0-9.e]+)"', r.stdout))
    if "figure-top" not in found:
        raise AssertionError(f"the layout probe reported nothing (exit {r.returncode}):\n"
                             f"{r.stderr[-2000:]}")
    return {k: float(v) for k, v in found.items()}


def drawn_fraction(png):
    """Fraction of pixels that are not (nearly) the background colour of the image."""
    image = matplotlib.image.imread(png)[..., :3]
    background = np.median(image.reshape(-1, 3), axis=0)
    return float(np.mean(np.abs(image - background).sum(axis=2) > 0.1))


class PageParser(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.verdict_rows, self._in_verdicts = [], 0, False
        self.folds = []  # (id, open) of each <details> of the verdicts

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        if tag == "details":
            self.folds.append((a.get("id", ""), "open" in a))
        if tag == "table" and a.get("class") == "verdicts":
            self._in_verdicts = True
        if tag == "tr" and self._in_verdicts and a.get("class") in ("pass", "fail", "inconclusive",
                                                                        "expected"):
            self.verdict_rows += 1

    def handle_endtag(self, tag):
        if tag == "table":
            self._in_verdicts = False


class CiReport:
    """The CI campaign run, averaged, checked and reported in `work`; the page parsed."""

    def __init__(self, jam, src, work):
        self.work = work
        run([jam, "campaign", "run", os.path.join(src, "reference/campaigns/ci.toml"),
             "--quiet"], self.work)
        run([jam, "stats", "runs/ci"], self.work)
        # Status 1 (a failed verdict) and 3 (an inconclusive one) still leave a complete set of
        # checks to report on. --with-lammps: the stored LAMMPS self-checks, which `all` judges
        # only when asked, so that the lammps figure is drawn too.
        self.checked = run([jam, "check", "all", "runs/ci", "--no-lmp", "--with-lammps",
                            "--reference-dir", os.path.join(src, "reference")], self.work,
                           expect=(0, 1, 3))
        self.result = run([jam, "report", "runs/ci"], self.work)
        self.out = os.path.join(self.work, "reports", "ci")
        with open(os.path.join(self.out, "index.html")) as f:
            self.page = f.read()
        self.parser = PageParser()
        self.parser.feed(self.page)


@pytest.fixture(scope="module")
def ci(jam, source, tmp_path_factory):
    return CiReport(jam, source, str(tmp_path_factory.mktemp("report")))


def test_every_figure_exists_and_shows_something(ci):
    # The CI campaign has 2 samples per ensemble: sample_pairs needs 3 and is inconclusive, so its
    # figure is absent; its 2 rates give no scaling fit, so neither the scan nor the
    # collapse is drawn (each only when a row of the scan has a result, and a
    # representative); every other section of the report must be there.
    expected = {"pressure.png", "finite_size.png", "finite_size_z.png", "pressure_rate.png",
                "relative_errors.png", "jamming_points.png", "jamming_width.png",
                "lammps.png"}
    with h5py.File(os.path.join(ci.work, "runs", "ci", "stats.h5"), "r") as f:
        if "fit/scan/phi_j" in f and np.isfinite(f["fit/scan/phi_j"][:]).any():
            expected.add("fit_scan.png")
        if "fit/representative" in f:
            expected.add("collapse.png")
    assert set(ci.parser.images) == expected
    for src in ci.parser.images:
        path = os.path.join(ci.out, src)
        assert os.path.isfile(path), src
        with open(path, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n", src
        # An empty matplotlib canvas is all background; axes, labels and data cover well
        # over 2% of any of these figures (measured 5-20%).
        assert drawn_fraction(path) > 0.02, src


def test_jamming_width_is_stated_against_the_rate(ci):
    # The width of phi_Ji per size at the slowest rate, in numbers, and whether the slowest
    # rate feels the finite size (when the campaign's fit gives 1/(z nu)).
    assert "width Delta phi_J(N) (standard deviation of phi_Ji):" in ci.page
    with h5py.File(os.path.join(ci.work, "runs", "ci", "stats.h5"), "r") as f:
        fitted = "fit/representative" in f
    assert ("feel the finite size" if fitted else "the rate&#x27;s scale is not drawn") in ci.page


def test_captions_are_whole(ci):
    # Captions run to several hundred characters (the fit's reason, the paper's values
    # cited): none may be cut as an over-long value would be ("... (N characters)").
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", ci.page, re.S)
    assert len(captions) > 5
    assert max(map(len, captions)) > 300, "no long caption to test with"
    for caption in captions:
        assert not re.search(r"\.\.\. \(\d+ characters\)$", caption)


def test_verdicts_folded_per_check_after_the_figures(ci):
    with open(os.path.join(ci.work, "runs", "ci", "checks.json")) as f:
        verdicts = json.load(f)["verdicts"]
    assert len(verdicts) > 10
    assert ci.parser.verdict_rows == len(verdicts)
    checks = list(dict.fromkeys(v["check"] for v in verdicts))
    assert ci.parser.folds == [(f"verdicts-{c}", False) for c in checks]
    # Figures first: the first image before the verdicts, the headline before both.
    assert ci.page.index("<img") < ci.page.index("class='verdicts'")
    assert ci.page.index("class=\"headlines\"") < ci.page.index("<img")


def test_a_figure_is_in_the_first_screen_and_the_verdicts_folded(ci):
    seen = layout(os.path.join(ci.out, "index.html"), ci.work)
    assert seen["figure-loaded"] == 1, seen
    # The image starts within the first screen and at least 200 px of it show there.
    assert seen["figure-top"] + 200 < seen["screen"], seen
    assert seen["figure-height"] > 200, seen
    assert seen["verdict-rows-height"] == 0, seen


def test_layout_probe_fires_on_planted_faults(ci):
    # The old layout's fault: a long table before the first figure; and an image that
    # does not load; and verdict tables left open.
    with open(os.path.join(ci.out, "index.html")) as f:
        page = f.read()
    planted = os.path.join(ci.out, "planted.html")
    rows = "".join(f"<tr><td>row {k}</td></tr>" for k in range(200))
    with open(planted, "w") as f:
        f.write(page.replace("<h2>", f"<table>{rows}</table><h2>", 1)
                .replace("<details ", "<details open ")
                .replace("src='pressure.png'", "src='missing.png'"))
    try:
        seen = layout(planted, ci.work)
    finally:
        os.remove(planted)
    assert seen["figure-top"] > seen["screen"], seen
    assert seen["figure-loaded"] == 0, seen
    assert seen["verdict-rows-height"] > 0, seen


def test_text_summary_and_provenance(ci):
    assert "passed" in ci.result.stdout
    assert os.path.join("reports", "ci", "index.html") in ci.result.stdout
    with open(os.path.join(ci.out, "summary.txt")) as f:
        assert f.read() == ci.result.stdout
    for field in ("code version", "wall time: runs", "wall time: stats", "wall time: checks",
                  "dependencies", "machine", "Campaign file"):
        assert field in ci.page
    assert "paper" in ci.page  # the fit table compares with the paper


def test_summary_tables_are_those_jam_check_prints(ci):
    # One table per check with whole case names and one unit, the same text in the
    # report's summary (what `jam pipeline` prints) as in `jam check`'s output: from the
    # first check's heading to the line counting every verdict.
    def tables(text):
        lines = text.splitlines()
        start = next(k for k, line in enumerate(lines) if line.endswith(" verdicts")
                     or " verdicts, " in line or " verdict, " in line)
        end = next(k for k, line in enumerate(lines) if k > start
                   and line.split(" ")[0].isdigit() and " verdicts, " in line)
        return lines[start:end + 1]
    printed = tables(ci.checked.stdout)
    assert len(printed) > 10
    assert tables(ci.result.stdout) == printed
    with open(os.path.join(ci.work, "runs", "ci", "checks.json")) as f:
        verdicts = json.load(f)["verdicts"]
    for v in verdicts:  # whole case names, never cut
        assert any(v["case"] in line for line in printed), v["case"]


def test_verdict_rows_show_the_cells_jam_wrote(ci):
    # Every verdict's row on the page shows its estimate, the effects allowed and the
    # range judged (with margin, region, samples and rule) as checks.json's `table` has
    # them: the cells jam check printed.
    with open(os.path.join(ci.work, "runs", "ci", "checks.json")) as f:
        verdicts = json.load(f)["verdicts"]
    rows = re.findall(r"<tr class='(?:pass|fail|inconclusive|expected)'>(.*?)</tr>",
                      ci.page, re.S)
    shown = [[html.unescape(c) for c in re.findall(r"<td[^>]*>([^<]*)</td>", row)]
             for row in rows]
    for v in verdicts:
        t = v["table"]
        wanted = [t[k] for k in ("estimate", "allowed", "margin", "unit", "range", "region",
                                 "samples", "rule")]
        assert any(r[1:1 + len(wanted)] == wanted for r in shown), (v["case"], wanted)
    assert (any(v["table"]["range"] != "-" and v["table"]["estimate"] != "-"
                        for v in verdicts))


def test_no_partial_directories_left(ci):
    left = [d for d in os.listdir(os.path.join(ci.work, "reports")) if d != "ci"]
    assert left == []


def test_page_opens_in_chromium_without_console_errors(ci):
    shot = os.path.join(ci.work, "screenshot.png")
    console = render("file://" + os.path.join(ci.out, "index.html"), shot, ci.work)
    assert console == []
    # The top of the page: title, verdict table (coloured status cells) and text.
    assert drawn_fraction(shot) > 0.03


def test_detectors_fire_on_planted_faults(ci):
    bad = os.path.join(ci.work, "bad.html")
    with open(bad, "w") as f:
        f.write("<!DOCTYPE html><html><body><script>console.error('planted')</script>"
                "</body></html>")
    console = render("file://" + bad, os.path.join(ci.work, "bad.png"), ci.work)
    assert any("planted" in line for line in console), console
    assert drawn_fraction(os.path.join(ci.work, "bad.png")) < 0.001


def test_missing_statistics_is_a_one_line_error_and_no_report(ci, jam):
    empty = os.path.join(ci.work, "runs", "empty")
    os.makedirs(empty)
    r = run([jam, "report", empty, "--out", os.path.join(ci.work, "reports", "x")],
            ci.work, expect=(2,))
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "stats.h5" in r.stderr
    assert not os.path.exists(os.path.join(ci.work, "reports", "x"))
