"""The jamming points' spread: the distribution of phi_Ji per size at the slowest rate, and its
width Delta phi_J(N) against the distance from phi_J that the slowest rate resolves,
rate_min^(1/(z nu)) with 1/(z nu) from the campaign's own fit. Where Delta phi_J(N) is larger,
the slowest rate already feels the finite size (the paper's question of its Fig. 4)."""

import math

import matplotlib.pyplot as plt
import numpy as np

from report_plot import Figure, Plotted, decorate, save


def _slowest_found(c):
    """The ensembles of the slowest rate whose runs looked for phi_Ji, by size."""
    found = [e for e in c.ensembles if e.jamming and e.jamming.get("found", 0) > 1]
    if not found:
        return {}, None
    slowest = min(e.log10_rate for e in found)
    by_size = {}
    for e in found:
        if e.log10_rate == slowest:
            by_size.setdefault(e.n, []).extend(
                x for x in np.asarray(e.jamming["packing_fraction_samples"]) if math.isfinite(x))
    return {n: np.asarray(v) for n, v in sorted(by_size.items()) if len(v) > 1}, slowest


def jamming_width_figure(c, out_dir):
    """Left: phi_Ji histograms per size (slowest rate, every phi_init pooled). Right: their
    standard deviation Delta phi_J(N) against N, with the rate's scale as a line."""
    by_size, slowest = _slowest_found(c)
    if not by_size:
        return None
    rep = (c.fit or {}).get("representative") or {}
    inv_znu = rep.get("inv_znu", float("nan"))
    scale = 10.0 ** (slowest * inv_znu) if math.isfinite(inv_znu) else float("nan")
    fig, (left, right) = plt.subplots(1, 2, layout="constrained", figsize=(12, 4.5))
    plotted = Plotted()
    plotted.panel("distribution", "phi_Ji", "runs")
    edges = np.linspace(min(v.min() for v in by_size.values()),
                        max(v.max() for v in by_size.values()), 16)
    for n, values in by_size.items():
        counts, _ = np.histogram(values, bins=edges)
        left.stairs(counts, edges, label=f"N={n} ({len(values)} runs)")
        plotted.add("distribution", f"N={n}", list(0.5 * (edges[1:] + edges[:-1])), list(counts))
    decorate(left, r"$\phi_{Ji}$", "runs")
    sizes = list(by_size)
    widths = [float(np.std(by_size[n], ddof=1)) for n in sizes]
    plotted.panel("width", "N", "std of phi_Ji")
    right.plot(sizes, widths, "o-", label=r"$\Delta\phi_J(N)$, standard deviation of $\phi_{Ji}$")
    plotted.add("width", "Delta phi_J(N)", sizes, widths)
    if math.isfinite(scale):
        right.axhline(scale, color="tab:red", ls="--",
                      label=f"rate_min^(1/(z nu)) = 1e{slowest:g}^{inv_znu:.3f}")
    right.set_xscale("log")
    right.set_yscale("log")
    decorate(right, "N", r"$\Delta\phi_J(N)$")
    file = save(fig, out_dir, "jamming_width.png", plotted)
    caption = (f"Jamming points at the slowest rate, 1e{slowest:g}, every phi_init pooled. "
               f"Left: their distribution per size. Right: its width Delta phi_J(N) (standard "
               f"deviation of phi_Ji): {', '.join(f'{w:.2g} at N={n}' for n, w in zip(sizes, widths))}.")
    if math.isfinite(scale):
        feels = [n for n, w in zip(sizes, widths) if w > scale]
        caption += (f" Dashed: rate_min^(1/(z nu)) = {scale:.2g}, the distance from phi_J below "
                    f"which the slowest rate's scaling resolves (1/(z nu) = {inv_znu:.3f} from "
                    "this campaign's fit, up to the scaling function's constant). ")
        caption += (f"Delta phi_J(N) exceeds it at N = {', '.join(map(str, feels))}: there the "
                    "slowest rate already feels the finite size." if feels else
                    "Delta phi_J(N) stays below it at every size: the slowest rate does not yet "
                    "feel the finite size.")
    else:
        caption += " The campaign has no fit, so the rate's scale is not drawn."
    return Figure(file, "Jamming points: distribution and width against the rate's scale",
                  caption)
