"""The figures of the checks' curves (checks.h5): finite size, sample pairs, LAMMPS."""

import matplotlib.patches
import matplotlib.pyplot as plt
import numpy as np

from report_plot import Figure, Plotted, label, panels_with_key, rate_label, rate_text, save


# A panel's title gives each phi_init's verdict, shortened to fit.
SHORT = {"pass": "pass", "fail": "FAIL", "inconclusive": "inconcl."}
# Each panel's vertical range, in margins: at least +-2 (the band and some room), at most +-6
# (so that a difference of one margin still takes a sixth of the axis); points beyond the
# range are left in the CSV and said so in the caption.
MARGINS_SHOWN = (2.0, 6.0)


def _series(v):
    """What tells curves of one rate panel apart: the pair of sizes and phi_init."""
    n_a, n_b = int(v.values.get("n_a", 0)), int(v.values.get("n_b", 0))
    return f"N={n_a} vs {n_b}, phi_init {v.values.get('phi_init', 0.0):g}"


def _y_range(mine, margin):
    """+-(2..6) margins, wide enough for the curves inside the judged range."""
    spans = []
    for v in mine:
        g, d, s = v.curves["grid"], v.curves["delta"], v.curves["sigma"]
        inside = (g >= v.values.get("range_min", -np.inf)) & (g <= v.values.get("range_max", np.inf))
        inside &= np.isfinite(d) & np.isfinite(s)
        if inside.any():
            spans.append(np.percentile(np.abs(d[inside]) + s[inside], 90))
    lo, hi = MARGINS_SHOWN
    return margin * float(np.clip(max(spans, default=0) / margin * 1.15, lo, hi))


# The regions around jamming (checks/regions.hpp), shaded by their verdict.
REGION_COLOR = {"pass": "tab:green", "fail": "tab:red", "inconclusive": "0.6"}
REGIONS = ("below", "at", "above")


def region_bands(ax, regions):
    """Each region verdict as a band over the range it judged, labelled with its outcome."""
    for v in regions:
        lo, hi = v.values.get("range_min"), v.values.get("range_max")
        if lo is None or hi is None:
            continue
        ax.axvspan(lo, hi, ymin=0.9, ymax=1.0, color=REGION_COLOR.get(v.status, "0.6"),
                   alpha=0.6, lw=0)
        ax.text((lo + hi) / 2, 0.95, f"{v.region[:2]} {SHORT.get(v.status, v.status)}",
                transform=ax.get_xaxis_transform(), ha="center", va="center", fontsize=5)


