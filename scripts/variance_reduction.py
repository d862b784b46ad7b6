#!/usr/bin/env python3
"""Does a run's own jamming point phi_Ji reduce the sample scatter of its pressure near phi_J?

  scripts/variance_reduction.py reference/results/reduced-2d/stats.h5 [--phi-init 0.4]

For every ensemble with phi_Ji of every run, at phi = phi_J + dx (phi_J the stored fit's,
dx = -0.008 ... +0.008), prints the sample standard deviation of ln p three ways:
  plain    ln p_i(phi)                                  (what the checks compare)
  shifted  ln p_i(phi + phi_Ji - <phi_Ji>)              (averaging at constant phi - phi_Ji)
  control  ln p_i(phi) - b (phi_Ji - <phi_Ji>), b fitted by least squares leaving run i out
           (phi_Ji as a control variate; leaving i out keeps the slope's own noise in)
Pressures between grid points are interpolated linearly in ln p. Reads with h5py.
"""
import argparse

import h5py
import numpy as np

from script_files import fail, require_input

OFFSETS = (-0.008, -0.004, 0.0, 0.004, 0.008)


def ln_p_at(phi_grid, p, phi):
    return np.interp(phi, phi_grid, np.log(np.maximum(p, 1e-300)))


def scatter(phi_grid, p, phi_ji, phi):
    plain = np.array([ln_p_at(phi_grid, row, phi) for row in p])
    shifted = np.array([ln_p_at(phi_grid, row, phi + j - phi_ji.mean())
                        for row, j in zip(p, phi_ji)])
    residual = []
    for i in range(len(plain)):
        keep = np.arange(len(plain)) != i
        slope, intercept = np.polyfit(phi_ji[keep], plain[keep], 1)
        residual.append(plain[i] - (slope * phi_ji[i] + intercept))
    return (np.std(plain, ddof=1), np.std(shifted, ddof=1),
            np.sqrt(np.mean(np.square(residual))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("stats")
    ap.add_argument("--phi-init", type=float, default=None,
                    help="only the ensembles of this phi_init (default: the lowest)")
    args = ap.parse_args()
    require_input(args.stats, "stats")
    with h5py.File(args.stats, "r") as f:
        phi_j = float(f["fit/representative"].attrs["phi_j"])
        groups = [g for g in f["ensembles"].values() if "jamming" in g]
        lowest = min(float(g.attrs["phi_init"]) for g in groups)
        phi_init = lowest if args.phi_init is None else args.phi_init
        print(f"phi_J {phi_j:.4f}; sd of ln p: plain / shifted / control, at phi_J + "
              + ", ".join(f"{dx:+.3f}" for dx in OFFSETS))
        key = lambda g: (int(g.attrs["n"]), float(g.attrs["log10_rate"]))
        for g in sorted(groups, key=key):
            if abs(float(g.attrs["phi_init"]) - phi_init) > 1e-9:
                continue
            phi_ji = g["jamming/packing_fraction_samples"][:]
            if not np.all(np.isfinite(phi_ji)):
                continue
            grid = g["constant_phi/packing_fraction"][:]
            p = g["constant_phi/pressure_samples"][:]
            # Each sample's phi_Ji beside its own pressures: the same samples, in one order.
            ids = (g["jamming/sample_ids"][:], g["constant_phi/sample_ids"][:])
            if p.shape != (len(phi_ji), len(grid)) or not np.array_equal(*ids):
                fail(f"stats {args.stats}: ensemble {g.name}: pressure_samples {p.shape} and "
                     f"jamming points of samples {ids[0].tolist()} against "
                     f"{ids[1].tolist()} x {len(grid)} points do not pair")
            cells = [scatter(grid, p, phi_ji, phi_j + dx) for dx in OFFSETS]
            print(f"N {int(g.attrs['n']):5d} rate 1e{float(g.attrs['log10_rate']):<5g} "
                  + "  ".join("{:.2f}/{:.2f}/{:.2f}".format(*c) for c in cells))


if __name__ == "__main__":
    main()
