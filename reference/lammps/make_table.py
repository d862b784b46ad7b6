#!/usr/bin/env python3
"""Writes harmonic_contact.table, the one-sided harmonic contact for LAMMPS's pair_style table.

U(r) = (1/2)(1 - r/d)^2 and f(r) = -dU/dr = (1/d)(1 - r/d) for r < d, one table per pair
type (SS: d = 1, SB: d = (1 + ratio)/2, BB: d = ratio), in units d_s = 1, k_e = 1. An optional
stiffness k multiplies U and f (k = 1 is the model; other values make a deliberately wrong
contact), and an optional inner radius (a fraction of d, default 0.4) sets where each table
starts: LAMMPS stops on any pair closer than that, so unrelaxed random starts need a small one.

LAMMPS (pair_style table linear N, N = 100000 in the inputs here) also stops with "Pair distance
> table outer cutoff" when the bin index (rsq - inner^2) / delta of a pair just inside the cutoff
rounds up to N - 1. That happens only within a few ulps of r = d, but a relaxation at zero rate
drives contacts to r -> d from inside and meets it (with inner 0.01 d for d = 1, for example).
Each table's inner radius is therefore raised by the least relative amount (steps of 1e-9) that
makes the largest double below d^2 map to a bin below N - 1, for the cutoff d as written here
and as LAMMPS prints it (%.15g); the index is monotone in rsq, so that double decides.
The force is linear in r, so LAMMPS's clamped cubic spline through these points reproduces it
exactly and its r^2-spaced interpolation table (pair_style table linear N) is the only source of
error: O((d^2/N)^2) relative, below 1e-11 for N = 1e5.

Usage: python3 make_table.py [diameter_ratio [stiffness [inner]]] > harmonic_contact.table
"""
import math
import sys

TABLE_N = 100000  # pair_style table linear 100000 in compress_inertial.in, compress_random.in


def index_safe(lo, cut, n=TABLE_N):
    """True if no distance below cut falls in LAMMPS's bin n - 1 (PairTable::compute)."""
    tlm1 = n - 1
    innersq = lo * lo
    invdelta = 1.0 / ((cut * cut - innersq) / tlm1)
    return int((math.nextafter(cut * cut, 0.0) - innersq) * invdelta) < tlm1


def safe_inner(lo, d):
    cuts = (d, float(f"{d:.15g}"))
    for k in range(100000):
        candidate = lo * (1.0 + k * 1e-9)
        if all(index_safe(candidate, cut) for cut in cuts if cut <= d):
            return candidate
    sys.exit(f"make_table.py: no safe inner radius near {lo} for d = {d}")


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
    lo = safe_inner(inner * d, d)
    print(f"\n{name}\nN {points} R {lo!r} {d!r}\n")
    for k in range(points):
        r = lo + (d - lo) * k / (points - 1) if k < points - 1 else d
        overlap = 1.0 - r / d
        if stiffness == 1.0:
            print(f"{k + 1} {r!r} {0.5 * overlap * overlap!r} {overlap / d!r}")
        else:
            print(f"{k + 1} {r!r} {0.5 * stiffness * overlap * overlap!r} "
                  f"{stiffness * overlap / d!r}")
