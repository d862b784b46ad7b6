"""The report's figures, one function each, drawn with matplotlib from a loaded Campaign.

Each function writes one PNG into the output directory and returns a Figure record (file name,
title, caption), or None when the campaign has nothing to draw for it. Only drawing happens
here: every number comes from stats.h5 or checks.h5.
"""

import os
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 110


@dataclass
class Figure:
    file: str
    title: str
    caption: str


def _rate_colors(log10_rates):
    rates = sorted(set(log10_rates), reverse=True)
    cmap = plt.get_cmap("viridis")
    return {r: cmap(0.85 * k / max(1, len(rates) - 1)) for k, r in enumerate(rates)}


def _rate_label(log10_rate):
    return f"rate $10^{{{log10_rate:g}}}$"


def _decorate(ax, xlabel, ylabel, log_y=False):
    """Axis labels, legend and grid, the same on every single-panel figure."""
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both" if log_y else "major")


def _save(fig, out_dir, file):
    path = os.path.join(out_dir, file)
    try:
        fig.savefig(path, dpi=DPI)
    except OSError as e:  # a full disk fails on close, where the error names no file
        if e.filename is None:
            e.filename = path
        raise
    finally:
        plt.close(fig)
    return file


def representative_phi_init(c):
    """The phi_init the fit used (stats.h5 fit/phi_init), else the lowest one."""
    if c.fit and "phi_init" in c.fit["attrs"]:
        return float(c.fit["attrs"]["phi_init"])
    return min(e.phi_init for e in c.ensembles)


