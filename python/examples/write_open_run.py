#!/usr/bin/python3
"""Writes one open run from a Python code's arrays (docs/porting.md), then reads it back.

The "code" here is a minimal overdamped simulation of the model of docs/model.md, in jam's
units, standing in for yours: N/2 small (diameter 1) and N/2 big (1.4) discs at random in a
periodic square box at phi_init, relaxed at zero rate with the same overdamped dynamics until the
energy per particle is below 1e-4 rate^2 (jam's default; never CG minimisation), then compressed
at `rate`, L(t) = L0 exp(-rate t), with forward Euler in scaled coordinates s = r/L, where the
host flow is exact: ds/dt = f / (gamma L), gamma_i = (2/D) V_i/V_s. Pair forces of the
one-sided harmonic contact, U = (1/2)(1 - r/d_ij)^2, over all pairs (O(N^2): a few dozen
particles). The pressure is the virial, p = sum_pairs r_ij f_ij / (D V).

Only the last lines concern jam: one array per output point, handed to jamio.write_run, which
checks every field before writing and refuses an existing file; then `jam validate OUT` and
`jam campaign import DIR OUT` take it.

Usage: /usr/bin/python3 python/examples/write_open_run.py --out run.h5 [--n 32] [--seed 1]
       (jamio from this source tree: the script puts python/ first on its path)
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import jamio  # noqa: E402

DIM, RATIO = 2, 1.4


def forces(s, L, d):
    """Forces, elastic energy and virial pressure of scaled positions s in a box of side L."""
    delta = s[:, None, :] - s[None, :, :]
    delta -= np.round(delta)  # nearest image
    r_vec = delta * L
    r = np.sqrt((r_vec ** 2).sum(axis=2))
    dij = 0.5 * (d[:, None] + d[None, :])
    np.fill_diagonal(r, L)  # no particle touches itself (L > 2 d_ij)
    overlap = np.clip(1.0 - r / dij, 0.0, None)
    magnitude = overlap / dij  # -dU/dr
    f = (magnitude / r)[:, :, None] * r_vec
    energy = 0.25 * (overlap ** 2).sum()  # each pair twice, U = overlap^2 / 2
    pressure = 0.5 * (magnitude * r).sum() / (DIM * L ** DIM)
    return f.sum(axis=1), energy, pressure


def simulate(n, seed, phi_init, phi_stop, rate, dt, every):
    """One compression run: the arrays a code would hand to jam."""
    rng = np.random.default_rng(seed)
    d = np.where(np.arange(n) < n // 2, 1.0, RATIO)
    volumes = math.pi / 4 * d ** 2
    L0 = math.sqrt(volumes.sum() / phi_init)
    gamma = (2.0 / DIM) * volumes / volumes[0]
    s = rng.random((n, DIM))
    target = 1e-4 * rate ** 2
    for _ in range(10_000_000):  # relaxation at zero rate, the box fixed
        f, energy, _ = forces(s, L0, d)
        if energy / n < target:
            break
        s = (s + dt * f / (gamma[:, None] * L0)) % 1.0
    else:
        sys.exit("write_open_run: the relaxation did not reach its target")
    out = {"time": [], "phi": [], "p": [], "e": []}
    steps = math.ceil(math.log(phi_stop / phi_init) / (DIM * rate * dt))
    for k in range(steps + 1):
        t = k * dt
        L = L0 * math.exp(-rate * t)
        f, energy, pressure = forces(s, L, d)
        if k % every == 0 or k == steps:
            out["time"].append(t)
            out["phi"].append(phi_init * math.exp(DIM * rate * t))
            out["p"].append(pressure)
            out["e"].append(energy / n)
        s = (s + dt * f / (gamma[:, None] * L)) % 1.0
    return {k: np.array(v) for k, v in out.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", required=True)
    p.add_argument("--n", type=int, default=32)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--phi-init", type=float, default=0.75)
    p.add_argument("--phi-stop", type=float, default=0.84)
    p.add_argument("--rate", type=float, default=1e-3)
    a = p.parse_args()
    run = simulate(a.n, a.seed, a.phi_init, a.phi_stop, a.rate, dt=0.05, every=20)
    # What jam needs: one value per output point, in jam's units, and the model's parameters.
    written = jamio.write_run(a.out, run["phi"], run["p"], time=run["time"],
                              energy_per_particle=run["e"], dim=DIM, n=a.n, rate=a.rate,
                              phi_init=a.phi_init, simulator="write_open_run.py example",
                              simulator_version="1", sample=a.seed, diameter_ratio=RATIO)
    print(f"{a.out}: {written}")


if __name__ == "__main__":
    try:
        main()
    except jamio.JamioError as e:
        sys.exit(str(e))
