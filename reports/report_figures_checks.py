"""The figures of the checks' curves (checks.h5): finite size, sample pairs, LAMMPS."""

import matplotlib.pyplot as plt
import numpy as np

from report_plot import (Figure, Plotted, decorate, label, rate_colors, rate_label, rate_text,
                         save)


def _offset_step(curves):
    """A vertical offset between rates that keeps the curves apart (robust to outliers)."""
    spans = [np.nanpercentile((np.abs(d) + s)[len(d) // 20:], 90) for d, s in curves if len(d)]
    return float(np.clip(2.2 * max(spans, default=0.1), 0.02, 2.0))


def _finite_size_panels(found):
    """(phi_init, at_z, verdicts) for each panel that has verdicts: rows of phi_init, constant
    phi beside constant Z."""
    panels = []
    for phi_init in sorted({v.values.get("phi_init", 0.0) for v in found}):
        for at_z in (0.0, 1.0):
            mine = [v for v in found if v.values.get("phi_init", 0.0) == phi_init
                    and v.values.get("constant_z", 0.0) == at_z]
            if mine:
                mine.sort(key=lambda v: -v.values.get("log10_rate", 0.0))
                panels.append((phi_init, at_z, mine))
    return panels


def _finite_size_panel(ax, phi_init, at_z, mine, colors, plotted):
    step = _offset_step([(v.curves["delta"], v.curves["sigma"]) for v in mine])
    n_a, n_b = int(mine[0].values.get("n_a", 0)), int(mine[0].values.get("n_b", 0))
    panel = (f"N={n_a} vs N={n_b}, phi_init {phi_init:g}, constant "
             f"{'Z' if at_z else 'phi'}")
    plotted.panel(panel, "contacts per particle Z" if at_z else "packing fraction phi",
                  "Delta p/p + offset")
    for k, v in enumerate(mine):
        r = v.values.get("log10_rate", 0.0)
        offset = k * step
        label = f"{rate_label(r)} (+{offset:.2g}), {v.status}"
        ax.axhline(offset, color=colors[r], lw=0.6, ls="--")
        ax.errorbar(v.curves["grid"], v.curves["delta"] + offset, yerr=v.curves["sigma"],
                    marker="o", ms=2.5, lw=0.8, color=colors[r], label=label)
        plotted.add(panel, f"{rate_text(r)} (offset +{offset:.2g}), {v.status}",
                    v.curves["grid"], v.curves["delta"] + offset, v.curves["sigma"])
    ax.set_title(panel, fontsize=9)
    decorate(ax, "contacts per particle $Z$" if at_z else r"packing fraction $\phi$",
             r"$\Delta p/p$ + offset")


def finite_size_figure(c, out_dir):
    """The supplement's relE-p figures: Delta p/p between sizes against phi and Z per rate."""
    found = [v for v in c.verdicts if v.figure == "finite_size" and "delta" in v.curves]
    if not found:
        return None
    panels = _finite_size_panels(found)
    columns = 2 if len(panels) > 1 else 1
    rows = (len(panels) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, layout="constrained", squeeze=False,
                             figsize=(5.5 * columns, 3.6 * rows))
    colors = rate_colors([v.values.get("log10_rate", 0.0) for v in found])
    plotted = Plotted()
    for ax, (phi_init, at_z, mine) in zip(axes.ravel(), panels):
        _finite_size_panel(ax, phi_init, at_z, mine, colors, plotted)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    file = save(fig, out_dir, "finite_size.png", plotted)
    return Figure(file, "Finite size: Delta p/p between the two sizes",
                  "Delta p/p = 2(p_a - p_b)/(p_a + p_b) of the sample means, against phi "
                  "and against Z (each panel's title says which), each rate offset vertically "
                  "(dashed line: its zero); error bars are the errors the finite-size check uses.")


def sample_pairs_figure(c, out_dir):
    """Delta p/p of single pairs of samples (sample i of one size against sample i of the other)."""
    found = [v for v in c.verdicts if v.figure == "sample_pairs" and "grid" in v.curves]
    if not found:
        return None
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.5))
    colors = rate_colors([v.values.get("log10_rate", 0.0) for v in found])
    found.sort(key=lambda v: (v.values.get("phi_init", 0.0), -v.values.get("log10_rate", 0.0)))
    pairs = [[(k, v.curves[k]) for k in v.curves if k.startswith("pair_")] for v in found]
    step = _offset_step([(p, np.zeros_like(p)) for ps in pairs for _, p in ps])
    plotted = Plotted()
    plotted.panel("sample pairs", "packing fraction phi", "Delta p/p of the pair + offset")
    for k, (v, ps) in enumerate(zip(found, pairs)):
        r = v.values.get("log10_rate", 0.0)
        offset = k * step
        series = (f"phi_init {v.values.get('phi_init', 0):g}, {{}} (+{offset:.2g}), "
                  f"{v.status}")
        ax.axhline(offset, color="k", lw=0.5, ls="--")
        for j, (name, p) in enumerate(ps):
            ax.plot(v.curves["grid"], p + offset, lw=0.7, color=colors[r], alpha=0.7,
                    label=series.format(rate_label(r)) if j == 0 else None)
            plotted.add("sample pairs", f"{series.format(rate_text(r))}, {name}",
                        v.curves["grid"], p + offset)
    decorate(ax, r"packing fraction $\phi$", r"$\Delta p/p$ of sample pairs + offset")
    file = save(fig, out_dir, "sample_pairs.png", plotted)
    return Figure(file, "Sample pairs",
                  "Each line is one pair (sample i of the smaller size against sample i of the "
                  "larger), offset per (phi_init, rate); the sample_pairs check compares their "
                  "spread with the within-size fluctuations.")


def _lammps_panels(top, bottom, v, plotted):
    g = v.curves["grid"]
    top.plot(g, v.curves["pressure_jam"], "o", ms=4, mfc="none", label="jam (overdamped)")
    top.plot(g, v.curves["pressure_lammps"], "-", lw=1, label="LAMMPS (inertial, small Q)")
    plotted.panel(v.case + ": pressure", "packing fraction phi", "pressure (mean over samples)")
    plotted.add(v.case + ": pressure", "jam (overdamped)", g, v.curves["pressure_jam"])
    plotted.add(v.case + ": pressure", "LAMMPS (inertial, small Q)", g,
                v.curves["pressure_lammps"])
    top.set_yscale("log")
    top.set_ylabel("pressure (mean over samples)")
    top.set_title(label(v.case), fontsize=9)
    top.legend(fontsize=7)
    top.grid(alpha=0.3, which="both")
    bottom.errorbar(g, 100 * v.curves["delta"], yerr=100 * v.curves["sigma"], marker="o",
                    ms=3, ls="none", capsize=2)
    plotted.panel(v.case + ": difference", "packing fraction phi", "Delta p/p (%)")
    plotted.add(v.case + ": difference", "mean Delta p/p", g, 100 * v.curves["delta"],
                100 * v.curves["sigma"])
    bottom.axhline(0, color="k", lw=0.5)
    for s in (-0.5, 0.5):
        bottom.axhline(s, color="tab:red", lw=0.8, ls="--")
    bottom.set_ylabel(r"$\Delta p/p$ (%)")
    bottom.set_xlabel(r"packing fraction $\phi$")
    bottom.grid(alpha=0.3)


def lammps_figure(c, out_dir):
    """jam against LAMMPS through jamming: pressure overlay and residuals per dimension."""
    found = [v for v in c.verdicts if v.figure == "lammps" and "pressure_lammps" in v.curves]
    if not found:
        return None
    fig, axes = plt.subplots(2, len(found), layout="constrained", figsize=(5.5 * len(found), 6),
                             squeeze=False, sharex="col", gridspec_kw={"height_ratios": [2, 1]})
    plotted = Plotted()
    for k, v in enumerate(found):
        _lammps_panels(axes[0][k], axes[1][k], v, plotted)
    file = save(fig, out_dir, "lammps.png", plotted)
    return Figure(file, "Cross-check against LAMMPS",
                  "The same relaxed starts compressed by jam (overdamped) and by LAMMPS "
                  "(inertial at small Q); top: sample-mean pressure, bottom: mean Delta p/p with "
                  "its standard error; dashed red: the 0.5% systematic difference the check allows "
                  "(plus 3 errors).")