def pressure_figure(c, out_dir):
    """The paper's Fig. 1: pressure and bulk viscosity against phi, every rate, every size."""
    phi_init = representative_phi_init(c)
    chosen = [e for e in c.ensembles if e.phi_init == phi_init and e.constant_phi]
    if not chosen:
        return None
    sizes = sorted({e.n for e in chosen})
    colors = _rate_colors([e.log10_rate for e in chosen])
    fig, axes = plt.subplots(1, 2, layout="constrained", figsize=(11, 4.2))
    lowest = []
    for e in chosen:
        a = e.constant_phi
        phi, p, dp = a["packing_fraction"], a["pressure_mean"], a["pressure_error"]
        keep = p > 0
        lowest.append(np.percentile(p[keep], 5) / e.compression_rate if keep.any() else np.inf)
        solid = e.n == sizes[0]
        style = dict(marker="o", ms=4, lw=0.8, capsize=0, color=colors[e.log10_rate],
                     markevery=max(1, int(keep.sum()) // 30), errorevery=max(1, len(p) // 30),
                     mfc=colors[e.log10_rate] if solid else "none",
                     label=f"N={e.n}, {_rate_label(e.log10_rate)}")
        axes[0].errorbar(phi[keep], p[keep], yerr=dp[keep], **style)
        rate = e.compression_rate
        axes[1].errorbar(phi[keep], p[keep] / rate, yerr=dp[keep] / rate, **style)
    # The first points after the start carry the relaxed start's residual pressure, orders of
    # magnitude below the compression's: the vertical range starts near the compression's.
    floor = 0.3 * min(lowest)
    axes[1].set_ylim(bottom=floor)
    axes[0].set_ylim(bottom=floor * min(e.compression_rate for e in chosen))
    for ax, label in zip(axes, ["pressure $p$", r"bulk viscosity $\eta_p = p/\dot\epsilon$"]):
        ax.set_yscale("log")
        ax.set_xlabel(r"packing fraction $\phi$")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[1].legend(fontsize=7, ncol=1 + len(sizes) // 2, loc="lower right")
    file = _save(fig, out_dir, "pressure.png")
    return Figure(file, "Pressure and bulk viscosity",
                  f"Averages at constant phi over samples, phi_init = {phi_init:g}; solid symbols "
                  f"N = {sizes[0]}, open symbols larger sizes; error bars are standard errors "
                  "(the paper's Fig. 1). The residual pressure of the relaxed start, right after "
                  "phi_init, is below the vertical range.")


def _offset_step(curves):
    """A vertical offset between rates that keeps the curves apart (robust to outliers)."""
    spans = [np.nanpercentile((np.abs(d) + s)[len(d) // 20:], 90) for d, s in curves if len(d)]
    return float(np.clip(2.2 * max(spans, default=0.1), 0.02, 2.0))


def finite_size_figure(c, out_dir):
    """The supplement's relE-p figures: Delta p/p between sizes against phi and Z per rate."""
    found = [v for v in c.verdicts if v.check == "finite_size" and "delta" in v.curves]
    if not found:
        return None
    starts = sorted({v.values.get("phi_init", 0.0) for v in found})
    fig, axes = plt.subplots(len(starts), 2, layout="constrained", figsize=(11, 3.6 * len(starts)), squeeze=False)
    colors = _rate_colors([v.values.get("log10_rate", 0.0) for v in found])
    for row, phi_init in enumerate(starts):
        for col, at_z in enumerate([0.0, 1.0]):
            ax = axes[row][col]
            mine = [v for v in found if v.values.get("phi_init", 0.0) == phi_init
                    and v.values.get("constant_z", 0.0) == at_z]
            mine.sort(key=lambda v: -v.values.get("log10_rate", 0.0))
            step = _offset_step([(v.curves["delta"], v.curves["sigma"]) for v in mine])
            for k, v in enumerate(mine):
                r = v.values.get("log10_rate", 0.0)
                offset = k * step
                ax.axhline(offset, color=colors[r], lw=0.6, ls="--")
                ax.errorbar(v.curves["grid"], v.curves["delta"] + offset, yerr=v.curves["sigma"],
                            marker="o", ms=2.5, lw=0.8, color=colors[r],
                            label=f"{_rate_label(r)} (+{offset:.2g}), {v.status}")
            ax.set_xlabel("contacts per particle $Z$" if at_z else r"packing fraction $\phi$")
            ax.set_ylabel(r"$\Delta p/p$ + offset")
            if mine:
                n_a, n_b = int(mine[0].values.get("n_a", 0)), int(mine[0].values.get("n_b", 0))
                ax.set_title(f"N={n_a} vs N={n_b}, phi_init {phi_init:g}, constant "
                             f"{'Z' if at_z else 'phi'}", fontsize=9)
            ax.legend(fontsize=7)
            ax.grid(alpha=0.3)
    file = _save(fig, out_dir, "finite_size.png")
    return Figure(file, "Finite size: Delta p/p between the two sizes",
                  "Delta p/p = 2(p_a - p_b)/(p_a + p_b) of the sample means, against phi (left) "
                  "and Z (right), each rate offset vertically (dashed line: its zero); error bars "
                  "are the errors the finite-size check uses.")


def sample_pairs_figure(c, out_dir):
    """Delta p/p of single pairs of samples (sample i of one size against sample i of the other)."""
    found = [v for v in c.verdicts if v.check == "sample_pairs" and "grid" in v.curves]
    if not found:
        return None
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.5))
    colors = _rate_colors([v.values.get("log10_rate", 0.0) for v in found])
    found.sort(key=lambda v: (v.values.get("phi_init", 0.0), -v.values.get("log10_rate", 0.0)))
    pairs = [[v.curves[k] for k in v.curves if k.startswith("pair_")] for v in found]
    step = _offset_step([(p, np.zeros_like(p)) for ps in pairs for p in ps])
    for k, (v, ps) in enumerate(zip(found, pairs)):
        r = v.values.get("log10_rate", 0.0)
        offset = k * step
        ax.axhline(offset, color="k", lw=0.5, ls="--")
        for j, p in enumerate(ps):
            ax.plot(v.curves["grid"], p + offset, lw=0.7, color=colors[r], alpha=0.7,
                    label=f"phi_init {v.values.get('phi_init', 0):g}, {_rate_label(r)} "
                    f"(+{offset:.2g}), {v.status}" if j == 0 else None)
    _decorate(ax, r"packing fraction $\phi$", r"$\Delta p/p$ of sample pairs + offset")
    file = _save(fig, out_dir, "sample_pairs.png")
    return Figure(file, "Sample pairs",
                  "Each line is one pair (sample i of the smaller size against sample i of the "
                  "larger), offset per (phi_init, rate); the sample_pairs check compares their "
                  "spread with the within-size fluctuations.")


def relative_error_figure(c, out_dir):
    """The supplement's fluctuation figure: relative error of p, constant phi beside constant Z."""
    phi_init = representative_phi_init(c)
    chosen = [e for e in c.ensembles if e.phi_init == phi_init and e.constant_phi]
    if not chosen:
        return None
    largest = max(e.n for e in chosen)
    chosen = [e for e in chosen if e.n == largest]
    colors = _rate_colors([e.log10_rate for e in chosen])
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.5))
    for e in chosen:
        a, z = e.constant_phi, e.constant_z
        ok = np.isfinite(a["pressure_relative_error"]) & (a["pressure_mean"] > 0)
        ax.plot(a["packing_fraction"][ok], a["pressure_relative_error"][ok], "-",
                color=colors[e.log10_rate], label=f"{_rate_label(e.log10_rate)}, constant phi")
        if z:
            okz = np.isfinite(z["pressure_relative_error"]) & (z["pressure_mean"] > 0)
            ax.plot(z["packing_fraction_mean"][okz], z["pressure_relative_error"][okz], "--",
                    color=colors[e.log10_rate], label=f"{_rate_label(e.log10_rate)}, constant Z")
    _decorate(ax, r"packing fraction $\phi$ (constant Z: mean $\phi$ at that Z)",
              r"relative error $\sigma_p / (p \sqrt{N_s})$", log_y=True)
    file = _save(fig, out_dir, "relative_errors.png")
    return Figure(file, "Relative errors: constant phi against constant Z",
                  f"N = {largest}, phi_init = {phi_init:g}. Averaging at constant Z (dashed) "
                  "removes most of the sample-to-sample scatter that constant-phi averaging "
                  "(solid) carries near jamming (the supplement's fluctuation figure).")


def jamming_figure(c, out_dir):
    """phi_Ji for each phi_init (left) and the largest phi_init the phi_init check allows for
    each size and rate (right)."""
    found = [e for e in c.ensembles if e.jamming and e.jamming.get("found", 0) > 0]
    safe = [v.values for v in c.verdicts
            if v.check == "phi_init" and "largest_consistent_phi_init" in v.values]
    if not found and not safe:
        return None
    fig, (ax, right) = plt.subplots(1, 2, layout="constrained", figsize=(12, 4.5))
    colors = _rate_colors([e.log10_rate for e in c.ensembles])
    sizes = sorted({e.n for e in c.ensembles})
    groups = sorted({(e.n, e.log10_rate) for e in found}, key=lambda g: (g[0], -g[1]))
    starts = sorted({e.phi_init for e in found})
    width = 0.6 * (min(np.diff(starts)) if len(starts) > 1 else 0.1)
    for k, (n, r) in enumerate(groups):
        mine = sorted([e for e in found if e.n == n and e.log10_rate == r],
                      key=lambda e: e.phi_init)
        shift = width * (k / max(1, len(groups) - 1) - 0.5)
        ax.errorbar([e.phi_init + shift for e in mine], [e.jamming["mean"] for e in mine],
                    yerr=[e.jamming["error"] for e in mine], marker="o" if n == sizes[0] else "s",
                    mfc=colors[r] if n == sizes[0] else "none", color=colors[r], ls="none",
                    capsize=3, label=f"N={n}, {_rate_label(r)}")
    if found:
        paper = c.stats_attrs.get("paper", {})
        if "phi_j" in paper:
            ax.axhline(paper["phi_j"], color="k", ls=":", lw=1,
                       label=f"paper phi_J = {paper['phi_j']:g} (N, 1/rate -> inf)")
        if safe:
            ax.axvline(min(x["largest_consistent_phi_init"] for x in safe), color="tab:red",
                       lw=1, ls="--", label="largest safe phi_init (all sizes and rates)")
        _decorate(ax, r"$\phi_{init}$", r"$\langle\phi_{Ji}\rangle$ (error bars: standard error)")
    else:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "jamming points phi_Ji were not sought in this campaign\n"
                "(campaign key jamming_point = true)", ha="center", va="center",
                transform=ax.transAxes)
    for n in sizes:
        mine = sorted([x for x in safe if x.get("n") == n], key=lambda x: x["log10_rate"])
        if mine:
            right.plot([x["log10_rate"] for x in mine],
                       [x["largest_consistent_phi_init"] for x in mine],
                       marker="o" if n == sizes[0] else "s", mfc="none" if n != sizes[0] else None,
                       ls="-", label=f"N={n}")
    starts_all = sorted({e.phi_init for e in c.ensembles})
    right.set_yticks(starts_all)
    _decorate(right, r"$\log_{10}$ rate", "largest phi_init consistent with the lowest")
    file = _save(fig, out_dir, "jamming_points.png")
    return Figure(file, "Jamming points and the largest safe initial packing",
                  "Left: mean jamming point of the runs of each (size, rate) for every phi_init, "
                  "shifted sideways for legibility, with the largest phi_init consistent at every "
                  "size and rate (dashed red). Right: per size and rate, the largest phi_init whose "
                  "pressure curve the phi_init check finds consistent with the lowest phi_init's.")


