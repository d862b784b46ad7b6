#!/usr/bin/python3
"""The report end to end: the tiny CI campaign -> stats -> checks -> `jam report`, then the page
is checked the way a reader would meet it: every figure it references exists and is a non-empty
PNG with something drawn on it, the verdicts are folded per check with one row per verdict of
checks.json, and the page opens in headless Chromium without console errors, renders non-blank,
and shows a figure, loaded, within the first screen (1280 x 800) with the verdict tables folded.

The detectors this relies on (console errors, a blank screenshot, the layout probe) are
themselves tested on pages with a planted fault, so a detector that can never fire would fail
here.

Usage (ctest runs it): test_report.py --jam build/jam --source .
"""

import argparse
import html.parser
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import h5py
import matplotlib.image
import numpy as np

ARGS = None
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--enable-logging=stderr",
                  "--v=0", "--hide-scrollbars"]


def run(cmd, cwd, expect=(0,)):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=900)
    if r.returncode not in expect:
        raise AssertionError(f"{' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}")
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


class Report(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="jam-report-test-")
        jam, src = ARGS.jam, ARGS.source
        run([jam, "campaign", "run", os.path.join(src, "reference/campaigns/ci.toml"),
             "--quiet"], cls.work)
        run([jam, "stats", "runs/ci"], cls.work)
        # Status 1 (a failed verdict) and 3 (an inconclusive one) still leave a complete set of
        # checks to report on. --with-lammps: the stored LAMMPS self-checks, which `all` judges
        # only when asked, so that the lammps figure is drawn too.
        cls.checked = run([jam, "check", "all", "runs/ci", "--no-lmp", "--with-lammps",
                           "--reference-dir", os.path.join(src, "reference")], cls.work,
                          expect=(0, 1, 3))
        cls.result = run([jam, "report", "runs/ci"], cls.work)
        cls.out = os.path.join(cls.work, "reports", "ci")
        with open(os.path.join(cls.out, "index.html")) as f:
            cls.page = f.read()
        cls.parser = PageParser()
        cls.parser.feed(cls.page)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_every_figure_exists_and_shows_something(self):
        # The CI campaign has 2 samples per ensemble: sample_pairs needs 3 and is inconclusive, so its
        # figure is absent; its 2 rates give no scaling fit, so neither the scan nor the
        # collapse is drawn (each only when a row of the scan has a result, and a
        # representative); every other section of the report must be there.
        expected = {"pressure.png", "finite_size.png", "finite_size_z.png", "pressure_rate.png",
                    "relative_errors.png", "jamming_points.png", "jamming_width.png",
                    "lammps.png"}
        with h5py.File(os.path.join(self.work, "runs", "ci", "stats.h5"), "r") as f:
            if "fit/scan/phi_j" in f and np.isfinite(f["fit/scan/phi_j"][:]).any():
                expected.add("fit_scan.png")
            if "fit/representative" in f:
                expected.add("collapse.png")
        self.assertEqual(set(self.parser.images), expected)
        for src in self.parser.images:
            path = os.path.join(self.out, src)
            self.assertTrue(os.path.isfile(path), src)
            with open(path, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", src)
            # An empty matplotlib canvas is all background; axes, labels and data cover well
            # over 2% of any of these figures (measured 5-20%).
            self.assertGreater(drawn_fraction(path), 0.02, src)

    def test_jamming_width_is_stated_against_the_rate(self):
        # The width of phi_Ji per size at the slowest rate, in numbers, and whether the slowest
        # rate feels the finite size (when the campaign's fit gives 1/(z nu)).
        self.assertIn("width Delta phi_J(N) (standard deviation of phi_Ji):", self.page)
        with h5py.File(os.path.join(self.work, "runs", "ci", "stats.h5"), "r") as f:
            fitted = "fit/representative" in f
        self.assertIn("feel the finite size" if fitted else "the rate&#x27;s scale is not drawn",
                      self.page)

    def test_captions_are_whole(self):
        # Captions run to several hundred characters (the fit's reason, the paper's values
        # cited): none may be cut as an over-long value would be ("... (N characters)").
        captions = re.findall(r"<figcaption>(.*?)</figcaption>", self.page, re.S)
        self.assertGreater(len(captions), 5)
        self.assertGreater(max(map(len, captions)), 300, "no long caption to test with")
        for caption in captions:
            self.assertNotRegex(caption, r"\.\.\. \(\d+ characters\)$")

    def test_verdicts_folded_per_check_after_the_figures(self):
        with open(os.path.join(self.work, "runs", "ci", "checks.json")) as f:
            verdicts = json.load(f)["verdicts"]
        self.assertGreater(len(verdicts), 10)
        self.assertEqual(self.parser.verdict_rows, len(verdicts))
        checks = list(dict.fromkeys(v["check"] for v in verdicts))
        self.assertEqual(self.parser.folds, [(f"verdicts-{c}", False) for c in checks])
        # Figures first: the first image before the verdicts, the headline before both.
        self.assertLess(self.page.index("<img"), self.page.index("class='verdicts'"))
        self.assertLess(self.page.index("class=\"headlines\""), self.page.index("<img"))

    def test_a_figure_is_in_the_first_screen_and_the_verdicts_folded(self):
        seen = layout(os.path.join(self.out, "index.html"), self.work)
        self.assertEqual(seen["figure-loaded"], 1, seen)
        # The image starts within the first screen and at least 200 px of it show there.
        self.assertLess(seen["figure-top"] + 200, seen["screen"], seen)
        self.assertGreater(seen["figure-height"], 200, seen)
        self.assertEqual(seen["verdict-rows-height"], 0, seen)

    def test_layout_probe_fires_on_planted_faults(self):
        # The old layout's fault: a long table before the first figure; and an image that
        # does not load; and verdict tables left open.
        with open(os.path.join(self.out, "index.html")) as f:
            page = f.read()
        planted = os.path.join(self.out, "planted.html")
        rows = "".join(f"<tr><td>row {k}</td></tr>" for k in range(200))
        with open(planted, "w") as f:
            f.write(page.replace("<h2>", f"<table>{rows}</table><h2>", 1)
                    .replace("<details ", "<details open ")
                    .replace("src='pressure.png'", "src='missing.png'"))
        try:
            seen = layout(planted, self.work)
        finally:
            os.remove(planted)
        self.assertGreater(seen["figure-top"], seen["screen"], seen)
        self.assertEqual(seen["figure-loaded"], 0, seen)
        self.assertGreater(seen["verdict-rows-height"], 0, seen)

    def test_text_summary_and_provenance(self):
        self.assertIn("passed", self.result.stdout)
        self.assertIn(os.path.join("reports", "ci", "index.html"), self.result.stdout)
        with open(os.path.join(self.out, "summary.txt")) as f:
            self.assertEqual(f.read(), self.result.stdout)
        for field in ("code version", "wall time: runs", "wall time: stats", "wall time: checks",
                      "dependencies", "machine", "Campaign file"):
            self.assertIn(field, self.page)
        self.assertIn("paper", self.page)  # the fit table compares with the paper

    def test_summary_tables_are_those_jam_check_prints(self):
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
        printed = tables(self.checked.stdout)
        self.assertGreater(len(printed), 10)
        self.assertEqual(tables(self.result.stdout), printed)
        with open(os.path.join(self.work, "runs", "ci", "checks.json")) as f:
            verdicts = json.load(f)["verdicts"]
        for v in verdicts:  # whole case names, never cut
            self.assertTrue(any(v["case"] in line for line in printed), v["case"])

    def test_verdict_rows_show_the_cells_jam_wrote(self):
        # Every verdict's row on the page shows its estimate, the effects allowed and the
        # range judged (with margin, region, samples and rule) as checks.json's `table` has
        # them: the cells jam check printed.
        with open(os.path.join(self.work, "runs", "ci", "checks.json")) as f:
            verdicts = json.load(f)["verdicts"]
        rows = re.findall(r"<tr class='(?:pass|fail|inconclusive|expected)'>(.*?)</tr>",
                          self.page, re.S)
        shown = [[html.unescape(c) for c in re.findall(r"<td[^>]*>([^<]*)</td>", row)]
                 for row in rows]
        for v in verdicts:
            t = v["table"]
            wanted = [t[k] for k in ("estimate", "allowed", "margin", "unit", "range", "region",
                                     "samples", "rule")]
            self.assertTrue(any(r[1:1 + len(wanted)] == wanted for r in shown),
                            (v["case"], wanted))
        self.assertTrue(any(v["table"]["range"] != "-" and v["table"]["estimate"] != "-"
                            for v in verdicts))

    def test_no_partial_directories_left(self):
        left = [d for d in os.listdir(os.path.join(self.work, "reports")) if d != "ci"]
        self.assertEqual(left, [])

    def test_page_opens_in_chromium_without_console_errors(self):
        shot = os.path.join(self.work, "screenshot.png")
        console = render("file://" + os.path.join(self.out, "index.html"), shot, self.work)
        self.assertEqual(console, [])
        # The top of the page: title, verdict table (coloured status cells) and text.
        self.assertGreater(drawn_fraction(shot), 0.03)

    def test_detectors_fire_on_planted_faults(self):
        bad = os.path.join(self.work, "bad.html")
        with open(bad, "w") as f:
            f.write("<!DOCTYPE html><html><body><script>console.error('planted')</script>"
                    "</body></html>")
        console = render("file://" + bad, os.path.join(self.work, "bad.png"), self.work)
        self.assertTrue(any("planted" in line for line in console), console)
        self.assertLess(drawn_fraction(os.path.join(self.work, "bad.png")), 0.001)

    def test_missing_statistics_is_a_one_line_error_and_no_report(self):
        empty = os.path.join(self.work, "runs", "empty")
        os.makedirs(empty)
        r = run([ARGS.jam, "report", empty, "--out", os.path.join(self.work, "reports", "x")],
                self.work, expect=(2,))
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("stats.h5", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.work, "reports", "x")))


