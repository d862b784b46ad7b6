"""The report's figures, one function each, drawn with matplotlib from a loaded Campaign.

Each function writes one figure into the output directory (PNG, SVG and the CSV of its plotted
numbers, one stem: report_plot.save) and returns a Figure record (file name, title, caption),
or None when the campaign has nothing to draw for it; a panel with nothing to draw is left out
of its figure. Only drawing happens here: every number comes from stats.h5 or checks.h5.
This file: the averages (pressure, relative errors) and the jamming points; the checks' and
the fit's figures are in report_figures_checks.py and report_figures_fit.py; ALL lists them in
page order.
"""

import matplotlib.pyplot as plt
import numpy as np

from report_figures_checks import finite_size_figure, lammps_figure, sample_pairs_figure
from report_figures_fit import collapse_figure, scan_figure
from report_figures_jamming import jamming_width_figure
from report_plot import (Figure, Plotted, decorate, rate_colors, rate_label, rate_text,
                         representative_phi_init, save, shade)

MARKERS = ["o", "s", "^", "D", "v", "P", "X"]


def _pressure_style(chosen):
    """style(e): one hue per phi_init, a lighter shade and another marker per slower rate,
    solid symbols for the smallest size and open ones for the others."""
    starts = sorted({e.phi_init for e in chosen})
    rates = sorted({e.log10_rate for e in chosen}, reverse=True)
    smallest = min(e.n for e in chosen)
    hues = plt.get_cmap("tab10")

    def style(e):
        k = rates.index(e.log10_rate)
        color = shade(hues(starts.index(e.phi_init) % 10), k, len(rates))
        return dict(marker=MARKERS[k % len(MARKERS)], ms=4, lw=0.8, capsize=0, color=color,
                    mfc=color if e.n == smallest else "none")
    return style


