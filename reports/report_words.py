"""What the report says, the same on its page and in its summary (report_html.py): values as
text, the counts and the headlines of the checks, the question a campaign asked, the lines of
compare_with's campaigns, and the fit's rows or the sentence saying why there is none.

Every value that comes from a file reaches the page through one route: `text()` (made
visible, shortened, HTML-escaped with quotes) or `num()` (a number formatted, anything else
shown as text). The plain-text summary goes through `plain()` (made visible, shortened), so a
control character in a case name never reaches the terminal raw.
"""

import html
import math
import numbers
import re

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


def number_text(x, spec):
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
    return html.escape(number_text(x, spec), quote=True)


def fmt(x):
    return number_text(x, ".4g")


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
        margin = _percent(margins[0]) if relative else number_text(margins[0], ".3g")
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
    alpha = number_text(q.get("alpha"), "g") if _is_number(q.get("alpha")) else "-"
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


def by_check(verdicts):
    """check name -> its verdicts, in the order the checks first appear."""
    out = {}
    for v in verdicts:
        out.setdefault(v.check, []).append(v)
    return out


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