class QuestionAndWholeCompression(unittest.TestCase):
    """The question a campaign asked (checks.json "question") and a pooled verdict over the
    whole compression, as the report's headline and summary say them (reports/report_html.py),
    the same words as `jam check`'s table (checks/verdict_table.cpp)."""

    @staticmethod
    def modules():
        sys.path.insert(0, os.path.join(os.path.abspath(ARGS.source), "reports"))
        import report_data
        import report_html
        return report_data, report_html

    def verdict(self, region, status, values=None):
        data, _ = self.modules()
        return data.Verdict("finite_size", f"n64 vs n128, {region}", status, "r", "s", 1.0, 2.0,
                            0.05, 0.08, values or {}, margin=0.1, region=region)

    def test_the_question_is_one_line(self):
        _, h = self.modules()
        q = {"range": {"phi_min": 0.83, "phi_max": 0.85, "from": "[question] phi_min, phi_max"},
             "pooled": "the scaling fit's window, else the whole compression",
             "checks": ["finite_size"], "margins": {"finite_size": 0.1}, "alpha": 0.05}
        self.assertEqual(h.question_text(q),
                         "question: the range asked, phi in [0.83, 0.85] ([question] phi_min, "
                         "phi_max); checks finite_size; alpha 0.05")
        q["range"] = None
        self.assertIn("no range asked", h.question_text(q))
        self.assertIsNone(h.question_text(None))

    def test_a_whole_compression_pool_says_so_and_the_range_asked_is_counted(self):
        _, h = self.modules()
        whole = [self.verdict("pooled", "pass", {"whole_compression": 1.0})]
        self.assertIn("pooled over the whole compression", h.headline("finite_size", whole))
        self.assertIn(h.POOLED_WHOLE, h.check_table("finite_size", whole))
        asked = [self.verdict("pooled", "pass"), self.verdict("asked", "fail")]
        line = h.headline("finite_size", asked)
        self.assertIn("in the range asked 0 passed, 1 failed, 0 inconclusive", line)
        self.assertNotIn("pooled only", line)
        self.assertNotIn(h.POOLED_ONLY, h.check_table("finite_size", asked))


