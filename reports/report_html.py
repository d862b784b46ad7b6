"""The report's HTML page and its plain-text summary (what `jam check` prints, table for table),
from a loaded Campaign and its figures; the words both say are report_words.py's.
"""

from report_words import (CAPTION_LONGEST, POOLED_ONLY, POOLED_WHOLE, SUMMARY_LONGEST,
                          SUMMARY_ROWS, by_check, comparison_lines, counts, counts_text, fit_rows,
                          fmt, headlines, no_fit_sentence, num, number_text, outcome_word,
                          own_verdicts, plain, question_text, text)

STYLE = """
body { font-family: sans-serif; max-width: 1200px; margin: 1em auto; color: #222; }
h1 { margin-bottom: 0.2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 3px 7px; text-align: left; vertical-align: top; }
td.num { text-align: right; font-family: monospace; }
tr.pass td.status { background: #d8f0d8; }
tr.fail td.status { background: #f6caca; font-weight: bold; }
tr.inconclusive td.status { background: #f3ecd0; color: #665; }
tr.expected td.status { background: #eadcf2; }
ul.headlines { font-size: 1em; margin: 0.3em 0; }
.reason { color: #555; font-size: 0.9em; }
figure { margin: 0.5em 0 1em; }
h2 { margin: 1.2em 0 0.3em; font-size: 1.25em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.85em; }
.summary { font-size: 1.1em; }
nav.contents { font-size: 0.85em; color: #444; margin: 0.5em 0 1em; }
details.check { margin: 0.4em 0; }
details.check summary { cursor: pointer; padding: 3px 6px; }
details.fail summary { background: #f6caca; }
details.inconclusive summary { background: #f3ecd0; }
details.pass summary { background: #d8f0d8; }
p.files { font-size: 0.85em; margin-top: 0.2em; }
"""


def verdict_table_html(verdicts):
    """One check's verdicts as a table: the cells `jam check` prints (checks.json `table`), the
    case with its short reason and whole reason, then the statistic."""
    rows = ["<table class='verdicts'><tr><th>status</th><th>case</th>"
            "<th>estimate</th><th>|effect| allowed</th><th>margin</th><th>effects in</th>"
            "<th>range judged</th><th>region</th><th>samples per set</th><th>decided by</th>"
            "<th>statistic</th><th>value</th><th>threshold</th></tr>"]
    for v in verdicts:
        c = cells(v)
        css = "expected" if v.expected_failure else v.status
        whole = "" if c["short_reason"] == v.reason else \
            f"<div class='reason'>{text(v.reason)}</div>"
        rows.append(
            f"<tr class='{text(css)}'><td class='status'>{text(c['status'])}</td>"
            f"<td>{text(c['case'])}<div><b>{text(c['short_reason'])}</b></div>{whole}</td>"
            + "".join(f"<td class='num'>{text(c[k])}</td>"
                      for k in ("estimate", "allowed", "margin"))
            + "".join(f"<td>{text(c[k])}</td>"
                      for k in ("unit", "range", "region", "samples", "rule"))
            + f"<td>{text(v.statistic_name)}</td><td class='num'>{num(v.statistic, '.4g')}</td>"
            f"<td class='num'>{num(v.threshold, '.4g')}</td></tr>")
    rows.append("</table>")
    return "\n".join(rows)


def verdicts_html(verdicts):
    """The verdicts folded per check: a line of counts each, the table on demand (a
    <details> element: no script)."""
    parts = []
    for check, mine in by_check(verdicts).items():
        n = counts(mine)
        css = "fail" if n["fail"] else ("inconclusive" if n["inconclusive"] else "pass")
        parts.append(f"<details class='check {css}' id='verdicts-{text(check)}'><summary>"
                     f"<b>{text(check)}</b>: {text(counts_text(n))} "
                     f"({num(len(mine))} verdicts)</summary>{verdict_table_html(mine)}"
                     "</details>")
    return ("<p>Each check folded: its counts, then every verdict with its reason on a click. "
            "The same in checks.json and summary.txt.</p>" + "\n".join(parts))


