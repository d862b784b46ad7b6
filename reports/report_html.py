"""The report's HTML page and its plain-text summary, from a loaded Campaign and its figures.

Every value that comes from a file reaches the page through one route: `text()` (made
visible, shortened, HTML-escaped with quotes) or `num()` (a number formatted, anything else
shown as text). The plain-text summary goes through `plain()` (made visible, shortened), so a
control character in a case name never reaches the terminal raw.
"""

import html
import math
import numbers
import re

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


# A value longer than this is shown shortened, with its length (a 50 MB case name once made a
# 2 GB summary).
LONGEST = 300
# The summary is read in a terminal or a CI log: each column padded to the longest value shown,
# so values are cut shorter there, and at most SUMMARY_ROWS verdicts are listed.
SUMMARY_LONGEST = 120
SUMMARY_ROWS = 2000
# A figure's caption is jam's own sentences with numbers (the longest about 800 characters):
# shown whole, bounded only against a value in it grown out of all proportion.
CAPTION_LONGEST = 4000


def plain(x, longest=LONGEST, lines=False):
    """A value as text for a terminal or a page: control characters shown as escapes (\\x1b,
    \\x00; line breaks kept when `lines`), at most `longest` characters."""
    s = x if isinstance(x, str) else str(x)
    if len(s) > longest:
        s = f"{s[:longest]}... ({len(s)} characters)"
    keep = " \n" if lines else " "
    return "".join(ch if ch.isprintable() or ch in keep else ascii(ch)[1:-1] for ch in s)


def text(x, longest=LONGEST, lines=False):
    """A value as HTML text: plain(), then escaped (quotes too, so attributes are safe)."""
    return html.escape(plain(x, longest, lines), quote=True)


def _is_number(x):
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def _number_text(x, spec):
    """A number formatted by spec (integers whole when spec is empty), '-' for None or a
    non-finite number; anything else as plain text."""
    if x is None:
        return "-"
    if not _is_number(x):
        return plain(x)
    if isinstance(x, numbers.Integral) and not spec:
        return str(int(x))
    x = float(x)
    return format(x, spec or "g") if math.isfinite(x) else "-"


def num(x, spec=""):
    """A number for the page (formatted, then escaped like any text)."""
    return html.escape(_number_text(x, spec), quote=True)


def _fmt(x):
    return _number_text(x, ".4g")


def counts(verdicts):
    """The three outcomes, with the failures the campaign expects counted apart."""
    out = {"pass": 0, "fail": 0, "inconclusive": 0, "expected": 0, "expected_passed": 0}
    for v in verdicts:
        if v.status == "fail" and v.expected_failure:
            out["expected"] += 1
        else:
            out[v.status] = out.get(v.status, 0) + 1
        if v.status == "pass" and v.expected_failure:
            out["expected_passed"] += 1
    return out


def counts_text(n):
    words = f"{n['pass']} passed, {n['fail']} failed, {n['inconclusive']} inconclusive"
    if n["expected"]:
        words += f", {n['expected']} failed as expected"
    if n["expected_passed"]:
        words += f" ({n['expected_passed']} expected to fail passed)"
    return words


def _percent(x):
    return f"{100 * x:.3g}%" if _is_number(x) else plain(x)


def headline(check, verdicts):
    """One line per check: what it excludes, at what margin, and what it could not decide."""
    n = counts(verdicts)
    margins = sorted({v.margin for v in verdicts if v.margin is not None})
    relative = verdicts[0].margin_unit == "relative"
    if len(margins) == 1:
        margin = _percent(margins[0]) if relative else _number_text(margins[0], ".3g")
    else:
        margin = "each verdict's margin" if margins else "its margin"
    parts = [f"no effect above {margin} in {n['pass']} of {len(verdicts)}"]
    if n["fail"]:
        parts.append(f"{n['fail']} failed{_where(verdicts, 'fail')}")
    if n["expected"]:
        parts.append(f"{n['expected']} failed as expected")
    if n["inconclusive"]:
        needed = [v.samples_needed for v in verdicts
                  if v.status == "inconclusive" and v.samples_needed is not None]
        span = (f"{int(min(needed))}" if needed and min(needed) == max(needed)
                else f"{int(min(needed or [0]))}-{int(max(needed or [0]))}")
        need = f", needs about {span} samples per set (estimate)" if needed else ""
        parts.append(f"{n['inconclusive']} inconclusive{_where(verdicts, 'inconclusive')}{need}")
    regions = {v.region for v in verdicts}
    asked = [v for v in verdicts if v.region == "asked"]
    if asked:
        a = counts(asked)
        parts.append(f"in the range asked {a['pass']} passed, {a['fail']} failed, "
                     f"{a['inconclusive']} inconclusive")
    if any(v.region == "pooled" and "whole_compression" in (v.values or {}) for v in verdicts) \
            and not regions & set(REGIONS + ("asked",)):
        parts.append(POOLED_WHOLE.strip().lower())
    elif "pooled" in regions and not regions & set(REGIONS + ("asked",)):
        parts.append("pooled only, no region around jamming judged (no phi_J: no scaling fit, "
                     "no jamming points, no --phi-j)")
    return f"{plain(check).replace('_', ' ')}: " + "; ".join(parts)