class NoFitWithoutAResult(unittest.TestCase):
    """A scan none of whose fits could be made draws no scan and no collapse figure; the fit's
    section says in one sentence why (fewer than 3 rates, else the scan's distinct reasons),
    and so does the summary (reports/report_figures_fit.py, report_html.py)."""

    @staticmethod
    def modules():
        sys.path.insert(0, os.path.join(os.path.abspath(ARGS.source), "reports"))
        import report_data
        import report_figures_fit
        import report_html
        return report_data, report_figures_fit, report_html

    def campaign(self, log10_rates, failures):
        data, _, _ = self.modules()
        rows = len(failures)
        nan = np.full(rows, np.nan)
        scan = {name: nan.copy() for name in data.SCAN}
        scan["rate_max"] = np.full(rows, 10.0 ** log10_rates[0])
        scan["half_window"] = np.array([0.01, 0.02, 0.03] * rows)[:rows]
        fit = {"attrs": {"phi_init": 0.7, "n": 0, "rates_note": "-", "failure": failures[-1]},
               "scan": scan,
               "scan_failures": "".join(f"rate_max 0.001 window +-0.01: {f}\n"
                                        for f in failures)}
        ensembles = [data.Ensemble(f"n64_r{r}", 64, 0.7, r, 10.0 ** r, 3, {}, {}, None)
                     for r in log10_rates]
        return data.Campaign("d", "small", 2, {"paper": {}}, ensembles, fit, [], {}, {}, "",
                             [])

    def test_two_rates_and_no_fit_in_stats_h5_say_why(self):
        # `jam stats` attempts no fit with fewer than 3 rates and writes none: the sentence is
        # the design's, not "--no-fit".
        _, figures, h = self.modules()
        c = self.campaign([-2.5, -3.0], ["-"])
        c.fit = None
        with tempfile.TemporaryDirectory() as out:
            self.assertIsNone(figures.scan_figure(c, out))
            self.assertIsNone(figures.collapse_figure(c, out))
        self.assertTrue(h.no_fit_sentence(c).startswith(
            "No scaling fit: fewer than 3 rates (the fitted ensembles have 2: 1e-2.5, 1e-3)"),
            h.no_fit_sentence(c))

    def test_no_figure_and_one_sentence_with_two_rates(self):
        _, figures, h = self.modules()
        c = self.campaign([-2.5, -3.0], ["fit: 2 rate(s) at or below rate_max 0.00316; a "
                                         "scaling fit needs at least 3"] * 3)
        with tempfile.TemporaryDirectory() as out:
            self.assertIsNone(figures.scan_figure(c, out))
            self.assertIsNone(figures.collapse_figure(c, out))
            self.assertEqual(os.listdir(out), [])
        section = h.fit_table_html(c)
        self.assertEqual(section.count("<p>"), 1, section)
        self.assertIn("No scaling fit: fewer than 3 rates (the fitted ensembles have 2: "
                      "1e-2.5, 1e-3)", section)
        summary = h.text_summary(c, "index.html")
        self.assertEqual(summary.count("No scaling fit"), 1, summary)

    def test_the_scans_distinct_reasons_when_it_has_rates_enough(self):
        _, figures, h = self.modules()
        c = self.campaign([-4.0, -4.5, -5.0, -5.5],
                          ["fit: phi_J = 0.9 lies outside the packings",
                           "fit ends on a bound: q = 1.2 (0 < q < 1)",
                           "fit: phi_J = 0.91 lies outside the packings"])
        with tempfile.TemporaryDirectory() as out:
            self.assertIsNone(figures.scan_figure(c, out))
        self.assertEqual(
            h.no_fit_sentence(c),
            "No scaling fit: none of the 3 fits of the scan could be made (2 rows, e.g.: "
            "phi_J = 0.9 lies outside the packings | 1 row: fit ends on a bound: q = 1.2 "
            "(0 < q < 1)).")
        # A row with a result: the scan is drawn (its failures said in the caption).
        c.fit["scan"]["phi_j"][1] = 0.84
        for name in ("phi_j_error", "beta", "beta_error", "y", "y_error"):
            c.fit["scan"][name][1] = 0.1
        with tempfile.TemporaryDirectory() as out:
            self.assertIsNotNone(figures.scan_figure(c, out))


