"""The pressure figures, as small multiples: p and the bulk viscosity zeta = p/rate against phi
per size (the paper's Fig. 1), and p against the rate at fixed phi (the paper's first result:
zeta reaches a rate-independent plateau below phi_J, p a rate-independent yield pressure above
it, and p ~ rate^q at phi_J). Only drawing: every number comes from stats.h5."""

import matplotlib.pyplot as plt
import numpy as np

from report_plot import (Figure, Plotted, panels_with_key, rate_colors, rate_label, rate_text,
                         representative_phi_init, save)

# Packing fractions of the rate figure, as distances from phi_J: two below, at, one above.
RATE_OFFSETS = (-0.02, -0.01, 0.0, 0.01)


def _positive(e):
    a = e.constant_phi
    phi, p, dp = a["packing_fraction"], a["pressure_mean"], a["pressure_error"]
    keep = p > 0
    return phi[keep], p[keep], dp[keep]


def _floor(chosen, scaled):
    """0.3 times the lowest 5th percentile of the curves' positive p (p/rate when `scaled`):
    the residual pressure of the relaxed start, just after phi_init, lies orders of magnitude
    below the compression's and is left below the vertical range."""
    lows = [np.percentile(p / (e.compression_rate if scaled else 1.0), 5) for e in chosen
            for _, p, _ in [_positive(e)] if len(p)]
    return 0.3 * min(lows) if lows else None


def _pressure_panels(axes, e, color, main, plotted):
    phi, p, dp = _positive(e)
    every = dict(markevery=max(1, len(p) // 30), errorevery=max(1, len(p) // 30))
    style = (dict(marker="o", ms=3, lw=0.9, **every) if main
             else dict(lw=0.7, ls="--", alpha=0.8))
    series = f"N={e.n}, phi_init {e.phi_init:g}, {rate_text(e.log10_rate)}"
    for ax, panel, scale in zip(axes, ("pressure", "bulk viscosity"), (1.0, e.compression_rate)):
        if main:
            ax.errorbar(phi, p / scale, yerr=dp / scale, color=color, capsize=0, **style)
        else:
            ax.plot(phi, p / scale, color=color, **style)
        plotted.add(panel, series, phi, p / scale, dp / scale)


def _legend(key, colors, starts, main_start):
    """One legend for the whole figure: a colour per rate, the line style per phi_init."""
    handles = [plt.Line2D([], [], color=colors[r], marker="o", ms=4, lw=1, label=rate_label(r))
               for r in sorted(colors, reverse=True)]
    if len(starts) > 1:
        handles.append(plt.Line2D([], [], color="k", marker="o", ms=3, lw=0.9,
                                  label=f"phi_init {main_start:g} (the fit's)"))
        handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.7, label="other phi_init: "
                                  + ", ".join(f"{s:g}" for s in starts if s != main_start)))
    key.legend(handles=handles, loc="center left", fontsize=8, borderaxespad=0)


def pressure_figure(c, out_dir):
    """p (top row) and zeta = p/rate (bottom row) against phi, one column per size, one colour
    per rate; the fit's phi_init drawn with symbols and errors, other phi_init dashed."""
    chosen = [e for e in c.ensembles if e.constant_phi and len(_positive(e)[1])]
    if not chosen:
        return None
    sizes = sorted({e.n for e in chosen})
    starts = sorted({e.phi_init for e in chosen})
    main_start = representative_phi_init(c)
    colors = rate_colors([e.log10_rate for e in chosen])
    fig, axes, key = panels_with_key(2, len(sizes), (3.4, 3.1), sharex=True, sharey="row")
    plotted = Plotted()
    plotted.panel("pressure", "packing fraction phi", "pressure p")
    plotted.panel("bulk viscosity", "packing fraction phi", "p / rate")
    for e in sorted(chosen, key=lambda e: (e.phi_init != main_start, -e.log10_rate)):
        column = sizes.index(e.n)
        _pressure_panels(axes[:, column], e, colors[e.log10_rate], e.phi_init == main_start,
                         plotted)
    for column, n in enumerate(sizes):
        axes[0, column].set_title(f"N = {n}", fontsize=10)
        axes[1, column].set_xlabel(r"packing fraction $\phi$")
    for ax in axes.ravel():
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
    for row, scaled in ((0, False), (1, True)):
        floor = _floor(chosen, scaled)
        if floor:
            axes[row, 0].set_ylim(bottom=floor)
    axes[0, 0].set_ylabel("pressure $p$")
    axes[1, 0].set_ylabel(r"bulk viscosity $\zeta = p/\dot\epsilon$")
    _legend(key, colors, starts, main_start)
    file = save(fig, out_dir, "pressure.png", plotted)
    return Figure(file, "Pressure and bulk viscosity",
                  "Sample means at constant phi, one column per size and one colour per rate "
                  f"(the paper's Fig. 1); symbols with standard errors: phi_init {main_start:g}"
                  + (", the one the fit uses; dashed: the other phi_init" if len(starts) > 1
                     else "") + ". The residual pressure of the relaxed start, right after "
                  "phi_init, lies below the vertical range.")


