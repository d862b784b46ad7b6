"""The scaling fit's figures (stats.h5 fit/): the scan over windows and rates (the paper's
Fig. 2) and the collapse (Fig. 3). The paper's values are shown for comparison only: its
scaling function is not published as a formula, and nothing here is fitted with them."""

import matplotlib.pyplot as plt
import numpy as np

from report_plot import Figure, Plotted, panels_with_key, rate_colors, rate_label, rate_text, save

MARKERS = ["o", "s", "^", "D", "v"]
# Points outside the fit window are drawn for context, thinned to this many per rate and size
# (thousands of symbols with error bars made the figure the report's slowest).
UNFITTED_SHOWN = 80
PARAMETERS = [("phi_j", r"$\phi_J$", "phi_J"), ("beta", r"$\beta$", "beta"), ("y", "$y$", "y")]


def _windows(scan):
    """Each row's window index (windows by half-width, widest first; -1 where unknown) and the
    half-widths. Windows are centred on each row's own fitted phi_J."""
    half = scan.get("half_window")
    if half is None:  # files written before the windows were re-centred
        half = (scan["phi_max"] - scan["phi_min"]) / 2
    half = np.round(half, 6)
    widths = sorted(set(half[np.isfinite(half)]), reverse=True)
    index = np.array([widths.index(h) if np.isfinite(h) else -1 for h in half])
    return index, widths


def _x_axis(log_rate, index, widths):
    """(x of each row, tick positions, tick labels, x label): against log10 rate_max, the
    windows side by side around each rate, when the scan has several rates; one category per
    window when it has a single one (no made-up range of rates)."""
    rates = sorted(set(np.round(log_rate[np.isfinite(log_rate)], 6)))
    if len(rates) > 1:
        spread = 0.1 * min(np.diff(rates))
        x = log_rate + spread * (index - (len(widths) - 1) / 2)
        return (x, rates, [f"{r:g}" for r in rates],
                r"$\log_{10}\dot\epsilon_{max}$ (fastest rate in the fit)")
    label = (f"window half-width (single rate_max $10^{{{rates[0]:g}}}$)" if rates
             else "window half-width")
    return (index.astype(float), list(range(len(widths))), [f"±{w:g}" for w in widths], label)


def _usable(scan):
    """Rows whose fit converged and passed its own quality test (`quality_ok`; files written
    before it carry none: every converged row)."""
    ok = np.isfinite(scan["phi_j"])
    if "quality_ok" in scan:
        ok &= scan["quality_ok"] == 1
    return ok


def _scan_panel(ax, scan, name, text, geometry, plotted):
    index, widths, x, log_rate = geometry
    chosen = scan.get("chosen", np.zeros(len(scan["rate_max"])))
    usable = _usable(scan)
    for k, w in enumerate(widths):
        ok = (index == k) & usable & np.isfinite(scan[name])
        series = f"phi_J ± {w:g}"
        ax.errorbar(x[ok], scan[name][ok], yerr=scan[name + "_error"][ok], capsize=3,
                    marker=MARKERS[k % len(MARKERS)], ls="-", lw=0.8, label=f"$\\phi_J \\pm {w:g}$")
        plotted.add(text, series, log_rate[ok], scan[name][ok], scan[name + "_error"][ok])
        pick = ok & (chosen == 1)
        if pick.any():
            ax.plot(x[pick], scan[name][pick], marker="*", ms=16, color="black", ls="none",
                    label="representative")
        papers = np.isfinite(scan[name]) & (scan.get("papers_protocol", np.zeros(len(x))) == 1)
        if (papers & (index == k)).any():
            ax.plot(x[papers & (index == k)], scan[name][papers & (index == k)], marker="D",
                    ms=9, mfc="none", mec="tab:red", ls="none", label="paper's protocol")


def _total_band(ax, rep, name, plotted, text):
    """The representative with its total error, sqrt(jackknife^2 + systematic^2): the drift of
    the scan is inside it when the systematic covers it."""
    value, error = rep.get(name), rep.get(name + "_error")
    systematic = rep.get(name + "_systematic")
    if value is None or error is None or not np.isfinite(value):
        return
    total = float(np.hypot(error, systematic if systematic is not None and
                           np.isfinite(systematic) else 0.0))
    ax.axhspan(value - total, value + total, color="tab:blue", alpha=0.12,
               label="representative ± total error")
    plotted.add(text, "representative ± total error", [np.nan], [value], [total])


def _paper_band(ax, paper, name):
    if name in paper:
        ax.axhspan(paper[name] - paper[name + "_error"], paper[name] + paper[name + "_error"],
                   color="grey", alpha=0.25, label="paper")
        ax.axhline(paper[name], color="grey", lw=0.8)