class CompareWithHeadline(unittest.TestCase):
    """The verdicts of compare_with's campaigns (another code against this one) never turn the
    campaign's own headline: they get a line of their own, on the page and in the summary."""

    def test_a_wrong_code_fails_its_own_line_not_the_campaigns(self):
        sys.path.insert(0, os.path.join(os.path.abspath(ARGS.source), "reports"))
        import report_data
        import report_html as h

        def verdict(check, case, status):
            return report_data.Verdict(check, case, status, "r", "s", 1.0, 2.0, 0.05, 0.08, {},
                                       margin=0.05)
        verdicts = [verdict("finite_size", "n64 vs n128, pooled", "pass"),
                    verdict("compare", "n64 phi_init 0.7 rate 1e-3: other vs ref, constant phi",
                            "pass"),
                    verdict("compare", "n64 phi_init 0.7 rate 1e-3: planted vs ref, constant phi",
                            "fail"),
                    verdict("compare_fit", "planted vs ref: all", "inconclusive")]
        c = report_data.Campaign("d", "ref", 2, {"paper": {}}, [], None, verdicts, {}, {},
                                 'name = "ref"\ncompare_with = ["runs/other", "runs/planted"]\n',
                                 [])
        page = h.page(c, [], {})
        self.assertIn('<p class="summary"><b>PASS</b>: 1 passed, 0 failed, 0 inconclusive.',
                      page)
        self.assertIn("<b>compare with runs/planted: FAIL: 0 passed, 1 failed, 1 inconclusive"
                      "</b>", page)
        self.assertIn("<b>compare with runs/other: PASS: 1 passed", page)
        summary = h.text_summary(c, "index.html")
        self.assertIn("this campaign's own checks: PASS: 1 passed, 0 failed, 0 inconclusive\n",
                      summary)
        self.assertIn("compare with runs/planted: FAIL: 0 passed, 1 failed, 1 inconclusive\n",
                      summary)
        # The per-check headlines are the campaign's own.
        self.assertNotIn("\ncompare: no effect", summary)
        self.assertIn("\nfinite size: no effect above 5% in 1 of 1\n", summary)


