"""The report's HTML page and its plain-text summary, from a loaded Campaign and its figures."""

import html
import math

STYLE = """
body { font-family: sans-serif; max-width: 1200px; margin: 2em auto; color: #222; }
h1 { margin-bottom: 0.2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 3px 7px; text-align: left; vertical-align: top; }
td.num { text-align: right; font-family: monospace; }
tr.pass td.status { background: #d8f0d8; }
tr.fail td.status { background: #f6caca; font-weight: bold; }
tr.inconclusive td.status { background: #f3ecd0; color: #665; }
tr.expected td.status { background: #eadcf2; }
ul.headlines { font-size: 1.05em; }
.reason { color: #555; font-size: 0.9em; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.85em; }
.summary { font-size: 1.1em; }
nav.contents ol { columns: 2; font-size: 0.95em; }
p.files { font-size: 0.85em; margin-top: 0.2em; }
"""


def _fmt(x):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.4g}"


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
    text = f"{n['pass']} passed, {n['fail']} failed, {n['inconclusive']} inconclusive"
    if n["expected"]:
        text += f", {n['expected']} failed as expected"
    if n["expected_passed"]:
        text += f" ({n['expected_passed']} expected to fail passed)"
    return text


def _percent(x):
    return f"{100 * x:.3g}%"


def headline(check, verdicts):
    """One line per check: what it excludes, at what margin, and what it could not decide."""
    n = counts(verdicts)
    margins = sorted({v.margin for v in verdicts if v.margin is not None})
    relative = verdicts[0].margin_unit == "relative"
    if len(margins) == 1:
        margin = _percent(margins[0]) if relative else f"{margins[0]:.3g}"
    else:
        margin = "each verdict's margin" if margins else "its margin"
    parts = [f"no effect above {margin} in {n['pass']} of {len(verdicts)}"]
    if n["fail"]:
        parts.append(f"{n['fail']} failed")
    if n["expected"]:
        parts.append(f"{n['expected']} failed as expected")
    if n["inconclusive"]:
        needed = [v.samples_needed for v in verdicts
                  if v.status == "inconclusive" and v.samples_needed is not None]
        span = (f"{int(min(needed))}" if needed and min(needed) == max(needed)
                else f"{int(min(needed or [0]))}-{int(max(needed or [0]))}")
        need = f", needs about {span} samples per set (estimate)" if needed else ""
        parts.append(f"{n['inconclusive']} inconclusive{need}")
    return f"{check.replace('_', ' ')}: " + "; ".join(parts)


def headlines(verdicts):
    by_check = {}
    for v in verdicts:
        by_check.setdefault(v.check, []).append(v)
    return [headline(check, vs) for check, vs in by_check.items()]


def verdict_table_html(verdicts):
    rows = ["<table id='verdicts'><tr><th>status</th><th>check</th><th>case</th>"
            "<th>statistic</th><th>value</th><th>threshold</th>"
            "<th>smallest detectable effect</th><th>effects excluded above</th>"
            "<th>margin</th></tr>"]
    for v in verdicts:
        status = v.status + (" (expected)" if v.expected_failure else "")
        css = "expected" if v.expected_failure else v.status
        rows.append(
            f"<tr class='{html.escape(css)}'><td class='status'>{html.escape(status)}</td>"
            f"<td>{html.escape(v.check)}</td><td>{html.escape(v.case)}"
            f"<div class='reason'>{html.escape(v.reason)}</div></td>"
            f"<td>{html.escape(v.statistic_name)}</td><td class='num'>{_fmt(v.statistic)}</td>"
            f"<td class='num'>{_fmt(v.threshold)}</td><td class='num'>{_fmt(v.detectable)}</td>"
            f"<td class='num'>{_fmt(v.excluded_above)}</td><td class='num'>{_fmt(v.margin)}</td>"
            "</tr>")
    rows.append("</table>")
    return "\n".join(rows)


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


def fit_table_html(c):
    rows = fit_rows(c)
    if not rows:
        failure = (c.fit or {}).get("attrs", {}).get("failure", "no fit in stats.h5")
        return f"<p>No scaling fit: {html.escape(str(failure))}</p>"
    rep = c.fit["representative"]
    quality = str(rep.get("quality", "ok"))
    flag = ("" if quality == "ok" else
            f"<p class='summary'><b>Fit quality: {html.escape(quality)}</b> "
            f"({html.escape(str(rep.get('quality_reason', '')))})</p>")
    out = [flag, "<table><tr><th>parameter</th><th>this campaign (jackknife, bias-corrected)"
           "</th><th>plain fit</th><th>quality</th><th>paper</th></tr>"]
    for name, value, error, paper, paper_error in rows:
        paper_text = "-" if paper is None else f"{paper:g} &plusmn; {paper_error:g}"
        out.append(f"<tr><td>{name}</td><td class='num'>{value:.5g} &plusmn; {_fmt(error)}</td>"
                   f"<td class='num'>{_fmt(rep.get(name + '_plain'))}</td>"
                   f"<td>{html.escape(quality)}</td><td class='num'>{paper_text}</td></tr>")
    out.append("</table>")
    out.append(
        f"<p>Window phi in [{rep.get('phi_min', 0):.4f}, {rep.get('phi_max', 0):.4f}], rates up "
        f"to {rep.get('rate_max', 0):.3g}, {rep.get('points', 0)} points, "
        f"{rep.get('samples', 0)} samples; held fixed: {html.escape(str(rep.get('fixed')))}; "
        f"chi^2/dof {_fmt(rep.get('chi2_diag_per_dof'))} (diagonal), "
        f"{_fmt(rep.get('chi2_cov_per_dof'))} (with covariance); "
        f"start: {html.escape(str(rep.get('start', '-')))}; window settled after "
        f"{rep.get('iterations', '-')} iteration(s); chosen because: "
        f"{html.escape(str(rep.get('chosen_because', '-')))}; errors: "
        f"{html.escape(str(rep.get('error_method', '')))}.</p>")
    return "\n".join(out)