def fit_table_html(c):
    rows = fit_rows(c)
    if not rows:
        return f"<p>{text(no_fit_sentence(c), longest=CAPTION_LONGEST)}</p>"
    rep = c.fit["representative"]
    quality = str(rep.get("quality", "ok"))
    flag = ("" if quality == "ok" else
            f"<p class='summary'><b>Fit quality: {text(quality)}</b> "
            f"({text(str(rep.get('quality_reason', '')))})</p>")
    out = [flag, "<table><tr><th>parameter</th><th>this campaign (jackknife, bias-corrected)"
           "</th><th>systematic (the scan's choices)</th><th>plain fit</th><th>quality</th>"
           "<th>paper</th></tr>"]
    for name, value, error, paper, paper_error in rows:
        paper_text = "-" if paper is None else f"{num(paper)} &plusmn; {num(paper_error)}"
        # Half the spread over the scan's fits of quality ok (stats.h5 <name>_systematic).
        systematic = rep.get(name + "_systematic")
        out.append(f"<tr><td>{text(name)}</td><td class='num'>{num(value, '.5g')} &plusmn; "
                   f"{num(error, '.4g')}</td>"
                   f"<td class='num'>{'-' if systematic is None else '&plusmn; ' + num(systematic, '.3g')}</td>"
                   f"<td class='num'>{num(rep.get(name + '_plain'), '.4g')}</td>"
                   f"<td>{text(quality)}</td><td class='num'>{paper_text}</td></tr>")
    out.append("</table>")
    out.append(
        f"<p>Window phi in [{num(rep.get('phi_min', 0), '.4f')}, "
        f"{num(rep.get('phi_max', 0), '.4f')}], rates up to {num(rep.get('rate_max', 0), '.3g')}, "
        f"{num(rep.get('points', 0))} points, "
        f"{num(rep.get('samples', 0))} samples; held fixed: {text(str(rep.get('fixed')))}; "
        f"chi^2/dof {num(rep.get('chi2_diag_per_dof'), '.4g')} (diagonal), "
        f"{num(rep.get('chi2_cov_per_dof'), '.4g')} (with covariance); "
        f"start: {text(str(rep.get('start', '-')))}; window settled after "
        f"{num(rep.get('iterations', '-'))} iteration(s); chosen because: "
        f"{text(str(rep.get('chosen_because', '-')))}; errors: "
        f"{text(str(rep.get('error_method', '')))}.</p>")
    return "\n".join(out)


def provenance_html(c, provenance):
    items = "".join(f"<tr><th>{text(k)}</th><td>{text(str(v), longest=4000)}</td></tr>"
                    for k, v in provenance.items())
    campaign = text(c.campaign_text or "(campaign.toml not found)", longest=100000, lines=True)
    return f"<table>{items}</table>\n<h3>Campaign file</h3>\n<pre>{campaign}</pre>"


def _section(anchor, title, body):
    return (anchor, title, f"<section id='{text(anchor)}'><h2>{text(title)}</h2>{body}</section>")


def _figure_section(f):
    """A figure with its caption and the links to its SVG and to the CSV of what it plots."""
    files = (f"<p class='files'>Files: <a href='{text(f.file)}'>PNG</a> &middot; "
             f"<a href='{text(f.svg)}'>SVG</a> &middot; <a href='{text(f.csv)}'>"
             "CSV of the plotted numbers</a></p>")
    body = (f"<figure><img src='{text(f.file)}' alt='{text(f.title)}'>"
            f"<figcaption>{text(f.caption, longest=CAPTION_LONGEST)}</figcaption></figure>{files}")
    return _section("figure-" + f.stem, f.title, body)


def sections(c, figures, provenance):
    """(anchor, title, HTML) of every section in page order: the figures (the fit's table
    before the fit's first figure, else after the others), the verdicts folded per check, the
    provenance."""
    out = []
    fit = _section("section-fit", "Scaling fit (Eq. 1)", fit_table_html(c))
    for f in figures:
        if f.file in ("fit_scan.png", "collapse.png") and fit:
            out.append(fit)
            fit = None
        out.append(_figure_section(f))
    if fit:
        out.append(fit)
    out.append(_section("section-verdicts", "Verdicts", verdicts_html(c.verdicts)))
    out.append(_section("section-provenance", "Provenance", provenance_html(c, provenance)))
    return out


