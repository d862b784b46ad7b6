#!/usr/bin/python3
"""Log-log figures of `jam bench`: plot_benchmarks.py throughput|accuracy CSV PNG.

throughput: particle-steps/s and seconds per particle-step against N, jam and LAMMPS, per
dimension and mode. accuracy: wall time against the largest pressure error, per dimension and
rate, one marker per method and dt. The PNG is written whole (jamio's output.staged: a
temporary name beside it, renamed when complete).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# jamio of the same source tree (python/ beside bench/).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "python"))
from jamio.output import staged  # noqa: E402


def rows_of(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def throughput(rows, png):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for dim, marker in (("2", "o"), ("3", "s")):
        for mode, style in (("1 core", "-"), ("2 cores: campaign", "--"), ("2 cores: one run", ":")):
            sel = [r for r in rows if r["dim"] == dim and r["mode"] == mode]
            if not sel:
                continue
            n = [float(r["n"]) for r in sel]
            for engine, col, color in (("jam", "jam_particle_steps_per_s", "C0"),
                                       ("LAMMPS", "lammps_particle_steps_per_s", "C3")):
                y = [float(r[col]) for r in sel]
                if max(y) <= 0:
                    continue
                lbl = f"{engine} {dim}D, {mode}"
                axes[0].loglog(n, y, style, marker=marker, color=color, label=lbl)
                if mode == "1 core":
                    axes[1].loglog(n, [1e9 / v for v in y], style, marker=marker, color=color,
                                   label=f"{engine} {dim}D")
    axes[0].set_xlabel("N")
    axes[0].set_ylabel("particle-steps / s")
    axes[0].legend(fontsize=7)
    axes[1].set_xlabel("N")
    axes[1].set_ylabel("ns per particle-step (1 core; flat = cost linear in N)")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110, format="png")  # by format: the temporary name is not *.png


def accuracy(rows, png):
    cases = sorted({(r["dim"], float(r["rate"])) for r in rows}, key=lambda c: (c[0], -c[1]))
    fig, axes = plt.subplots(1, len(cases), figsize=(4.6 * len(cases), 4.3), squeeze=False)
    markers = {"euler": "o", "heun": "s", "verlet": "^"}
    for ax, (dim, rate) in zip(axes[0], cases):
        sel = [r for r in rows if r["dim"] == dim and float(r["rate"]) == rate
               and not r["integrator"].startswith("reference")]
        groups = {}
        for r in sel:
            key = (r["engine"], r["integrator"], r["q"])
            groups.setdefault(key, []).append(r)
        colors = {}
        for k, ((engine, integ, q), g) in enumerate(sorted(groups.items())):
            colors[(engine, integ, q)] = f"C{k % 10}"
            g.sort(key=lambda r: float(r["dt"]))
            err = [max(float(r["max_error"]), 1e-12) for r in g]
            wall = [float(r["wall_median_s"]) for r in g]
            lbl = f"{engine} {integ}" + (f" Q={q}" if integ == "verlet" else "")
            ax.loglog(err, wall, "-" if engine == "jam" else "--", marker=markers.get(integ, "x"),
                      color=colors[(engine, integ, q)], label=lbl)
        for target in (0.01, 0.001):
            ax.axvline(target, color="grey", lw=0.5)
        ax.set_title(f"{dim}D, rate {rate:g}")
        ax.set_xlabel("max |<p/p_ref - 1>| over 3 packings")
        ax.set_ylabel("wall time (s)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110, format="png")  # by format: the temporary name is not *.png


def main():
    kind, path, png = sys.argv[1:4]
    rows = rows_of(path)
    with staged(png, kind="figure") as partial:
        (throughput if kind == "throughput" else accuracy)(rows, partial)


if __name__ == "__main__":
    main()
