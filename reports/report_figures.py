"""The report's figures, one function each, drawn with matplotlib from a loaded Campaign.

Each function writes one figure into the output directory (PNG, SVG and the CSV of its plotted
numbers, one stem: report_plot.save) and returns a Figure record (file name, title, caption),
or None when the campaign has nothing to draw for it; a panel with nothing to draw is left out
of its figure. Only drawing happens here: every number comes from stats.h5 or checks.h5.
This file: the relative errors and the jamming points; the pressure figures are in
report_figures_pressure.py, the checks' in report_figures_checks.py, the fit's in
report_figures_fit.py; ALL lists them in page order.
"""

import matplotlib.pyplot as plt
import numpy as np

from report_figures_checks import (finite_size_figure, finite_size_z_figure, lammps_figure,
                                   sample_pairs_figure)
from report_figures_compare import compare_figure
from report_figures_fit import collapse_figure, scan_figure
from report_figures_jamming import jamming_width_figure
from report_figures_pressure import pressure_figure, rate_figure
from report_plot import (Figure, Plotted, decorate, panels_with_key, rate_colors, rate_label,
                         rate_text, representative_phi_init, save)


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


def _jamming_points(ax, n, found, starts, plotted):
    """One size: mean phi_Ji against the rate, a colour per phi_init."""
    colors = plt.get_cmap("tab10")
    for k, phi_init in enumerate(starts):
        mine = sorted([e for e in found if e.n == n and e.phi_init == phi_init],
                      key=lambda e: e.log10_rate)
        if not mine:
            continue
        x = [e.log10_rate for e in mine]
        y, dy = [e.jamming["mean"] for e in mine], [e.jamming["error"] for e in mine]
        ax.errorbar(x, y, yerr=dy, marker="o", ms=4, capsize=3, lw=0.8, color=colors(k % 10),
                    label=f"phi_init {phi_init:g}")
        plotted.add("jamming points", f"N={n}, phi_init {phi_init:g}", x, y, dy)
    ax.set_title(f"N = {n}", fontsize=10)
    ax.set_xlabel(r"$\log_{10}$ rate")
    ax.grid(alpha=0.3)


def _safe_starts(ax, c, safe, plotted):
    """The largest phi_init the phi_init check allows, per size and rate."""
    sizes = sorted({e.n for e in c.ensembles})
    plotted.panel("largest safe phi_init", "log10 rate", "largest consistent phi_init")
    for k, n in enumerate(sizes):
        mine = sorted([x for x in safe if x.get("n") == n], key=lambda x: x["log10_rate"])
        if mine:
            x = [v["log10_rate"] for v in mine]
            y = [v["largest_consistent_phi_init"] for v in mine]
            ax.plot(x, y, marker=MARKERS[k % len(MARKERS)], mfc="none", ls="-", color="k",
                    lw=0.8, label=f"largest safe phi_init, N={n}")
            plotted.add("largest safe phi_init", f"N={n}", x, y)
    ax.set_yticks(sorted({e.phi_init for e in c.ensembles}))
    ax.set_title("largest phi_init consistent with the lowest", fontsize=9)
    ax.set_xlabel(r"$\log_{10}$ rate")
    ax.grid(alpha=0.3)


MARKERS = ["o", "s", "^", "D", "v"]


def jamming_figure(c, out_dir):
    """phi_Ji against the rate, one panel per size and a colour per phi_init, and the largest
    phi_init the phi_init check allows per size and rate; each only when the campaign has its
    numbers."""
    found = [e for e in c.ensembles if e.jamming and e.jamming.get("found", 0) > 0]
    safe = [v.values for v in c.verdicts
            if v.figure == "jamming_points" and "largest_consistent_phi_init" in v.values]
    sizes = sorted({e.n for e in found})
    panels = len(sizes) + (1 if safe else 0)
    if not panels:
        return None
    fig, axes, key = panels_with_key(1, panels, (3.3, 3.6), key_width=2.2)
    plotted = Plotted()
    plotted.panel("jamming points", "log10 rate", "mean phi_Ji")
    starts = sorted({e.phi_init for e in found})
    for k, n in enumerate(sizes):
        _jamming_points(axes[0, k], n, found, starts, plotted)
        if k:
            axes[0, k].sharey(axes[0, 0])
    if sizes:
        axes[0, 0].set_ylabel(r"$\langle\phi_{Ji}\rangle$ (standard errors)")
        paper = c.stats_attrs.get("paper", {})
        for ax in axes[0, :len(sizes)]:
            if "phi_j" in paper:
                ax.axhline(paper["phi_j"], color="k", ls=":", lw=1,
                           label=f"paper phi_J = {paper['phi_j']:g} (N, 1/rate -> inf)")
        if "phi_j" in paper:  # the line in view (axhline leaves the range as it is)
            low, high = axes[0, 0].get_ylim()
            room = 0.05 * (high - low)
            axes[0, 0].set_ylim(min(low, paper["phi_j"] - room), max(high, paper["phi_j"] + room))
    if safe:
        _safe_starts(axes[0, -1], c, safe, plotted)
    handles, labels = [], []
    for ax in axes[0]:
        for h, text in zip(*ax.get_legend_handles_labels()):
            if text not in labels:
                handles.append(h)
                labels.append(text)
    key.legend(handles, labels, loc="center left", fontsize=8, borderaxespad=0)
    file = save(fig, out_dir, "jamming_points.png", plotted)
    caption = ("Mean jamming point phi_Ji of the runs of each size, rate and phi_init, with "
               "standard errors; a start that leaves a memory shows as a colour apart from "
               "the lowest phi_init's." if sizes else
               "Jamming points phi_Ji were not sought (campaign key jamming_point = true).")
    if safe:
        caption += (" Right: per size and rate, the largest phi_init whose pressure the phi_init "
                    "check finds consistent with the lowest phi_init's.")
    return Figure(file, "Jamming points and the largest safe initial packing", caption)


# Page order: the paper's figures first (Fig. 1, the size comparison, the rate dependence, the
# collapse of Fig. 3 and the scan of Fig. 2), then the supplement's and the cross-check.
ALL = [pressure_figure, finite_size_figure, rate_figure, collapse_figure, scan_figure,
       finite_size_z_figure, relative_error_figure, jamming_figure, jamming_width_figure,
       sample_pairs_figure, lammps_figure, compare_figure]


def page_order(c):
    """ALL, except that a campaign other simulators are compared with (compare verdicts: its
    campaign file's compare_with) shows that comparison first: it is what it was run for."""
    if any(v.figure == "compare" for v in c.verdicts):
        return [compare_figure] + [f for f in ALL if f is not compare_figure]
    return ALL