def question_text(q):
    """The question the verdicts answer (checks.json "question"), one line; None without one."""
    if not isinstance(q, dict):
        return None
    r = q.get("range")
    if isinstance(r, dict) and _is_number(r.get("phi_min")) and _is_number(r.get("phi_max")):
        where = (f"the range asked, phi in [{r['phi_min']:g}, {r['phi_max']:g}] "
                 f"({plain(r.get('from', ''))})")
    else:
        where = f"no range asked: the pooled verdicts judge {plain(q.get('pooled', 'their own range'))}"
    wanted = q.get("checks")
    checks = (", ".join(plain(c) for c in wanted) if isinstance(wanted, list) and wanted
              else "every check")
    alpha = _number_text(q.get("alpha"), "g") if _is_number(q.get("alpha")) else "-"
    return f"question: {where}; checks {checks}; alpha {alpha}"


REGIONS = ("below", "at", "above")
# The line under a check's heading when it judged no region (checks/verdict_table.cpp).
POOLED_ONLY = ("  pooled only: no region around jamming judged (no phi_J: no scaling fit, no "
               "jamming points, no --phi-j)")
# ... when its pooled range is besides the whole compression (checks/verdict_table.cpp).
POOLED_WHOLE = ("  POOLED OVER THE WHOLE COMPRESSION: no range asked ([question] phi_min, "
                "phi_max) and no region around jamming (no scaling fit, no jamming points, <Z> "
                "does not cross 2D, no --phi-j); each reason says why")


def _where(verdicts, status):
    """' (below jamming 5, at jamming 2)': the regions of the verdicts of a status, when any
    of them judged a region around jamming."""
    counted = {r: sum(v.status == status and v.region == r
                      and (status != "fail" or not v.expected_failure)
                      for v in verdicts) for r in REGIONS}
    if not any(counted.values()):
        return ""
    return " (" + ", ".join(f"{r} jamming {k}" for r, k in counted.items() if k) + ")"


def headlines(verdicts):
    return [headline(check, vs) for check, vs in by_check(verdicts).items()]


# The checks that judge the campaigns of compare_with against this one: compare and its parts
# (checks/check_registry.hpp). Their verdicts are another code's, not this campaign's: they
# get a headline line of their own and never turn this campaign's.
COMPARE_CHECKS = ("compare", "compare_jamming", "compare_fit", "compare_fit_phi_j")


def own_verdicts(verdicts):
    """The verdicts of the campaign's own checks (every one but compare_with's)."""
    return [v for v in verdicts if v.check not in COMPARE_CHECKS]


def outcome_word(n):
    if not any(n.values()):
        return "NOTHING JUDGED"  # e.g. a question that asks for compare alone
    return "FAIL" if n["fail"] else ("INCONCLUSIVE" if n["inconclusive"] else "PASS")


def _compare_with(c):
    """The directories of the campaign file's compare_with ([] when it has none or cannot be
    read: the verdicts then name each campaign by its name alone)."""
    try:
        import tomllib
        listed = tomllib.loads(c.campaign_text or "").get("compare_with", [])
    except (ImportError, ValueError, AttributeError):
        return []
    return [d for d in listed if isinstance(d, str)] if isinstance(listed, list) else []


def comparisons(c):
    """other campaign -> its compare verdicts, in the order met. The other campaign is named
    in each case ("... OTHER vs THIS, constant phi", "OTHER vs THIS: all"); by its directory
    in compare_with where that directory's last part is its name."""
    out = {}
    found = re.compile(r"(?:^|: )(\S+) vs " + re.escape(str(c.name)) + r"(?:[,:]|$)")
    directories = _compare_with(c)
    for v in c.verdicts:
        if v.check not in COMPARE_CHECKS:
            continue
        m = found.search(str(v.case))
        name = m.group(1) if m else "another campaign"
        where = next((d for d in directories
                      if d.rstrip("/").rsplit("/", 1)[-1] == name), name)
        out.setdefault(where, []).append(v)
    return out


