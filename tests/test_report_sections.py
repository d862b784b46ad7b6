#!/usr/bin/python3
"""Sections of the report on made-up campaigns, without jam (reports/report_words.py,
report_html.py, report_figures_fit.py, report_figures_jamming.py): the question a campaign asked and a pool over
the whole compression as the headline says them; no scan or collapse figure without a fit, and
one sentence why; compare_with's verdicts on lines of their own; the jamming width's power law
on planted widths. The report of a real campaign, end to end: tests/test_report.py.

Usage (ctest runs it): python3 -m pytest tests/test_report_sections.py --source .
"""

import os
import sys

import numpy as np
import pytest


@pytest.fixture(scope="module", autouse=True)
def reports_on_the_path(source):
    sys.path.insert(0, str(source / "reports"))


def report_module(name):
    return __import__(name)


# ---- the question a campaign asked and a pool over the whole compression ------------------------
# (checks.json "question"), as the report's headline and summary say them (reports/report_words.py),
# the same words as `jam check`'s table (checks/verdict_table.cpp).


def verdict(region, status, values=None):
    return report_module("report_data").Verdict(
        "finite_size", f"n64 vs n128, {region}", status, "r", "s", 1.0, 2.0, 0.05, 0.08,
        values or {}, margin=0.1, region=region)


def test_the_question_is_one_line():
    h = report_module("report_words")
    q = {"range": {"phi_min": 0.83, "phi_max": 0.85, "from": "[question] phi_min, phi_max"},
         "pooled": "the scaling fit's window, else the whole compression",
         "checks": ["finite_size"], "margins": {"finite_size": 0.1}, "alpha": 0.05}
    assert h.question_text(q) == ("question: the range asked, phi in [0.83, 0.85] ([question] "
                                  "phi_min, phi_max); checks finite_size; alpha 0.05")
    q["range"] = None
    assert "no range asked" in h.question_text(q)
    assert h.question_text(None) is None


def test_a_whole_compression_pool_says_so_and_the_range_asked_is_counted():
    words, h = report_module("report_words"), report_module("report_html")
    whole = [verdict("pooled", "pass", {"whole_compression": 1.0})]
    assert "pooled over the whole compression" in words.headline("finite_size", whole)
    assert words.POOLED_WHOLE in h.check_table("finite_size", whole)
    asked = [verdict("pooled", "pass"), verdict("asked", "fail")]
    line = words.headline("finite_size", asked)
    assert "in the range asked 0 passed, 1 failed, 0 inconclusive" in line
    assert "pooled only" not in line
    assert words.POOLED_ONLY not in h.check_table("finite_size", asked)


# ---- no fit without a result --------------------------------------------------------------------
# A scan none of whose fits could be made draws no scan and no collapse figure; the fit's section
# says in one sentence why (fewer than 3 rates, else the scan's distinct reasons), and so does
# the summary (reports/report_figures_fit.py, report_html.py).


def campaign(log10_rates, failures):
    data = report_module("report_data")
    rows = len(failures)
    nan = np.full(rows, np.nan)
    scan = {name: nan.copy() for name in data.SCAN}
    scan["rate_max"] = np.full(rows, 10.0 ** log10_rates[0])
    scan["half_window"] = np.array([0.01, 0.02, 0.03] * rows)[:rows]
    fit = {"attrs": {"phi_init": 0.7, "n": 0, "rates_note": "-", "failure": failures[-1]},
           "scan": scan,
           "scan_failures": "".join(f"rate_max 0.001 window +-0.01: {f}\n" for f in failures)}
    ensembles = [data.Ensemble(f"n64_r{r}", 64, 0.7, r, 10.0 ** r, 3, {}, {}, None)
                 for r in log10_rates]
    return data.Campaign("d", "small", 2, {"paper": {}}, ensembles, fit, [], {}, {}, "", [])


def test_no_fit_no_figure_and_one_sentence_with_two_rates(tmp_path):
    figures, h = report_module("report_figures_fit"), report_module("report_html")
    c = campaign([-2.5, -3.0], ["fit: 2 rate(s) at or below rate_max 0.00316; a scaling fit "
                                "needs at least 3"] * 3)
    assert figures.scan_figure(c, str(tmp_path)) is None
    assert figures.collapse_figure(c, str(tmp_path)) is None
    assert os.listdir(tmp_path) == []
    section = h.fit_table_html(c)
    assert section.count("<p>") == 1, section
    assert ("No scaling fit: fewer than 3 rates (the fitted ensembles have 2: 1e-2.5, 1e-3)"
            in section)
    summary = h.text_summary(c, "index.html")
    assert summary.count("No scaling fit") == 1, summary


def test_two_rates_and_no_fit_in_stats_h5_say_why(tmp_path):
    # `jam stats` attempts no fit with fewer than 3 rates and writes none: the sentence is the
    # design's, not "--no-fit".
    figures, words = report_module("report_figures_fit"), report_module("report_words")
    c = campaign([-2.5, -3.0], ["-"])
    c.fit = None
    assert figures.scan_figure(c, str(tmp_path)) is None
    assert figures.collapse_figure(c, str(tmp_path)) is None
    assert words.no_fit_sentence(c).startswith(
        "No scaling fit: fewer than 3 rates (the fitted ensembles have 2: 1e-2.5, 1e-3)"), \
        words.no_fit_sentence(c)


