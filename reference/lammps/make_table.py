#!/usr/bin/env python3
"""Writes harmonic_contact.table, the one-sided harmonic contact for LAMMPS's pair_style table.

U(r) = (1/2)(1 - r/d)^2 and f(r) = -dU/dr = (1/d)(1 - r/d) for r < d, one table per pair
type (SS: d = 1, SB: d = (1 + ratio)/2, BB: d = ratio), in units d_s = 1, k_e = 1.
The force is linear in r, so LAMMPS's clamped cubic spline through these points reproduces it
exactly and its r^2-spaced interpolation table (pair_style table linear N) is the only source of
error: O((d^2/N)^2) relative, below 1e-11 for N = 1e5.

Usage: python3 make_table.py [diameter_ratio] > harmonic_contact.table
"""
import sys

ratio = float(sys.argv[1]) if len(sys.argv) > 1 else 1.4
points = 201
print(f"# one-sided harmonic contact U = (1/2)(1 - r/d)^2, diameter ratio {ratio}")
print("# written by reference/lammps/make_table.py")
for name, d in (("SS", 1.0), ("SB", 0.5 * (1.0 + ratio)), ("BB", ratio)):
    lo = 0.4 * d
    print(f"\n{name}\nN {points} R {lo!r} {d!r}\n")
    for k in range(points):
        r = lo + (d - lo) * k / (points - 1) if k < points - 1 else d
        overlap = 1.0 - r / d
        print(f"{k + 1} {r!r} {0.5 * overlap * overlap!r} {overlap / d!r}")