class WidthPowerLaw(unittest.TestCase):
    """The fit of Delta phi_J(N) = a N^-w in the jamming-width figure, on planted widths: each
    the standard deviation of 10 normal values, so each log width scatters by about 0.25."""

    @staticmethod
    def module():
        sys.path.insert(0, os.path.join(os.path.abspath(ARGS.source), "reports"))
        import report_figures_jamming
        return report_figures_jamming

    def law(self):
        return self.module().width_power_law

    def planted(self, w, seed):
        rng = np.random.default_rng(seed)
        sizes = [256, 1024, 4096, 16384, 32768]
        widths = [float(np.std(rng.normal(0.84, 0.03 * n ** -w, 10), ddof=1)) for n in sizes]
        return self.law()(sizes, widths, [10] * len(sizes))

    def test_recovers_the_planted_exponent_within_its_error(self):
        # Over 400 planted sets the error covers the planted w about as a standard error should:
        # within 2 errors in about 95% (a wrong error, x2 or /2, gives ~100% or ~68%).
        for w in (0.5, 0.25):
            fits = [self.planted(w, seed) for seed in range(400)]
            inside = sum(abs(fit_w - w) < 2 * fit_error for fit_w, fit_error, _, _ in fits)
            self.assertGreater(inside, 0.90 * 400, w)
            self.assertLess(inside, 0.99 * 400, w)

    def test_log_width_variance_is_the_scatter_of_log_s(self):
        log_width_variance = self.module().log_width_variance
        rng = np.random.default_rng(3)
        for n in (2, 3, 10, 11):
            logs = np.log(np.std(rng.normal(size=(200000, n)), axis=1, ddof=1))
            # 200000 draws: the sample variance is good to about 0.3% (kurtosis near 3)
            self.assertAlmostEqual(float(np.var(logs)) / log_width_variance(n), 1.0, delta=0.015)

    def test_tells_one_half_from_one_quarter(self):
        # Five sizes over a factor 128 in N, 10 samples each: w's error is about 0.063, so 0.25
        # and 0.5 lie four errors apart, and a fit of planted 0.25 puts 0.5 beyond two of its
        # errors in about 97% of the sets (measured 0.978 over 400).
        fits = [self.planted(0.25, seed) for seed in range(400)]
        told = sum(abs(w - 0.5) > 2 * e for w, e, _, _ in fits)
        self.assertGreater(told, 0.93 * 400)
        self.assertIsNone(self.law()([256, 1024], [0.002, 0.001], [10, 10]))


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--jam", required=True)
    parser.add_argument("--source", required=True)
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
