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
from report_figures_fit import collapse_figure, scan_figure
from report_figures_jamming import jamming_width_figure
from report_figures_pressure import pressure_figure, rate_figure
from report_plot import (Figure, Plotted, decorate, rate_colors, rate_label, rate_text,
                         representative_phi_init, save)


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


# Page order: the paper's figures first (Fig. 1, the size comparison, the rate dependence, the
# collapse of Fig. 3 and the scan of Fig. 2), then the supplement's and the cross-check.
ALL = [pressure_figure, finite_size_figure, rate_figure, collapse_figure, scan_figure,
       finite_size_z_figure, relative_error_figure, jamming_figure, jamming_width_figure,
       sample_pairs_figure, lammps_figure]
