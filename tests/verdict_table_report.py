#!/usr/bin/python3
"""The report's verdict tables against jam's, from one checks.json (run by
tests/test_verdict_table.cpp, which writes the three files from the same verdicts):

  - the summary's tables (what `jam report` and `jam pipeline` print) are, line for line, the
    table `jam check` printed (table.txt);
  - each row of the page's folded tables shows the verdict's cells as checks.json has them
    (`table`: status, estimate, |effect| allowed, margin, unit, range, region, samples, rule,
    short reason);
  - each JUnit test case gives the same cells, one a line;
  - a checks.json written before jam wrote the cells (each `table` removed) still gives a row
    per verdict, with its whole reason and "-" for the numbers;
  - a cell holding markup or an escape sequence reaches the page escaped and the summary
    visible; a cell that is not a string is one line naming the verdict and the field.

Usage: verdict_table_report.py --source DIR checks.json table.txt checks.xml
Exit status 1, with what differs, when any of these fails.
"""

import argparse
import copy
import difflib
import html
import json
import os
import re
import sys
import tempfile
import xml.etree.ElementTree as ET


def summary_tables(report_data, report_html, jamio, path):
    """The summary's tables of the verdicts in the checks.json at path, and the verdicts."""
    verdicts = report_data._verdicts(jamio.load_checks(path))
    lines = []
    for check, mine in report_html.by_check(verdicts).items():
        lines.extend(report_html.check_table(check, mine))
        lines.append("")
    lines.append(f"{len(verdicts)} verdicts, "
                 f"{report_html.counts_text(report_html.counts(verdicts))}")
    return lines, verdicts


def html_rows(report_html, verdicts):
    """Each verdict's row of the page's table, as the text of its cells."""
    out = []
    for _, mine in report_html.by_check(verdicts).items():
        page = report_html.verdict_table_html(mine)
        for row in re.findall(r"<tr class='[a-z]+'>(.*?)</tr>", page, re.S):
            cells = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)
            out.append([html.unescape(re.sub(r"<[^>]+>", "\n", c)) for c in cells])
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("checks")
    parser.add_argument("table")
    parser.add_argument("junit")
    a = parser.parse_args()
    sys.path.insert(0, os.path.join(a.source, "reports"))
    import report_data
    import report_html
    jamio = report_data.jamio
    failures = []

    printed = open(a.table).read().splitlines()
    laid_out, verdicts = summary_tables(report_data, report_html, jamio, a.checks)
    if laid_out != printed:
        failures.append("the summary's tables differ from jam check's:\n" + "\n".join(
            difflib.unified_diff(printed, laid_out, "jam check", "report", lineterm="")))

    with open(a.checks) as f:
        written = json.load(f)["verdicts"]
    rows = html_rows(report_html, verdicts)
    # The page lists the verdicts check by check: the file's in that order.
    checks = list(dict.fromkeys(v["check"] for v in written))
    order = sorted(range(len(written)), key=lambda k: checks.index(written[k]["check"]))
    if len(rows) != len(written):
        failures.append(f"{len(rows)} rows on the page, {len(written)} verdicts")
    junit = ET.parse(a.junit).getroot().findall("testcase")
    for k, row in zip(order, rows):
        v = written[k]
        t = v["table"]
        # status, case + reasons, estimate, allowed, margin, unit, range, region, samples, rule
        shown = [row[0], row[2], row[3], row[4], row[5], row[6], row[7], row[8], row[9]]
        wanted = [t[key] for key in ("status", "estimate", "allowed", "margin", "unit", "range",
                                     "region", "samples", "rule")]
        if shown != wanted:
            failures.append(f"verdict {k}: the page shows {shown}, checks.json {wanted}")
        if t["short_reason"] not in row[1].split("\n") or t["case"] not in row[1]:
            failures.append(f"verdict {k}: the page's case cell {row[1]!r} lacks its case or "
                            f"short reason {t['short_reason']!r}")
        said = junit[k].find("system-out").text.splitlines()
        for label, key in (("effects in", "unit"), ("estimate", "estimate"),
                           ("|effect|", "allowed"), ("margin", "margin"),
                           ("range judged", "range"), ("region", "region"),
                           ("samples", "samples"), ("reason", "short_reason"),
                           ("decided by", "rule")):
            line = f"{label}: {t[key] or '-'}"
            if line not in said:
                failures.append(f"verdict {k}: JUnit lacks {line!r}: {said}")

    # A checks.json of an older jam: no cells; a row per verdict with its whole reason.
    old = copy.deepcopy(json.load(open(a.checks)))
    for v in old["verdicts"]:
        del v["table"]
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "checks.json")
        with open(path, "w") as f:
            json.dump(old, f)
        lines, old_verdicts = summary_tables(report_data, report_html, jamio, path)
    statuses = [line for line in lines if line.startswith("  ")
                and line.split()[0] in ("pass", "fail", "inconclusive")]
    if len(statuses) != len(written):
        failures.append(f"older checks.json: {len(statuses)} rows, {len(written)} verdicts")
    flowing = " ".join(line.strip() for line in lines)  # the reasons wrapped, joined again
    for v in written:
        if report_html.plain(v["reason"], report_html.SUMMARY_LONGEST)[:80] not in flowing:
            failures.append(f"older checks.json: the whole reason {v['reason']!r} not shown")
    if not any("from an older jam" in line for line in lines):
        failures.append("older checks.json: the summary does not say its cells are missing")
    if len(html_rows(report_html, old_verdicts)) != len(written):
        failures.append("older checks.json: the page lacks rows")

    # Cells are values from a file like any other: markup escaped on the page, control
    # characters visible in the summary; a cell that is not a string is one line naming it.
    hostile = copy.deepcopy(json.load(open(a.checks)))
    hostile["verdicts"][0]["table"]["estimate"] = "<script>\x1b[31m"
    hostile["verdicts"][0]["table"]["rule"] = "\"onerror=x"
    mistyped = copy.deepcopy(hostile)
    mistyped["verdicts"][1]["table"]["margin"] = 5
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "checks.json")
        with open(path, "w") as f:
            json.dump(hostile, f)
        lines, hostile_verdicts = summary_tables(report_data, report_html, jamio, path)
        page = report_html.verdict_table_html(hostile_verdicts)
        if "<script>" in page or "\"onerror" in page or "\x1b" in "\n".join(lines):
            failures.append("a hostile cell reached the page unescaped or the summary raw")
        with open(path, "w") as f:
            json.dump(mistyped, f)
        try:
            summary_tables(report_data, report_html, jamio, path)
            failures.append("a numeric table cell was accepted")
        except (report_data.ReportInputError, jamio.JamioError) as e:
            # jamio refuses it as it reads the file (the schema, reference/schema/checks.toml).
            if "verdict 1: field 'table.margin' is 5, not a string" not in str(e) or \
                    "\n" in str(e):
                failures.append(f"a numeric table cell: {e}")

    for f in failures:
        print("FAILED:", f)
    print(f"{'ok' if not failures else str(len(failures)) + ' failed'}: {len(written)} verdicts")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