def _failure_reasons(text):
    """The distinct reasons in fit/scan's `failures` (one line per failed row)."""
    reasons = []
    for line in str(text or "").splitlines():
        # The reason without its numbers in brackets: one entry per kind of failure.
        reason = line.split(": ", 1)[-1].split(" (")[0].strip()
        if reason and reason not in reasons:
            reasons.append(reason)
    return reasons


def scan_figure(c, out_dir):
    """The paper's Fig. 2: fit parameters against rate_max for the three phi windows. None
    when no row of the scan has a result: empty axes say nothing, and the fit's section says
    in one sentence why there is no fit (report_words.no_fit_sentence)."""
    scan = (c.fit or {}).get("scan")
    if not scan or not len(scan.get("rate_max", [])):
        return None
    if not np.isfinite(scan["phi_j"]).any():
        return None
    paper = c.stats_attrs.get("paper", {})
    index, widths = _windows(scan)
    log_rate = np.log10(scan["rate_max"])
    x, ticks, tick_labels, xlabel = _x_axis(log_rate, index, widths)
    fig, axes = plt.subplots(1, 3, layout="constrained", figsize=(13, 3.8))
    plotted = Plotted()
    for ax, (name, label, text) in zip(axes, PARAMETERS):
        plotted.panel(text, "log10 rate_max", text)
        _scan_panel(ax, scan, name, text, (index, widths, x, log_rate), plotted)
        _total_band(ax, (c.fit or {}).get("representative") or {}, name, plotted, text)
        _paper_band(ax, paper, name)
        ax.set_xticks(ticks, tick_labels)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    file = save(fig, out_dir, "fit_scan.png", plotted)
    return Figure(file, "Scaling fit against the fastest rate included", _scan_caption(c, ticks))


def _scan_caption(c, rates):
    rep = (c.fit or {}).get("representative") or {}
    caption = ("Fit parameters of Eq. 1 with jackknife errors for three windows in phi, each "
               "centred on its own fitted phi_J, against the largest rate included (the "
               f"paper's Fig. 2); held fixed: {rep.get('fixed', 'none')}. Star: the "
               f"representative fit ({rep.get('chosen_because', 'none')}); blue band: it with its "
               "total error sqrt(jackknife^2 + systematic^2), the systematic being the largest "
               "distance of any fit of quality ok from it. Red diamond: the paper's protocol "
               "(rate_max 10^-6.5, narrowest window), labelled, never chosen for it. Grey: the "
               "paper's values, for comparison only (nothing is fitted with them).")
    if len(rates) < 2 and len(c.fit["scan"]["rate_max"]):
        caption += " The scan has a single rate_max, so the windows stand side by side."
    scan = c.fit["scan"]
    failed = int(np.sum(~np.isfinite(scan["phi_j"])))
    poor = int(np.sum(np.isfinite(scan["phi_j"]) & ~_usable(scan)))
    if failed or poor:
        reasons = _failure_reasons(c.fit.get("scan_failures"))
        caption += (f" Left out: {failed} fits that failed"
                    + (f" ({'; '.join(reasons)})" if reasons else "")
                    + f" and {poor} that failed their own quality test (stats.h5 fit/scan "
                    "keeps every row).")
    return caption


def _paper_values(c):
    """The paper's published values for this dimension (stats.h5 paper/), one string each."""
    paper = c.stats_attrs.get("paper", {})
    return [f"{text} = {paper[name]:g} ± {paper.get(name + '_error', float('nan')):g}"
            for name, _, text in PARAMETERS if name in paper]


def _paper_citation(c):
    values = _paper_values(c)
    return f"Peshkov & Teitel ({c.dim}D): " + ", ".join(values) if values else ""