def _pressure_curve(axes, e, style, plotted):
    """One ensemble on both panels; the 5th percentile of its positive p/rate (for the floor)."""
    a = e.constant_phi
    phi, p, dp = a["packing_fraction"], a["pressure_mean"], a["pressure_error"]
    keep = p > 0
    label = f"N={e.n}, phi_init {e.phi_init:g}, {rate_label(e.log10_rate)}"
    series = f"N={e.n}, phi_init {e.phi_init:g}, {rate_text(e.log10_rate)}"
    every = dict(markevery=max(1, int(keep.sum()) // 30), errorevery=max(1, len(p) // 30))
    rate = e.compression_rate
    for ax, panel, scale in zip(axes, ("pressure", "bulk viscosity"), (1.0, rate)):
        ax.errorbar(phi[keep], p[keep] / scale, yerr=dp[keep] / scale, label=label, **every,
                    **style(e))
        plotted.add(panel, series, phi[keep], p[keep] / scale, dp[keep] / scale)
    return np.percentile(p[keep], 5) / rate if keep.any() else np.inf


def pressure_figure(c, out_dir):
    """The paper's Fig. 1: pressure and bulk viscosity against phi, every rate, every size,
    every phi_init."""
    chosen = [e for e in c.ensembles if e.constant_phi]
    if not chosen:
        return None
    sizes = sorted({e.n for e in chosen})
    starts = sorted({e.phi_init for e in chosen})
    style = _pressure_style(chosen)
    # The legend has a column of its own: with every phi_init, rate and size it is long.
    fig, (*axes, key) = plt.subplots(1, 3, layout="constrained", figsize=(13, 4.4),
                                     width_ratios=[1, 1, 0.45])
    plotted = Plotted()
    labels = ["pressure $p$", r"bulk viscosity $\eta_p = p/\dot\epsilon$"]
    for panel, label in zip(("pressure", "bulk viscosity"), ("pressure p", "p / rate")):
        plotted.panel(panel, "packing fraction phi", label)
    lowest = [_pressure_curve(axes, e, style, plotted) for e in chosen]
    # The first points after the start carry the relaxed start's residual pressure, orders of
    # magnitude below the compression's: the vertical range starts near the compression's.
    floor = 0.3 * min(lowest)
    if np.isfinite(floor):
        axes[1].set_ylim(bottom=floor)
        axes[0].set_ylim(bottom=floor * min(e.compression_rate for e in chosen))
    for ax, label in zip(axes, labels):
        ax.set_yscale("log")
        ax.set_xlabel(r"packing fraction $\phi$")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    key.axis("off")
    key.legend(*axes[1].get_legend_handles_labels(), fontsize=7, loc="center left",
               ncol=1 + len(chosen) // 24, borderaxespad=0)
    file = save(fig, out_dir, "pressure.png", plotted)
    return Figure(file, "Pressure and bulk viscosity",
                  "Averages at constant phi over samples; one colour per phi_init "
                  f"({', '.join(f'{s:g}' for s in starts)}; the fit uses "
                  f"{representative_phi_init(c):g}), lighter shades and other markers for "
                  f"slower rates; solid symbols N = {sizes[0]}, open symbols larger sizes; error "
                  "bars are standard errors (the paper's Fig. 1). The residual pressure of the "
                  "relaxed start, right after phi_init, is below the vertical range.")


def _relative_errors(ax, e, color, plotted):
    a, z = e.constant_phi, e.constant_z
    ok = np.isfinite(a["pressure_relative_error"]) & (a["pressure_mean"] > 0)
    ax.plot(a["packing_fraction"][ok], a["pressure_relative_error"][ok], "-", color=color,
            label=f"{rate_label(e.log10_rate)}, constant phi")
    plotted.add("relative errors", f"{rate_text(e.log10_rate)}, constant phi",
                a["packing_fraction"][ok],
                a["pressure_relative_error"][ok])
    if z:
        okz = np.isfinite(z["pressure_relative_error"]) & (z["pressure_mean"] > 0)
        ax.plot(z["packing_fraction_mean"][okz], z["pressure_relative_error"][okz], "--",
                color=color, label=f"{rate_label(e.log10_rate)}, constant Z")
        plotted.add("relative errors", f"{rate_text(e.log10_rate)}, constant Z",
                    z["packing_fraction_mean"][okz],
                    z["pressure_relative_error"][okz])


def relative_error_figure(c, out_dir):
    """The supplement's fluctuation figure: relative error of p, constant phi beside constant Z."""
    phi_init = representative_phi_init(c)
    chosen = [e for e in c.ensembles if e.phi_init == phi_init and e.constant_phi]
    if not chosen:
        return None
    largest = max(e.n for e in chosen)
    chosen = [e for e in chosen if e.n == largest]
    colors = rate_colors([e.log10_rate for e in chosen])
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.5))
    plotted = Plotted()
    plotted.panel("relative errors", "packing fraction phi (constant Z: mean phi at that Z)",
                  "relative error of p")
    for e in chosen:
        _relative_errors(ax, e, colors[e.log10_rate], plotted)
    decorate(ax, r"packing fraction $\phi$ (constant Z: mean $\phi$ at that Z)",
             r"relative error $\sigma_p / (p \sqrt{N_s})$", log_y=True)
    file = save(fig, out_dir, "relative_errors.png", plotted)
    return Figure(file, "Relative errors: constant phi against constant Z",
                  f"N = {largest}, phi_init = {phi_init:g}. Averaging at constant Z (dashed) "
                  "removes most of the sample-to-sample scatter that constant-phi averaging "
                  "(solid) carries near jamming (the supplement's fluctuation figure).")


def _jamming_points(ax, c, found, safe, plotted):
    """Left panel: mean phi_Ji of each (size, rate) for every phi_init."""
    colors = rate_colors([e.log10_rate for e in c.ensembles])
    sizes = sorted({e.n for e in c.ensembles})
    groups = sorted({(e.n, e.log10_rate) for e in found}, key=lambda g: (g[0], -g[1]))
    starts = sorted({e.phi_init for e in found})
    width = 0.6 * (min(np.diff(starts)) if len(starts) > 1 else 0.1)
    plotted.panel("jamming points", "phi_init", "mean phi_Ji")
    for k, (n, r) in enumerate(groups):
        mine = sorted([e for e in found if e.n == n and e.log10_rate == r],
                      key=lambda e: e.phi_init)
        shift = width * (k / max(1, len(groups) - 1) - 0.5)
        x = [e.phi_init for e in mine]
        y, dy = [e.jamming["mean"] for e in mine], [e.jamming["error"] for e in mine]
        ax.errorbar(np.add(x, shift), y, yerr=dy, marker="o" if n == sizes[0] else "s",
                    mfc=colors[r] if n == sizes[0] else "none", color=colors[r], ls="none",
                    capsize=3, label=f"N={n}, {rate_label(r)}")
        plotted.add("jamming points", f"N={n}, {rate_text(r)}", x, y, dy)
    paper = c.stats_attrs.get("paper", {})
    if "phi_j" in paper:
        ax.axhline(paper["phi_j"], color="k", ls=":", lw=1,
                   label=f"paper phi_J = {paper['phi_j']:g} (N, 1/rate -> inf)")
    if safe:
        ax.axvline(min(x["largest_consistent_phi_init"] for x in safe), color="tab:red",
                   lw=1, ls="--", label="largest safe phi_init (all sizes and rates)")
    decorate(ax, r"$\phi_{init}$", r"$\langle\phi_{Ji}\rangle$ (error bars: standard error)")


def _safe_starts(ax, c, found, safe, plotted):
    """Right panel: the largest phi_init the phi_init check allows, per size and rate."""
    sizes = sorted({e.n for e in c.ensembles})
    plotted.panel("largest safe phi_init", "log10 rate", "largest consistent phi_init")
    for n in sizes:
        mine = sorted([x for x in safe if x.get("n") == n], key=lambda x: x["log10_rate"])
        if mine:
            x = [v["log10_rate"] for v in mine]
            y = [v["largest_consistent_phi_init"] for v in mine]
            ax.plot(x, y, marker="o" if n == sizes[0] else "s",
                    mfc="none" if n != sizes[0] else None, ls="-", label=f"N={n}")
            plotted.add("largest safe phi_init", f"N={n}", x, y)
    ax.set_yticks(sorted({e.phi_init for e in c.ensembles}))
    decorate(ax, r"$\log_{10}$ rate", "largest phi_init consistent with the lowest")


JAMMING_CAPTIONS = {
    _jamming_points: "mean jamming point of the runs of each (size, rate) for every phi_init, "
                     "shifted sideways for legibility",
    _safe_starts: "per size and rate, the largest phi_init whose pressure curve the phi_init "
                  "check finds consistent with the lowest phi_init's"}


def jamming_figure(c, out_dir):
    """phi_Ji for each phi_init and the largest phi_init the phi_init check allows for each
    size and rate; each panel only when the campaign has its numbers."""
    found = [e for e in c.ensembles if e.jamming and e.jamming.get("found", 0) > 0]
    safe = [v.values for v in c.verdicts
            if v.figure == "jamming_points" and "largest_consistent_phi_init" in v.values]
    panels = [draw for draw, have in ((_jamming_points, found), (_safe_starts, safe)) if have]
    if not panels:
        return None
    fig, axes = plt.subplots(1, len(panels), layout="constrained", squeeze=False,
                             figsize=(6 * len(panels), 4.5))
    plotted = Plotted()
    for ax, draw in zip(axes[0], panels):
        draw(ax, c, found, safe, plotted)
    file = save(fig, out_dir, "jamming_points.png", plotted)
    sides = ["Left: ", "Right: "] if len(panels) == 2 else [""]
    caption = " ".join(f"{side}{JAMMING_CAPTIONS[draw]}." for side, draw in zip(sides, panels))
    if found and safe:
        caption += " Dashed red: the largest phi_init consistent at every size and rate."
    if not found:
        caption += " Jamming points phi_Ji were not sought (campaign key jamming_point = true)."
    return Figure(file, "Jamming points and the largest safe initial packing",
                  caption[:1].upper() + caption[1:])


ALL = [pressure_figure, finite_size_figure, sample_pairs_figure, relative_error_figure,
       jamming_figure, jamming_width_figure, scan_figure, collapse_figure, lammps_figure]