def _nearest(e, phi):
    """(p, error) at the grid point of e nearest phi, when one lies within half a grid step."""
    grid = e.constant_phi["packing_fraction"]
    if len(grid) < 2:
        return None
    k = int(np.argmin(np.abs(grid - phi)))
    step = float(np.median(np.diff(grid)))
    if abs(grid[k] - phi) > 0.5 * abs(step) + 1e-12 or not e.constant_phi["pressure_mean"][k] > 0:
        return None
    return float(e.constant_phi["pressure_mean"][k]), float(e.constant_phi["pressure_error"][k])


def _phi_j(c, chosen):
    """phi_J of the representative fit, else the mean phi_Ji of the slowest rate (None)."""
    rep = (c.fit or {}).get("representative") or {}
    if np.isfinite(rep.get("phi_j", np.nan)):
        return float(rep["phi_j"]), "the representative fit's phi_J"
    found = [e for e in chosen if e.jamming and e.jamming.get("found", 0) > 0]
    if not found:
        return None, None
    slowest = min(e.log10_rate for e in found)
    return (float(np.mean([e.jamming["mean"] for e in found if e.log10_rate == slowest])),
            "the mean jamming point phi_Ji at the slowest rate (no fit)")


def _rate_panel(ax, mine, phis, plotted, n):
    colors = plt.get_cmap("plasma")(np.linspace(0.05, 0.8, len(phis)))
    for color, (offset, phi) in zip(colors, phis):
        points = [(e.compression_rate, *v) for e in mine for v in [_nearest(e, phi)] if v]
        if len(points) < 2:
            continue
        rate, p, dp = map(np.array, zip(*sorted(points)))
        ax.errorbar(rate, p, yerr=dp, marker="o", ms=4, lw=1, capsize=2, color=color,
                    label=f"$\\phi_J {offset:+g}$" if offset else r"$\phi_J$")
        plotted.add("p against rate", f"N={n}, phi {phi:.4f} (phi_J {offset:+g})", rate, p, dp)


def _guides(ax, q):
    """Slopes 1 (zeta constant: Newtonian below phi_J) and q (at phi_J), through the panel's
    middle: a reader compares slopes, not levels."""
    lo, hi = ax.get_xlim()
    y_lo, y_hi = ax.get_ylim()
    x = np.array([lo, hi])
    middle = np.sqrt(y_lo * y_hi)
    for slope, style, text in ((1.0, ":", "slope 1"), (q, "-.", f"slope q = {q:.3g}")):
        if slope and np.isfinite(slope):
            x0 = np.sqrt(lo * hi)
            ax.plot(x, middle * (x / x0) ** slope, "k" + style, lw=0.8, alpha=0.6, label=text)


def rate_figure(c, out_dir):
    """p against rate at fixed phi (two below phi_J, at it, one above), one panel per size."""
    main_start = representative_phi_init(c)
    chosen = [e for e in c.ensembles if e.constant_phi and e.phi_init == main_start]
    if len({e.log10_rate for e in chosen}) < 2:
        return None
    phi_j, source = _phi_j(c, chosen)
    if phi_j is None:
        return None
    phis = [(offset, phi_j + offset) for offset in RATE_OFFSETS]
    sizes = sorted({e.n for e in chosen})
    fig, axes, key = panels_with_key(1, len(sizes), (3.4, 3.6), sharey="all")
    plotted = Plotted()
    plotted.panel("p against rate", "compression rate", "pressure p at fixed phi")
    q = ((c.fit or {}).get("representative") or {}).get("q", np.nan)
    for ax, n in zip(axes[0], sizes):
        _rate_panel(ax, [e for e in chosen if e.n == n], phis, plotted, n)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"N = {n}", fontsize=10)
        ax.set_xlabel(r"compression rate $\dot\epsilon$")
        ax.grid(alpha=0.3)
    for ax in axes[0]:
        _guides(ax, q)
    axes[0, 0].set_ylabel(r"pressure $p$ at fixed $\phi$")
    key.legend(*axes[0, -1].get_legend_handles_labels(), loc="center left", fontsize=8,
               borderaxespad=0)
    file = save(fig, out_dir, "pressure_rate.png", plotted)
    return Figure(file, "Pressure against rate at fixed packing",
                  f"phi_J = {phi_j:.4f} ({source}); phi_init {main_start:g}; each point the "
                  "grid point nearest phi (no interpolation), with its standard error. Below "
                  "phi_J p grows as the rate (slope 1: a constant bulk viscosity), at phi_J as "
                  "rate^q, above it p tends to a rate-independent value (the paper's first "
                  "result). Guide lines show slopes only; their height means nothing.")
