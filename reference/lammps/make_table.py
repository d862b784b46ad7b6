#!/usr/bin/env python3
"""Writes harmonic_contact.table, the one-sided harmonic contact for LAMMPS's pair_style table.

U(r) = (1/2)(1 - r/d)^2 and f(r) = -dU/dr = (1/d)(1 - r/d) for r < d, one table per pair
type (SS: d = 1, SB: d = (1 + ratio)/2, BB: d = ratio), in units d_s = 1, k_e = 1. An optional
stiffness k multiplies U and f (k = 1 is the model; other values make a deliberately wrong
contact), and an optional inner radius (a fraction of d, default 0.4) sets where each table
starts: LAMMPS stops on any pair closer than that, so unrelaxed random starts need a small one.
The force is linear in r, so LAMMPS's clamped cubic spline through these points reproduces it
exactly and its r^2-spaced interpolation table (pair_style table linear N) is the only source of
error: O((d^2/N)^2) relative, below 1e-11 for N = 1e5.

Usage: python3 make_table.py [diameter_ratio [stiffness [inner]]] > harmonic_contact.table
"""
import sys

ratio = float(sys.argv[1]) if len(sys.argv) > 1 else 1.4
stiffness = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
inner = float(sys.argv[3]) if len(sys.argv) > 3 else 0.4
if not (1.0 <= ratio <= 2.0 and stiffness > 0.0 and 0.0 < inner < 1.0):
    sys.exit(f"make_table.py: need 1 <= ratio <= 2, stiffness > 0, 0 < inner < 1 "
             f"(got {ratio}, {stiffness}, {inner})")
points = 201
if stiffness == 1.0:
    print(f"# one-sided harmonic contact U = (1/2)(1 - r/d)^2, diameter ratio {ratio}")
else:
    print(f"# one-sided harmonic contact U = ({stiffness}/2)(1 - r/d)^2, diameter ratio {ratio}")
print("# written by reference/lammps/make_table.py")
for name, d in (("SS", 1.0), ("SB", 0.5 * (1.0 + ratio)), ("BB", ratio)):
    lo = inner * d
    print(f"\n{name}\nN {points} R {lo!r} {d!r}\n")
    for k in range(points):
        r = lo + (d - lo) * k / (points - 1) if k < points - 1 else d
        overlap = 1.0 - r / d
        if stiffness == 1.0:
            print(f"{k + 1} {r!r} {0.5 * overlap * overlap!r} {overlap / d!r}")
        else:
            print(f"{k + 1} {r!r} {0.5 * stiffness * overlap * overlap!r} "
                  f"{stiffness * overlap / d!r}")