def test_no_fit_the_scans_distinct_reasons_when_it_has_rates_enough(tmp_path):
    figures, words = report_module("report_figures_fit"), report_module("report_words")
    c = campaign([-4.0, -4.5, -5.0, -5.5],
                 ["fit: phi_J = 0.9 lies outside the packings",
                  "fit ends on a bound: q = 1.2 (0 < q < 1)",
                  "fit: phi_J = 0.91 lies outside the packings"])
    assert figures.scan_figure(c, str(tmp_path)) is None
    assert words.no_fit_sentence(c) == (
        "No scaling fit: none of the 3 fits of the scan could be made (2 rows, e.g.: "
        "phi_J = 0.9 lies outside the packings | 1 row: fit ends on a bound: q = 1.2 "
        "(0 < q < 1)).")
    # A row with a result: the scan is drawn (its failures said in the caption).
    c.fit["scan"]["phi_j"][1] = 0.84
    for name in ("phi_j_error", "beta", "beta_error", "y", "y_error"):
        c.fit["scan"][name][1] = 0.1
    assert figures.scan_figure(c, str(tmp_path)) is not None


# ---- compare_with's headline --------------------------------------------------------------------


def test_compare_with_a_wrong_code_fails_its_own_line_not_the_campaigns():
    """The verdicts of compare_with's campaigns (another code against this one) never turn the
    campaign's own headline: they get a line of their own, on the page and in the summary."""
    data, h = report_module("report_data"), report_module("report_html")

    def made(check, case, status):
        return data.Verdict(check, case, status, "r", "s", 1.0, 2.0, 0.05, 0.08, {}, margin=0.05)
    verdicts = [made("finite_size", "n64 vs n128, pooled", "pass"),
                made("compare", "n64 phi_init 0.7 rate 1e-3: other vs ref, constant phi", "pass"),
                made("compare", "n64 phi_init 0.7 rate 1e-3: planted vs ref, constant phi",
                     "fail"),
                made("compare_fit", "planted vs ref: all", "inconclusive")]
    c = data.Campaign("d", "ref", 2, {"paper": {}}, [], None, verdicts, {}, {},
                      'name = "ref"\ncompare_with = ["runs/other", "runs/planted"]\n', [])
    page = h.page(c, [], {})
    assert '<p class="summary"><b>PASS</b>: 1 passed, 0 failed, 0 inconclusive.' in page
    assert ("<b>compare with runs/planted: FAIL: 0 passed, 1 failed, 1 inconclusive</b>"
            in page)
    assert "<b>compare with runs/other: PASS: 1 passed" in page
    summary = h.text_summary(c, "index.html")
    assert "this campaign's own checks: PASS: 1 passed, 0 failed, 0 inconclusive\n" in summary
    assert "compare with runs/planted: FAIL: 0 passed, 1 failed, 1 inconclusive\n" in summary
    # The per-check headlines are the campaign's own.
    assert "\ncompare: no effect" not in summary
    assert "\nfinite size: no effect above 5% in 1 of 1\n" in summary


# ---- the jamming width's power law --------------------------------------------------------------
# The fit of Delta phi_J(N) = a N^-w in the jamming-width figure, on planted widths: each the
# standard deviation of 10 normal values, so each log width scatters by about 0.25.


def planted(w, seed):
    rng = np.random.default_rng(seed)
    sizes = [256, 1024, 4096, 16384, 32768]
    widths = [float(np.std(rng.normal(0.84, 0.03 * n ** -w, 10), ddof=1)) for n in sizes]
    return report_module("report_figures_jamming").width_power_law(sizes, widths,
                                                                   [10] * len(sizes))


@pytest.mark.parametrize("w", [0.5, 0.25])
def test_width_law_recovers_the_planted_exponent_within_its_error(w):
    # Over 400 planted sets the error covers the planted w about as a standard error should:
    # within 2 errors in about 95% (a wrong error, x2 or /2, gives ~100% or ~68%).
    fits = [planted(w, seed) for seed in range(400)]
    inside = sum(abs(fit_w - w) < 2 * fit_error for fit_w, fit_error, _, _ in fits)
    assert inside > 0.90 * 400, w
    assert inside < 0.99 * 400, w


@pytest.mark.parametrize("n", [2, 3, 10, 11])
def test_log_width_variance_is_the_scatter_of_log_s(n):
    log_width_variance = report_module("report_figures_jamming").log_width_variance
    rng = np.random.default_rng(3)
    logs = np.log(np.std(rng.normal(size=(200000, n)), axis=1, ddof=1))
    # 200000 draws: the sample variance is good to about 0.3% (kurtosis near 3)
    assert float(np.var(logs)) / log_width_variance(n) == pytest.approx(1.0, abs=0.015)


def test_width_law_tells_one_half_from_one_quarter():
    # Five sizes over a factor 128 in N, 10 samples each: w's error is about 0.063, so 0.25
    # and 0.5 lie four errors apart, and a fit of planted 0.25 puts 0.5 beyond two of its
    # errors in about 97% of the sets (measured 0.978 over 400).
    law = report_module("report_figures_jamming").width_power_law
    fits = [planted(0.25, seed) for seed in range(400)]
    told = sum(abs(w - 0.5) > 2 * e for w, e, _, _ in fits)
    assert told > 0.93 * 400
    assert law([256, 1024], [0.002, 0.001], [10, 10]) is None