def provenance_html(c, provenance):
    items = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>"
                    for k, v in provenance.items())
    campaign = html.escape(c.campaign_text or "(campaign.toml not found)")
    return f"<table>{items}</table>\n<h3>Campaign file</h3>\n<pre>{campaign}</pre>"


def _section(anchor, title, body):
    return (anchor, title, f"<section id='{anchor}'><h2>{html.escape(title)}</h2>{body}</section>")


def _figure_section(f):
    """A figure with its caption and the links to its SVG and to the CSV of what it plots."""
    files = (f"<p class='files'>Files: <a href='{html.escape(f.file)}'>PNG</a> &middot; "
             f"<a href='{html.escape(f.svg)}'>SVG</a> &middot; <a href='{html.escape(f.csv)}'>"
             "CSV of the plotted numbers</a></p>")
    body = (f"<figure><img src='{html.escape(f.file)}' alt='{html.escape(f.title)}'>"
            f"<figcaption>{html.escape(f.caption)}</figcaption></figure>{files}")
    return _section("figure-" + f.stem, f.title, body)


def sections(c, figures, provenance):
    """(anchor, title, HTML) of every section in page order: the verdicts, the figures with
    the fit's table before the fit's first figure (else after the others), the provenance."""
    out = [_section("section-verdicts", "Verdicts", verdict_table_html(c.verdicts))]
    fit = _section("section-fit", "Scaling fit (Eq. 1)", fit_table_html(c))
    for f in figures:
        if f.file in ("fit_scan.png", "collapse.png") and fit:
            out.append(fit)
            fit = None
        out.append(_figure_section(f))
    if fit:
        out.append(fit)
    out.append(_section("section-provenance", "Provenance", provenance_html(c, provenance)))
    return out


def contents_html(parts):
    items = "".join(f"<li><a href='#{anchor}'>{html.escape(title)}</a></li>"
                    for anchor, title, _ in parts)
    return f"<nav class='contents'><h2>Contents</h2><ol>{items}</ol></nav>"


def page(c, figures, provenance):
    """The page: the headline (verdict counts, one line per check), the contents, the sections."""
    n = counts(c.verdicts)
    parts = sections(c, figures, provenance)
    verdict_word = "FAIL" if n["fail"] else ("INCONCLUSIVE" if n["inconclusive"] else "PASS")
    lines = "".join(f"<li>{html.escape(h)}</li>" for h in headlines(c.verdicts))
    body = "\n".join(part for _, _, part in parts)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><link rel="icon" href="data:,">
<title>jam report: {html.escape(c.name)}</title><style>{STYLE}</style></head>
<body>
<h1>Campaign <code>{html.escape(c.name)}</code>, {c.dim}D</h1>
<p class="summary"><b>{verdict_word}</b>: {html.escape(counts_text(n))}.</p>
<ul class="headlines">{lines}</ul>
{contents_html(parts)}
{body}
</body></html>
"""


def text_summary(c, report_path):
    """The terminal/CI-log summary: the verdict table, the fit against the paper, the path."""
    n = counts(c.verdicts)
    lines = [f"jam report: campaign {c.name} ({c.dim}D), {len(c.ensembles)} ensembles", ""]
    width = max([len(v.case) for v in c.verdicts] + [4])
    check_width = max([len(v.check) for v in c.verdicts] + [5])
    lines.append(f"{'status':<16}{'check':<{check_width + 2}}{'case':<{width + 2}}"
                 f"{'value':>11}{'threshold':>11}{'detectable':>11}{'excluded>':>11}"
                 f"{'margin':>9}")
    for v in c.verdicts:
        status = v.status + ("(expected)" if v.expected_failure else "")
        lines.append(f"{status:<16}{v.check:<{check_width + 2}}{v.case:<{width + 2}}"
                     f"{_fmt(v.statistic):>11}{_fmt(v.threshold):>11}{_fmt(v.detectable):>11}"
                     f"{_fmt(v.excluded_above):>11}{_fmt(v.margin):>9}")
    lines.append(counts_text(n))
    lines.append("")
    lines.extend(headlines(c.verdicts))
    lines.append("")
    rep = (c.fit or {}).get("representative") or {}
    for name, value, error, paper, paper_error in fit_rows(c):
        if name in ("phi_j", "beta", "y"):
            ref = "" if paper is None else f"   (paper {paper:g} +- {paper_error:g})"
            lines.append(f"fit {name:<6} {value:.5g} +- {_fmt(error)} "
                         f"[plain {_fmt(rep.get(name + '_plain'))}]{ref}")
    if rep and str(rep.get("quality", "ok")) != "ok":
        lines.append(f"fit quality: {rep.get('quality')} ({rep.get('quality_reason', '')})")
    lines.append(f"report: {report_path}")
    return "\n".join(lines) + "\n"
