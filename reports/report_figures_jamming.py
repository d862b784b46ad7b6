"""The jamming points' spread: the distribution of phi_Ji per size at the slowest rate, its
width Delta phi_J(N) against the distance from phi_J that the slowest rate resolves,
rate_min^(1/(z nu)) with 1/(z nu) from the campaign's own fit (where Delta phi_J(N) is larger,
the slowest rate already feels the finite size: the paper's question of its Fig. 4), the power
law Delta phi_J ~ N^-w fitted to it, and the mean <phi_Ji> against N (the supplement: the spread
vanishes as N grows; does the mean move?)."""

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


def log_width_variance(n):
    """The variance of the log of a standard deviation of n normal values:
    var(log s) = trigamma((n - 1) / 2) / 4 (s^2 (n - 1) / sigma^2 is chi^2 with n - 1 degrees
    of freedom), from trigamma(1/2) = pi^2/2, trigamma(1) = pi^2/6 and trigamma(x + 1) =
    trigamma(x) - 1/x^2. For n = 10: 0.0622 (the large-n 1/(2(n - 1)) says 0.0556)."""
    if n < 2:
        raise ValueError(f"a standard deviation needs 2 values, not {n}")
    x, value = (1.0, math.pi ** 2 / 6) if (n - 1) % 2 == 0 else (0.5, math.pi ** 2 / 2)
    while x < (n - 1) / 2:
        value -= 1.0 / x ** 2
        x += 1.0
    return value / 4


def width_power_law(sizes, widths, runs):
    """Delta phi_J(N) = a N^-w by weighted least squares in logs, each log width weighted by
    its variance for normal samples (log_width_variance). Returns (w, its standard error, a,
    chi^2 per degree of freedom), or None with fewer than 3 sizes."""
    if len(sizes) < 3:
        return None
    x = np.log(np.asarray(sizes, float))
    y = np.log(np.asarray(widths, float))
    weight = np.array([1.0 / log_width_variance(k) for k in runs])
    xm = np.sum(weight * x) / np.sum(weight)
    ym = np.sum(weight * y) / np.sum(weight)
    sxx = np.sum(weight * (x - xm) ** 2)
    slope = np.sum(weight * (x - xm) * (y - ym)) / sxx
    chi2 = np.sum(weight * (y - ym - slope * (x - xm)) ** 2) / (len(sizes) - 2)
    return -slope, 1.0 / math.sqrt(sxx), math.exp(ym - slope * xm), float(chi2)


def jamming_width_figure(c, out_dir):
    """Left: phi_Ji histograms per size (slowest rate, every phi_init pooled). Middle: their
    standard deviation Delta phi_J(N) against N with its errors, the power law fitted to it and
    the rate's scale as a line. Right: their mean <phi_Ji> against N."""
    by_size, slowest = _slowest_found(c)
    if not by_size:
        return None
    rep = (c.fit or {}).get("representative") or {}
    inv_znu = rep.get("inv_znu", float("nan"))
    scale = 10.0 ** (slowest * inv_znu) if math.isfinite(inv_znu) else float("nan")
    fig, (left, right, mean) = plt.subplots(1, 3, layout="constrained", figsize=(16, 4.5))
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
    runs = [len(by_size[n]) for n in sizes]
    widths = [float(np.std(by_size[n], ddof=1)) for n in sizes]
    width_errors = [w * math.sqrt(log_width_variance(k)) for w, k in zip(widths, runs)]
    plotted.panel("width", "N", "std of phi_Ji")
    right.errorbar(sizes, widths, yerr=width_errors, fmt="o",
                   label=r"$\Delta\phi_J(N)$, standard deviation of $\phi_{Ji}$")
    plotted.add("width", "Delta phi_J(N)", sizes, widths, width_errors)
    law = width_power_law(sizes, widths, runs)
    if law:
        w, w_err, a, _ = law
        line = [a * n ** -w for n in sizes]
        right.plot(sizes, line, "k-", lw=1, label=f"fit: N^-{w:.2f}({round(100 * w_err):d})")
        plotted.add("width", "fit a N^-w", sizes, line)
    means = [float(np.mean(by_size[n])) for n in sizes]
    mean_errors = [w / math.sqrt(k) for w, k in zip(widths, runs)]
    plotted.panel("mean", "N", "mean of phi_Ji")
    mean.errorbar(sizes, means, yerr=mean_errors, fmt="o", label=r"$\langle\phi_{Ji}\rangle$")
    plotted.add("mean", "<phi_Ji>", sizes, means, mean_errors)
    mean.set_xscale("log")
    decorate(mean, "N", r"$\langle\phi_{Ji}\rangle$")
    if math.isfinite(scale):
        right.axhline(scale, color="tab:red", ls="--",
                      label=f"rate_min^(1/(z nu)) = 1e{slowest:g}^{inv_znu:.3f}")
    right.set_xscale("log")
    right.set_yscale("log")
    decorate(right, "N", r"$\Delta\phi_J(N)$")
    file = save(fig, out_dir, "jamming_width.png", plotted)
    caption = (f"Jamming points at the slowest rate, 1e{slowest:g}, every phi_init pooled. "
               f"Left: their distribution per size. Middle: its width Delta phi_J(N) (standard "
               f"deviation of phi_Ji): {', '.join(f'{w:.2g} at N={n}' for n, w in zip(sizes, widths))}"
               " (error bars: the scatter of a standard deviation of that many normal values).")
    if law:
        w, w_err, _, chi2 = law
        caption += (f" Fitted (weighted, in logs): Delta phi_J ~ N^-{w:.2f} +- {w_err:.2f} "
                    f"(chi^2/dof {chi2:.2f}); independent subvolumes would give N^-0.5.")
    caption += (" Right: the mean <phi_Ji>: " + ", ".join(
        f"{m:.5f} +- {e:.5f} at N={n}" for n, m, e in zip(sizes, means, mean_errors)) + ".")
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