def contents_html(parts):
    items = " &middot; ".join(f"<a href='#{text(anchor)}'>{text(title)}</a>"
                              for anchor, title, _ in parts)
    return f"<nav class='contents'>Contents: {items}</nav>"


def page(c, figures, provenance):
    """The page: the headline (verdict counts, one line per check), the contents, the sections."""
    own = own_verdicts(c.verdicts)
    n = counts(own)
    parts = sections(c, figures, provenance)
    verdict_word = outcome_word(n)
    # The campaign's own checks make its headline; each compared campaign gets a line apart.
    lines = "".join(f"<li>{text(h)}</li>" for h in headlines(own))
    compared = "".join(f"<p class='summary compare'><b>{text(line)}</b></p>"
                       for line in comparison_lines(c))
    asked = question_text(c.question)
    question_html = f"<p class='question'>{text(asked)}</p>" if asked else ""
    body = "\n".join(part for _, _, part in parts)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><link rel="icon" href="data:,">
<title>jam report: {text(c.name)}</title><style>{STYLE}</style></head>
<body>
<h1>Campaign <code>{text(c.name)}</code>, {num(c.dim)}D</h1>
<p class="summary"><b>{verdict_word}</b>: {text(counts_text(n))}.</p>
{compared}
{question_html}
<ul class="headlines">{lines}</ul>
{contents_html(parts)}
{body}
</body></html>
"""


def effect_unit(v):
    """The unit of a verdict's effects: checks.json's `unit`, else its check's margin unit."""
    return v.unit or v.margin_unit or "relative"


def _unit_words(unit):
    return {"relative": "%", "packing_fraction": "packing fraction"}.get(unit, plain(unit))


# The widest a line of the text table is meant to be (checks/verdict.hpp, kTableWidth).
TABLE_WIDTH = 100


def cells(v):
    """The cells of v's row: checks.json's `table`; a file written before jam wrote them gets
    its status, case, unit and region, "-" for the numbers and the whole reason (each number is
    in it, in words)."""
    if v.table is not None:
        return v.table
    return {"status": v.status + (" (expected)" if v.expected_failure else ""), "case": v.case,
            "unit": _unit_words(effect_unit(v)), "estimate": "-", "allowed": "-", "margin": "-",
            "range": "-", "region": v.region or "-", "samples": "-", "rule": "",
            "short_reason": v.reason}


def _numbers_line(w, row):
    """A verdict's numbers, each column as wide as w says (checks/verdict_table.cpp)."""
    status, estimate, allowed, margin, range_, region, samples = row
    return (f"  {status:<{w[0]}}  {estimate:>{w[1]}}  {allowed:<{w[2]}}  {margin:>{w[3]}}  "
            f"{range_:<{w[4]}}  {region:<{w[5]}}  {samples}").rstrip()


NUMBER_KEYS = ("status", "estimate", "allowed", "margin", "range", "region", "samples")


NUMBER_HEADERS = ("verdict", "estimate", "|effect|", "margin", "range judged", "region",
                  "samples")


def _wrapped(words):
    """words on lines of at most TABLE_WIDTH columns, each led by four blanks, broken at blanks
    (checks/verdict_table.cpp, wrapped)."""
    lines, line = [], ""
    for word in words.split():
        if line and 4 + len(line) + 1 + len(word) > TABLE_WIDTH:
            lines.append("    " + line)
            line = ""
        line += (" " if line else "") + word
    return lines + (["    " + line] if line else [])


def _verdict_lines(w, c):
    """A verdict's lines: its numbers, then its case and reason on one line if it fits, else
    the case whole on its line, then the reason and the rule on one line if they fit, else each
    wrapped on lines of their own (checks/verdict_table.cpp, verdict_rows)."""
    lines = [_numbers_line(w, [c[k] for k in NUMBER_KEYS])]
    rule = f"decided by {c['rule']}" if c["rule"] else ""
    why = f"{c['short_reason']}; {rule}" if rule else c["short_reason"]
    if 4 + len(c["case"]) + 2 + len(why) <= TABLE_WIDTH:
        return lines + [f"    {c['case']}: {why}".rstrip()]
    lines.append(f"    {c['case']}".rstrip())
    if 4 + len(why) <= TABLE_WIDTH:
        return lines + [f"    {why}".rstrip()]
    return lines + _wrapped(c["short_reason"]) + _wrapped(rule)