def scan_figure(c, out_dir):
    """The paper's Fig. 2: fit parameters against rate_max for the three phi windows."""
    scan = (c.fit or {}).get("scan")
    if not scan or not len(scan.get("rate_max", [])):
        return None
    paper = c.stats_attrs.get("paper", {})
    # Windows are centred on each row's own fitted phi_J: grouped by their half-width.
    half = scan.get("half_window")
    if half is None:  # files written before the windows were re-centred
        half = (scan["phi_max"] - scan["phi_min"]) / 2
    windows = sorted(set(np.round(half[np.isfinite(half)], 6)), reverse=True)
    chosen = scan.get("chosen", np.zeros(len(scan["rate_max"])))
    fig, axes = plt.subplots(1, 3, layout="constrained", figsize=(13, 3.8))
    markers = ["o", "s", "^", "D", "v"]
    for ax, name, label in zip(axes, ["phi_j", "beta", "y"], [r"$\phi_J$", r"$\beta$", "$y$"]):
        for k, w in enumerate(windows):
            sel = (np.round(half, 6) == w) & np.isfinite(scan[name])
            ax.errorbar(np.log10(scan["rate_max"][sel]) + 0.03 * (k - 1), scan[name][sel],
                        yerr=scan[name + "_error"][sel], marker=markers[k % len(markers)],
                        capsize=3, ls="-", lw=0.8,
                        label=f"$\\phi_J \\pm {w:g}$")
            pick = sel & (chosen == 1)
            if pick.any():
                ax.plot(np.log10(scan["rate_max"][pick]) + 0.03 * (k - 1), scan[name][pick],
                        marker="*", ms=16, color="black", ls="none",
                        label="representative" if name == "phi_j" else None)
        if name in paper:
            ax.axhspan(paper[name] - paper[name + "_error"], paper[name] + paper[name + "_error"],
                       color="grey", alpha=0.25, label="paper")
            ax.axhline(paper[name], color="grey", lw=0.8)
        ax.set_xlabel(r"$\log_{10}\dot\epsilon_{max}$ (fastest rate in the fit)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    file = _save(fig, out_dir, "fit_scan.png")
    fixed = (c.fit or {}).get("representative", {}).get("fixed", "none")
    return Figure(file, "Scaling fit against the fastest rate included",
                  "Fit parameters of Eq. 1 with jackknife errors for three windows in phi, each "
                  "centred on its own fitted phi_J, against the largest rate included (the "
                  f"paper's Fig. 2); held fixed: {fixed}. Star: the representative fit "
                  f"({(c.fit or {}).get('representative', {}).get('chosen_because', '-')}). Grey: "
                  "the paper's values, for comparison only (nothing is fitted with them).")


def collapse_figure(c, out_dir):
    """The paper's Fig. 3: the scaling collapse, fitted and unfitted points distinguished."""
    collapse = (c.fit or {}).get("collapse")
    if not collapse or not len(collapse.get("x", [])):
        return None
    rep = c.fit["representative"]
    log_rates = np.log10(collapse["compression_rate"])
    colors = _rate_colors(np.round(log_rates, 2))
    # Far below the window the pressure is that of the start (~0); not drawn, it says nothing.
    floor = 1e-3 * np.min(collapse["scaled_pressure"][collapse["in_fit"] == 1], initial=np.inf)
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.8))
    for r in sorted(set(np.round(log_rates, 2)), reverse=True):
        for in_fit in (1, 0):
            sel = (np.round(log_rates, 2) == r) & (collapse["in_fit"] == in_fit)
            sel &= collapse["scaled_pressure"] > (floor if np.isfinite(floor) else 0)
            if not sel.any():
                continue
            ax.errorbar(collapse["x"][sel], collapse["scaled_pressure"][sel],
                        yerr=collapse["scaled_pressure_error"][sel], marker="o", ms=3, ls="none",
                        color=colors[r], mfc=colors[r] if in_fit else "none", alpha=1 if in_fit
                        else 0.5, label=f"{_rate_label(r)}{'' if in_fit else ' (not fitted)'}")
    ax.axvline(0, color="k", lw=0.5)
    _decorate(ax, r"$x = (\phi - \phi_J)/\dot\epsilon^{1/z\nu}$", r"$p / \dot\epsilon^{q}$",
              log_y=True)
    file = _save(fig, out_dir, "collapse.png")
    return Figure(file, "Scaling collapse",
                  f"phi_J = {rep.get('phi_j', float('nan')):.5f}, q = {rep.get('q', float('nan')):.4f}, "
                  f"1/(z nu) = {rep.get('inv_znu', float('nan')):.4f} (held fixed: "
                  f"{rep.get('fixed', 'none')}); solid symbols were in the fit window "
                  f"phi in [{rep.get('phi_min', 0):.4f}, {rep.get('phi_max', 0):.4f}], rates up to "
                  f"{rep.get('rate_max', 0):.3g}; open symbols were not fitted (points more than 1000 "
                  "times below the fitted ones are left out); the paper's Fig. 3.")