def comparison_lines(c):
    """One line per compared campaign: "compare with DIR: FAIL: 4 passed, 4 failed, ..."."""
    return [f"compare with {plain(where)}: {outcome_word(counts(mine))}: "
            f"{counts_text(counts(mine))}" for where, mine in comparisons(c).items()]


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


def by_check(verdicts):
    """check name -> its verdicts, in the order the checks first appear."""
    out = {}
    for v in verdicts:
        out.setdefault(v.check, []).append(v)
    return out


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


def fit_rows(c):
    """(parameter, this campaign, error, paper, paper error) of the representative fit."""
    rep = (c.fit or {}).get("representative")
    if not rep:
        return []
    paper = c.stats_attrs.get("paper", {})
    out = []
    for name in ("phi_j", "beta", "y", "q", "inv_znu"):
        if name in rep:
            out.append((name, rep[name], rep.get(name + "_error"), paper.get(name),
                        paper.get(name + "_error")))
    return out


# A number in a fit's failure reason: reasons that differ only in these are one kind.
_NUMBER = re.compile(r"[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?")


def folded_failures(failures):
    """stats.h5 fit/scan's `failures` (one line per failed row, "rate_max R window +-W:
    reason") folded as `jam stats` prints them (stats/scan_failures.cpp): each kind of reason
    once, with its rows, "6 rows, e.g.: reason | 1 row: reason"."""
    kinds = {}
    for line in str(failures or "").splitlines():
        reason = line.split(": ", 1)[-1].strip()
        reason = reason[len("fit: "):] if reason.startswith("fit: ") else reason
        if not reason or reason == "none":
            continue
        kind = kinds.setdefault(_NUMBER.sub("#", reason), [reason, 0, False])
        kind[1] += 1
        kind[2] = kind[2] or reason != kind[0]
    return " | ".join(f"{rows} row{'' if rows == 1 else 's'}{', e.g.' if differ else ''}: "
                      f"{reason}" for reason, rows, differ in kinds.values())


def _fitted_rates(c):
    """The log10 rates of the ensembles at the fit's phi_init (every ensemble without one)."""
    phi_init = (c.fit or {}).get("attrs", {}).get("phi_init")
    return sorted({e.log10_rate for e in c.ensembles
                   if not _is_number(phi_init) or abs(e.phi_init - phi_init) < 1e-9},
                  reverse=True)


def no_fit_sentence(c):
    """Why the campaign has no scaling fit, in one sentence: fewer than 3 rates, else the
    scan's distinct failure reasons when none of its fits could be made, else why no fit was
    taken as the representative."""
    fit = c.fit or {}
    # First the design: with fewer than 3 rates `jam stats` attempts no fit and writes none.
    rates = _fitted_rates(c)
    if len(rates) < 3:
        listed = ", ".join(f"1e{r:g}" for r in rates) or "none"
        return (f"No scaling fit: fewer than 3 rates (the fitted ensembles have {len(rates)}: "
                f"{listed}); a scaling fit needs at least 3, with 2 phi_J and q trade off.")
    if not fit:
        return "No scaling fit: stats.h5 has none (jam stats --no-fit, or no ensemble to fit)."
    scan = fit.get("scan") or {}
    phi_j = scan.get("phi_j", [])
    if len(phi_j) and not any(math.isfinite(x) for x in phi_j):
        return (f"No scaling fit: none of the {len(phi_j)} fits of the scan could be made "
                f"({folded_failures(fit.get('scan_failures'))}).")
    return f"No scaling fit: {fit.get('attrs', {}).get('failure', 'no representative fit')}."


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
                   f"   (paper {_number_text(paper, 'g')} +- {_number_text(paper_error, 'g')})")
            lines.append(f"fit {name:<6} {_number_text(value, '.5g')} +- {_fmt(error)} "
                         f"[plain {_fmt(rep.get(name + '_plain'))}]{ref}")
    if rep and str(rep.get("quality", "ok")) != "ok":
        lines.append(f"fit quality: {plain(rep.get('quality'))} "
                     f"({plain(rep.get('quality_reason', ''))})")
    lines.append(f"report: {plain(report_path)}")
    return "\n".join(lines) + "\n"