def _finite_size_panel(ax, rate, mine, colors, plotted, panel_name, regions=()):
    margin = mine[0].margin or 0.1
    ax.axhspan(-margin, margin, color="tab:green", alpha=0.12, lw=0)
    ax.axhline(0, color="k", lw=0.5)
    judged = [v for v in mine if "range_min" in v.values]
    if judged:
        ax.axvspan(min(v.values["range_min"] for v in judged),
                   max(v.values["range_max"] for v in judged), color="tab:blue", alpha=0.07, lw=0)
    for v in mine:
        name = _series(v)
        g, d, s = v.curves["grid"], v.curves["delta"], v.curves["sigma"]
        ax.errorbar(g, d, yerr=s, marker="o", ms=2, lw=0.8, elinewidth=0.5, color=colors[name],
                    errorevery=max(1, len(g) // 40), markevery=max(1, len(g) // 40))
        plotted.add(panel_name, f"{rate_text(rate)}, {name}, {v.status}", g, d, s)
    shown = _y_range(mine, margin)
    ax.set_ylim(-shown, shown)
    region_bands(ax, regions)
    words = ", ".join(f"{v.values.get('phi_init', 0):g} {SHORT.get(v.status, v.status)}"
                      for v in mine)
    failed = sorted({v.region for v in regions if v.status == "fail"}, key=REGIONS.index)
    if failed:
        words += "; FAIL " + ", ".join(failed)
    ax.set_title(f"{rate_label(rate)}: {words}", fontsize=8)
    ax.grid(alpha=0.3)


def _finite_size_grid(c, found, at_z, out_dir):
    """One panel per rate, Delta p/p of every pair and phi_init on one scale, no offsets."""
    # The pooled verdicts carry the curves; the region verdicts (their cuts) are drawn as bands.
    every = [v for v in found if v.values.get("constant_z", 0.0) == at_z]
    mine = [v for v in every if v.region not in REGIONS]
    regions = [v for v in every if v.region in REGIONS]
    if not mine:
        return None
    rates = sorted({v.values.get("log10_rate", 0.0) for v in mine}, reverse=True)
    names = sorted({_series(v) for v in mine})
    palette = plt.get_cmap("tab10")
    colors = {name: palette(k % 10) for k, name in enumerate(names)}
    columns = min(len(rates), 5)
    rows = (len(rates) + columns - 1) // columns
    fig, axes, key = panels_with_key(rows, columns, (2.9, 2.5), key_width=2.2)
    plotted = Plotted()
    x_name = "contacts per particle Z" if at_z else "packing fraction phi"
    panel_name = "Delta p/p at constant " + ("Z" if at_z else "phi")
    plotted.panel(panel_name, x_name, "Delta p/p (fraction)")
    for ax, rate in zip(axes.ravel(), rates):
        here = [v for v in mine if v.values.get("log10_rate", 0.0) == rate]
        _finite_size_panel(ax, rate, here, colors, plotted, panel_name,
                           [v for v in regions if v.values.get("log10_rate", 0.0) == rate])
    for ax in axes.ravel()[len(rates):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("contacts per particle $Z$" if at_z else r"packing fraction $\phi$")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\Delta p/p$")
    handles = [plt.Line2D([], [], color=colors[n], marker="o", ms=3, lw=0.8, label=n)
               for n in names]
    handles += [matplotlib.patches.Patch(color="tab:green", alpha=0.25,
                                         label=f"margin +-{100 * (mine[0].margin or 0.1):g}%"),
                matplotlib.patches.Patch(color="tab:blue", alpha=0.15, label="range judged")]
    key.legend(handles=handles, loc="center left", fontsize=8, borderaxespad=0)
    stem = "finite_size_z" if at_z else "finite_size"
    file = save(fig, out_dir, stem + ".png", plotted)
    what = "Z" if at_z else "phi"
    return Figure(file, f"Finite size: Delta p/p at constant {what}",
                  "Delta p/p = 2(p_a - p_b)/(p_a + p_b) of the sample means against "
                  + ("Z" if at_z else "phi") + ", one panel per rate, all on one scale without "
                  "offsets; error bars: the errors the finite-size check uses; green band: the "
                  "margin; blue: the range the pooled verdict judges; the bands along the top: "
                  "the regions below (be), at and above (ab) jamming, each judged on its own, "
                  "green pass, red FAIL, grey inconclusive; each panel's title gives each "
                  "phi_init's pooled verdict (phi_init, then pass, FAIL or inconcl.) and the "
                  "regions that failed. Vertical range 2 to 6 margins: points beyond it "
                  "(far from phi_J, where p is small and Delta p/p noisy) are in the CSV.")


def finite_size_figure(c, out_dir):
    """The supplement's relE-p figures at constant phi, as small multiples per rate."""
    found = [v for v in c.verdicts if v.figure == "finite_size" and "delta" in v.curves]
    return _finite_size_grid(c, found, 0.0, out_dir) if found else None


def finite_size_z_figure(c, out_dir):
    """The same at constant Z."""
    found = [v for v in c.verdicts if v.figure == "finite_size" and "delta" in v.curves]
    return _finite_size_grid(c, found, 1.0, out_dir) if found else None


def _pairs_panel(ax, rate, mine, colors, plotted):
    margin = mine[0].margin or 0.1
    ax.axhspan(-margin, margin, color="tab:green", alpha=0.12, lw=0)
    ax.axhline(0, color="k", lw=0.5)
    spans = []
    for v in mine:
        start = f"phi_init {v.values.get('phi_init', 0):g}"
        for name in sorted(k for k in v.curves if k.startswith("pair_")):
            p = v.curves[name]
            ax.plot(v.curves["grid"], p, lw=0.6, alpha=0.6, color=colors[start])
            plotted.add("sample pairs", f"{rate_text(rate)}, {start}, {name}, {v.status}",
                        v.curves["grid"], p)
            spans.append(np.nanpercentile(np.abs(p), 90) if np.isfinite(p).any() else 0)
    lo, hi = MARGINS_SHOWN
    shown = margin * float(np.clip(max(spans, default=0) / margin * 1.15, lo, hi))
    ax.set_ylim(-shown, shown)
    words = ", ".join(f"{v.values.get('phi_init', 0):g} {SHORT.get(v.status, v.status)}"
                      for v in mine)
    ax.set_title(f"{rate_label(rate)}: {words}", fontsize=8)
    ax.grid(alpha=0.3)


def sample_pairs_figure(c, out_dir):
    """Delta p/p of single pairs of samples (sample i of one size against sample i of the
    other), one panel per rate on one scale, a colour per phi_init, no offsets."""
    found = [v for v in c.verdicts if v.figure == "sample_pairs" and "grid" in v.curves
             and v.region not in REGIONS]  # a region's pairs are a cut of the pooled ones
    if not found:
        return None
    rates = sorted({v.values.get("log10_rate", 0.0) for v in found}, reverse=True)
    starts = sorted({v.values.get("phi_init", 0.0) for v in found})
    palette = plt.get_cmap("tab10")
    colors = {f"phi_init {s:g}": palette(k % 10) for k, s in enumerate(starts)}
    columns = min(len(rates), 5)
    rows = (len(rates) + columns - 1) // columns
    fig, axes, key = panels_with_key(rows, columns, (2.9, 2.4), key_width=2.0)
    plotted = Plotted()
    plotted.panel("sample pairs", "packing fraction phi", "Delta p/p of the pair (fraction)")
    for ax, rate in zip(axes.ravel(), rates):
        _pairs_panel(ax, rate, [v for v in found if v.values.get("log10_rate", 0.0) == rate],
                     colors, plotted)
    for ax in axes.ravel()[len(rates):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(r"packing fraction $\phi$")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\Delta p/p$ of a pair")
    handles = [plt.Line2D([], [], color=colors[n], lw=1, label=n) for n in colors]
    handles.append(matplotlib.patches.Patch(color="tab:green", alpha=0.25,
                                            label=f"margin +-{100 * (found[0].margin or 0.1):g}%"))
    key.legend(handles=handles, loc="center left", fontsize=8, borderaxespad=0)
    file = save(fig, out_dir, "sample_pairs.png", plotted)
    return Figure(file, "Sample pairs",
                  "Each line is one pair (sample i of the smaller size against sample i of the "
                  "larger), one panel per rate on one scale, without offsets; the sample_pairs "
                  "check compares their spread with the within-size fluctuations; each panel's "
                  "title gives each phi_init's verdict. Vertical range 2 to 6 margins.")


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