def check_table(check, mine):
    """One check's table, as `jam check` prints it (checks/verdict_table.cpp) from the cells
    jam wrote: a heading with the counts and the unit of its effects, then per verdict a line of
    numbers and its whole case with its short reason."""
    groups = {}
    for v in mine:
        groups.setdefault(effect_unit(v), []).append(v)
    # The check's own unit first (the lammps check's pressures before its positions).
    own = mine[0].margin_unit or "relative"
    groups = dict(sorted(groups.items(), key=lambda g: g[0] != own))
    shown = {id(v): {k: plain(x, SUMMARY_LONGEST) for k, x in cells(v).items()} for v in mine}
    w = [max([len(h)] + [len(shown[id(v)][k]) for v in mine])
         for h, k in zip(NUMBER_HEADERS, NUMBER_KEYS)]
    one_unit = len(groups) == 1

    def unit_of(group):  # the words jam wrote for the unit of a group's effects
        return shown[id(group[0])]["unit"]
    plural = "" if len(mine) == 1 else "s"
    lines = [f"{plain(check)}: {len(mine)} verdict{plural}, {counts_text(counts(mine))}"
             + (f"; effects in {unit_of(next(iter(groups.values())))}" if one_unit else "")]
    regions = {v.region for v in mine}
    if "pooled" in regions and not regions - {"pooled", ""}:
        whole = any(v.region == "pooled" and "whole_compression" in (v.values or {})
                    for v in mine)
        lines.append(POOLED_WHOLE if whole else POOLED_ONLY)
    if any(v.table is None for v in mine):
        lines.append("  (checks.json from an older jam: no table cells; each reason whole)")
    lines.append(_numbers_line(w, NUMBER_HEADERS))
    lines.append("    case: reason; decided by")
    for rows in groups.values():
        if not one_unit:
            lines.append(f"  effects in {unit_of(rows)}:")
        for v in rows:
            lines.extend(_verdict_lines(w, shown[id(v)]))
    return lines


def text_summary(c, report_path):
    """The terminal/CI-log summary: one table per check (as `jam check` prints them), the
    headline per check, the fit against the paper, the page's path."""
    n = counts(c.verdicts)
    lines = [f"jam report: campaign {plain(c.name)} ({c.dim}D), {len(c.ensembles)} ensembles", ""]
    shown = c.verdicts[:SUMMARY_ROWS]
    for check, mine in by_check(shown).items():
        lines.extend(check_table(check, mine))
        lines.append("")
    if len(c.verdicts) > len(shown):
        lines.append(f"... and {len(c.verdicts) - len(shown)} more verdicts: the page lists "
                     "every one")
    lines.append(f"{len(c.verdicts)} verdicts, {counts_text(n)}")
    lines.append("")
    compared = comparison_lines(c)
    own = own_verdicts(c.verdicts)
    if compared:  # this campaign's headline, then each compared campaign's apart
        lines.append(f"this campaign's own checks: {outcome_word(counts(own))}: "
                     f"{counts_text(counts(own))}")
        lines.extend(compared)
    if question_text(c.question):
        lines.append(question_text(c.question))
    lines.extend(headlines(own))
    if not fit_rows(c):
        lines.append(no_fit_sentence(c))
    lines.append("")
    rep = (c.fit or {}).get("representative") or {}
    for name, value, error, paper, paper_error in fit_rows(c):
        if name in ("phi_j", "beta", "y"):
            ref = ("" if paper is None else
                   f"   (paper {number_text(paper, 'g')} +- {number_text(paper_error, 'g')})")
            lines.append(f"fit {name:<6} {number_text(value, '.5g')} +- {fmt(error)} "
                         f"[plain {fmt(rep.get(name + '_plain'))}]{ref}")
    if rep and str(rep.get("quality", "ok")) != "ok":
        lines.append(f"fit quality: {plain(rep.get('quality'))} "
                     f"({plain(rep.get('quality_reason', ''))})")
    lines.append(f"report: {plain(report_path)}")
    return "\n".join(lines) + "\n"
