"""The compare check's figure: another simulator's ensemble over this campaign's, with the
margin band (docs/cross-simulator.md). Only drawing: the reference's mean pressure comes from
stats.h5, the other's from the verdict's curves (Delta p/p = (p_other - p_ref)/p_ref of the
sample means on the reference's grid, with the error the check uses)."""

import re

import matplotlib.patches
import matplotlib.pyplot as plt
import numpy as np

from report_figures_checks import REGIONS, region_bands
from report_plot import Figure, Plotted, panels_with_key, rate_label, rate_text, save

SHORT = {"pass": "pass", "fail": "FAIL", "inconclusive": "inconcl."}
NAMES = re.compile(r": (.+?) vs (.+?), constant")


def _other(v):
    """The compared campaign's name, from the case name ('... : OTHER vs THIS, constant phi')."""
    m = NAMES.search(v.case)
    return m.group(1) if m else "other"


def _reference_pressure(c, v):
    """This campaign's mean p of the verdict's ensemble at its grid (NaN where not averaged)."""
    for e in c.ensembles:
        if (e.n == int(v.values.get("n", -1)) and abs(e.log10_rate - v.values.get("log10_rate", 0))
                < 1e-9 and abs(e.phi_init - v.values.get("phi_init", -1)) < 1e-6):
            a = e.constant_phi
            return np.interp(v.curves["grid"], a["packing_fraction"], a["pressure_mean"],
                             left=np.nan, right=np.nan)
    return None


def _difference_panel(ax, v, plotted, panel):
    """Delta p/p of the same verdict on a linear scale, where the margin band shows."""
    g, d, s = v.curves["grid"], v.curves["delta"], v.curves["sigma"]
    margin = v.margin or 0.05
    keep = np.isfinite(d) & np.isfinite(s)
    g, d, s = g[keep], d[keep], s[keep]
    ax.axhspan(-margin, margin, color="tab:green", alpha=0.2, lw=0)
    ax.axhline(0, color="k", lw=0.5)
    if "range_min" in v.values:
        ax.axvspan(v.values["range_min"], v.values["range_max"], color="tab:blue", alpha=0.07,
                   lw=0)
    every = max(1, len(g) // 40)
    ax.errorbar(g, d, yerr=s, fmt="o", ms=2, color="tab:red", elinewidth=0.5, markevery=every,
                errorevery=every)
    shown = margin * float(np.clip(np.percentile(np.abs(d) + s, 90) / margin * 1.15, 2, 6)) \
        if len(d) else 2 * margin
    ax.set_ylim(-shown, shown)
    ax.grid(alpha=0.3)
    plotted.add(panel, f"{_other(v)}, {rate_text(v.values.get('log10_rate', 0))}", g, d, s)


def _panel(ax, c, v, plotted, panel):
    g, d, s = v.curves["grid"], v.curves["delta"], v.curves["sigma"]
    p_ref = _reference_pressure(c, v)
    if p_ref is None:
        ax.set_visible(False)
        return
    margin = v.margin or 0.05
    keep = np.isfinite(p_ref) & (p_ref > 0) & np.isfinite(d)
    g, d, s, p_ref = g[keep], d[keep], s[keep], p_ref[keep]
    ax.fill_between(g, p_ref * (1 - margin), p_ref * (1 + margin), color="tab:green", alpha=0.2,
                    lw=0)
    ax.plot(g, p_ref, color="k", lw=0.9)
    every = max(1, len(g) // 40)
    ax.errorbar(g, p_ref * (1 + d), yerr=p_ref * s, fmt="o", ms=2.5, color="tab:red",
                elinewidth=0.5, markevery=every, errorevery=every)
    if "range_min" in v.values:
        ax.axvspan(v.values["range_min"], v.values["range_max"], color="tab:blue", alpha=0.07,
                   lw=0)
    ax.set_yscale("log")
    ax.set_title(f"{_other(v)}, {rate_label(v.values.get('log10_rate', 0))}: "
                 f"{SHORT.get(v.status, v.status)}", fontsize=8)
    ax.grid(alpha=0.3)
    series = f"{_other(v)}, N={int(v.values.get('n', 0))}, {rate_text(v.values.get('log10_rate', 0))}"
    plotted.add(panel, series + ", reference", g, p_ref)
    plotted.add(panel, series + ", other", g, p_ref * (1 + d), p_ref * s)


def compare_figure(c, out_dir):
    """Two rows per compared campaign, one column per rate: the reference's mean p (black) with
    its margin band and the other's (red) on the same grid, then their relative difference."""
    # The pooled verdicts carry the curves (a region verdict's are a cut of them).
    at_phi = [v for v in c.verdicts if v.figure == "compare"
              and v.values.get("constant_z", 0.0) == 0.0]
    found = [v for v in at_phi if "delta" in v.curves and v.region not in REGIONS]
    regions = [v for v in at_phi if v.region in REGIONS]
    if not found:
        return None
    others = sorted({_other(v) for v in found})
    rates = sorted({v.values.get("log10_rate", 0.0) for v in found}, reverse=True)
    fig, axes, key = panels_with_key(2 * len(others), len(rates), (3.2, 2.1), key_width=2.2)
    plotted = Plotted()
    panel, difference = "pressure of both ensembles at constant phi", "Delta p/p at constant phi"
    plotted.panel(panel, "packing fraction phi", "p (k_e/d_s^D)")
    plotted.panel(difference, "packing fraction phi", "(p_other - p_reference)/p_reference")
    for r, other in enumerate(others):
        for k, rate in enumerate(rates):
            here = [v for v in found if _other(v) == other and v.values.get("log10_rate") == rate]
            if here:
                _panel(axes[2 * r, k], c, here[0], plotted, panel)
                _difference_panel(axes[2 * r + 1, k], here[0], plotted, difference)
                region_bands(axes[2 * r + 1, k],
                         [v for v in regions if _other(v) == other
                          and v.values.get("log10_rate") == rate])
            else:
                axes[2 * r, k].set_visible(False)
                axes[2 * r + 1, k].set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(r"packing fraction $\phi$")
    for r in range(len(others)):
        axes[2 * r, 0].set_ylabel(r"$p$")
        axes[2 * r + 1, 0].set_ylabel(r"$\Delta p/p$")
    margin = found[0].margin or 0.05
    handles = [plt.Line2D([], [], color="k", lw=0.9, label=f"{c.name} (reference)"),
               plt.Line2D([], [], color="tab:red", marker="o", ms=3, lw=0,
                          label="compared ensemble"),
               matplotlib.patches.Patch(color="tab:green", alpha=0.3,
                                        label=f"margin +-{100 * margin:g}%"),
               matplotlib.patches.Patch(color="tab:blue", alpha=0.15, label="range judged")]
    key.legend(handles=handles, loc="center left", fontsize=8, borderaxespad=0)
    file = save(fig, out_dir, "compare.png", plotted)
    return Figure(file, "Other simulators against this campaign",
                  "Mean pressure at constant phi of each ensemble compared with this campaign "
                  "(jam check compare; campaign key compare_with), two rows per compared "
                  "campaign, one column per rate: this campaign's mean (black) with the margin "
                  "band, the other's (red, with the error the check uses) on this campaign's "
                  "grid; below each, their relative difference with the margin band (green) "
                  "and errors; blue: the range the pooled verdict judges; the bands along the "
                  "top: the regions below (be), at and above (ab) jamming judged on their own, "
                  "green pass, red FAIL, grey inconclusive; each title gives the pooled "
                  "verdict at constant phi (constant Z: the verdict table). Differences are "
                  "shown within 2 to 6 margins; points beyond are in the CSV.")