def _collapse_points(ax, collapse, plotted, colors, marker, size):
    """One size's collapse: a colour per rate, open symbols outside the fit window."""
    log_rates = np.round(np.log10(collapse["compression_rate"]), 2)
    # Far below the window the pressure is that of the start (~0); not drawn, it says nothing.
    floor = 1e-3 * np.min(collapse["scaled_pressure"][collapse["in_fit"] == 1], initial=np.inf)
    for r in sorted(set(log_rates), reverse=True):
        for in_fit in (1, 0):
            sel = (log_rates == r) & (collapse["in_fit"] == in_fit)
            sel &= collapse["scaled_pressure"] > (floor if np.isfinite(floor) else 0)
            if not sel.any():
                continue
            if not in_fit:  # context only: at most UNFITTED_SHOWN points per rate
                where = np.flatnonzero(sel)
                sel = np.zeros_like(sel)
                sel[where[::max(1, len(where) // UNFITTED_SHOWN)]] = True
            suffix = "" if in_fit else " (not fitted)"
            ax.errorbar(collapse["x"][sel], collapse["scaled_pressure"][sel],
                        yerr=collapse["scaled_pressure_error"][sel], marker=marker, ms=3.5,
                        ls="none", color=colors[r], mfc=colors[r] if in_fit else "none",
                        alpha=1 if in_fit else 0.45, elinewidth=0.6)
            plotted.add("collapse", f"N={size}, {rate_text(r)}{suffix}", collapse["x"][sel],
                        collapse["scaled_pressure"][sel], collapse["scaled_pressure_error"][sel])


def _collapse_sets(c):
    """(N, fit attributes, collapse) to draw: each size's own fit at the representative's
    phi_init and window (fit/families), else the representative fit alone."""
    rep = c.fit["representative"]
    phi_init = c.fit["attrs"].get("phi_init")
    families = [f for f in (c.fit.get("families") or {}).values()
                if phi_init is None or abs(f["family_phi_init"] - phi_init) < 1e-9]
    if len(families) > 1:
        return [(int(f["n"]), f, f["collapse"]) for f in sorted(families, key=lambda f: f["n"])]
    collapse = c.fit.get("collapse")
    if not collapse or not len(collapse.get("x", [])):
        return []
    return [(int(c.fit["attrs"].get("n", 0)), rep, collapse)]


def _collapse_legend(key, c, colors):
    handles = [plt.Line2D([], [], color=colors[r], marker="o", ls="none", label=rate_label(r))
               for r in sorted(colors, reverse=True)]
    handles.append(plt.Line2D([], [], color="grey", marker="o", mfc="none", ls="none",
                              label="open: not in the fit window"))
    values = _paper_values(c)
    title = (f"Peshkov & Teitel ({c.dim}D), cited,\nnothing drawn from them:\n" +
             "\n".join(values)) if values else None
    key.legend(handles=handles, fontsize=7, loc="center left", title=title, title_fontsize=7,
               alignment="left", borderaxespad=0)


def collapse_figure(c, out_dir):
    """The paper's Fig. 3: the scaling collapse, one panel per size, sharing p/rate^q (each size
    scaled with its own fit at the representative's window), fitted and unfitted points
    distinguished; the paper's values cited in the legend (its scaling function is not
    available as a formula: nothing is drawn from them)."""
    if not (c.fit or {}).get("representative"):
        return None
    sets = _collapse_sets(c)
    if not sets:
        return None
    rates = np.concatenate([np.round(np.log10(col["compression_rate"]), 2) for _, _, col in sets])
    colors = rate_colors(rates)
    # x is not shared: each size's own 1/(z nu) stretches its axis differently.
    fig, axes, key = panels_with_key(1, len(sets), (3.8, 4.4), key_width=2.3, sharey="all")
    plotted = Plotted()
    plotted.panel("collapse", "x = (phi - phi_J)/rate^(1/(z nu))", "p / rate^q")
    for ax, (n, fit, collapse) in zip(axes[0], sets):
        _collapse_points(ax, collapse, plotted, colors, "o", n)
        ax.axvline(0, color="k", lw=0.5)
        ax.set_yscale("log")
        ax.set_xlabel(r"$x = (\phi - \phi_J)/\dot\epsilon^{1/z\nu}$")
        ax.grid(alpha=0.3)
        ax.set_title(f"N = {n}: $\\phi_J$ {fit['phi_j']:.4f}, q {fit['q']:.3f}, "
                     f"1/z$\\nu$ {fit['inv_znu']:.3f}", fontsize=8)
    axes[0, 0].set_ylabel(r"$p / \dot\epsilon^{q}$")
    _collapse_legend(key, c, colors)
    file = save(fig, out_dir, "collapse.png", plotted)
    return Figure(file, "Scaling collapse",
                  _collapse_caption(c.fit["representative"], _paper_citation(c), len(sets)))


def _collapse_caption(rep, citation, sizes=1):
    nan = float("nan")
    caption = ("One panel per size (vertical axis shared), each scaled with its own fit "
               "(fit/families: the same window and order as the representative; parameters "
               "in the panel titles), so a size that collapses differently shows in its "
               "parameters and its curve. Representative fit: " if sizes > 1 else "")
    caption += (f"phi_J = {rep.get('phi_j', nan):.5f}, q = {rep.get('q', nan):.4f}, "
               f"1/(z nu) = {rep.get('inv_znu', nan):.4f} (held fixed: "
               f"{rep.get('fixed', 'none')}); solid symbols were in the fit window "
               f"phi in [{rep.get('phi_min', 0):.4f}, {rep.get('phi_max', 0):.4f}], rates up to "
               f"{rep.get('rate_max', 0):.3g}; open symbols were not fitted (thinned to at most "
               f"{UNFITTED_SHOWN} per rate and size; points more than 1000 times below the "
               "fitted ones are left out); the paper's Fig. 3.")
    if citation:
        caption += (f" The paper's values, {citation}, are cited for comparison: its scaling "
                    "function is not published as a formula, so nothing on the figure is "
                    "computed from them.")
    return caption