def lammps_figure(c, out_dir):
    """jam against LAMMPS through jamming: pressure overlay and residuals per dimension."""
    found = [v for v in c.verdicts if v.check == "lammps" and "pressure_lammps" in v.curves]
    if not found:
        return None
    fig, axes = plt.subplots(2, len(found), layout="constrained", figsize=(5.5 * len(found), 6), squeeze=False,
                             sharex="col", gridspec_kw={"height_ratios": [2, 1]})
    for k, v in enumerate(found):
        top, bottom = axes[0][k], axes[1][k]
        g = v.curves["grid"]
        top.plot(g, v.curves["pressure_jam"], "o", ms=4, mfc="none", label="jam (overdamped)")
        top.plot(g, v.curves["pressure_lammps"], "-", lw=1, label="LAMMPS (inertial, small Q)")
        top.set_yscale("log")
        top.set_ylabel("pressure (mean over samples)")
        top.set_title(v.case, fontsize=9)
        top.legend(fontsize=7)
        top.grid(alpha=0.3, which="both")
        bottom.errorbar(g, 100 * v.curves["delta"], yerr=100 * v.curves["sigma"], marker="o",
                        ms=3, ls="none", capsize=2)
        bottom.axhline(0, color="k", lw=0.5)
        for s in (-0.5, 0.5):
            bottom.axhline(s, color="tab:red", lw=0.8, ls="--")
        bottom.set_ylabel(r"$\Delta p/p$ (%)")
        bottom.set_xlabel(r"packing fraction $\phi$")
        bottom.grid(alpha=0.3)
    file = _save(fig, out_dir, "lammps.png")
    return Figure(file, "Cross-check against LAMMPS",
                  "The same relaxed starts compressed by jam (overdamped) and by LAMMPS "
                  "(inertial at small Q); top: sample-mean pressure, bottom: mean Delta p/p with "
                  "its standard error; dashed red: the 0.5% systematic difference the check allows "
                  "(plus 3 errors).")


ALL = [pressure_figure, finite_size_figure, sample_pairs_figure, relative_error_figure,
       jamming_figure, scan_figure, collapse_figure, lammps_figure]
