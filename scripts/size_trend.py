#!/usr/bin/env python3
"""How a size effect below jamming scales with N: paper-2d-followup's H3.

  scripts/size_trend.py runs/paper-2d-followup --reference-n 32768 --n 8192 16384 \\
      --rates -7.5 -8 -8.5 --phi-min 0.8289 --phi-max 0.8369

For each size n and rate, Delta_n = <p_n>(phi) / <p_ref>(phi) - 1 at constant phi, averaged
plainly over the output points of [phi-min, phi-max] (<.>: the mean over samples), then over
the rates. With two sizes n1 < n2 below the reference it prints

  R = Delta_n1 / Delta_n2   (rate-averaged Deltas)

which is ln(ref/n1) / ln(ref/n2) if the effect is linear in ln N (2 for 8192, 16384 against
32768), (1/n1 - 1/ref) / (1/n2 - 1/ref) if it goes as 1/N (3 for the same), and its
delete-one jackknife error over samples. A sample index is deleted from every size and rate at
once: the rates of one sample are chained (the same trajectory), the sizes independent. The
plain mean over the region is the registered H3 statistic (the campaign file's header), not the
check's weighted one. Reads the run files with jamio; prints a table, writes nothing
(`trend()` is the computation, on jamio.load_runs' table).
"""
import argparse
import math

import numpy as np

from script_files import fail

import jamio


def sample_curves(rows, n, rate, phi_lo, phi_hi):
    """sample -> pressures on the output points of [phi_lo, phi_hi] (rounded phi keys)."""
    keep = ((rows["n"] == n) & np.isclose(np.log10(rows["compression_rate"]), rate, atol=1e-6)
            & (rows["packing_fraction"] >= phi_lo - 1e-9)
            & (rows["packing_fraction"] <= phi_hi + 1e-9))
    curves = {}
    for s, phi, p in zip(rows["sample"][keep], rows["packing_fraction"][keep],
                         rows["pressure"][keep]):
        curves.setdefault(int(s), {})[round(float(phi), 6)] = float(p)
    return curves


def delta(curves_a, curves_b, samples):
    """Plain mean over the region's points of <p_a>/<p_b> - 1, over the given samples."""
    points = sorted(set.intersection(*(set(curves_a[s]) for s in samples if s in curves_a),
                                     *(set(curves_b[s]) for s in samples if s in curves_b)))
    if not points:
        return math.nan
    a = [np.mean([curves_a[s][x] for s in samples if s in curves_a]) for x in points]
    b = [np.mean([curves_b[s][x] for s in samples if s in curves_b]) for x in points]
    return float(np.mean(np.array(a) / np.array(b) - 1.0))


def deltas(curves, sizes, ref, rates, samples):
    """size -> rate-averaged Delta against the reference size, over the given samples."""
    return {n: float(np.mean([delta(curves[(n, r)], curves[(ref, r)], samples) for r in rates]))
            for n in sizes}


def trend(rows, sizes, ref, rates, phi_lo, phi_hi):
    """The trend of a table of runs (jamio.load_runs' columns, as_frame=False): a dict with
    `per_rate` ((n, rate) -> Delta), `delta` (n -> (rate-averaged Delta, jackknife error)),
    `samples` and, for two sizes, `ratio` ((R, error), the smaller size's Delta over the
    larger's). Raises ValueError naming the ensemble with fewer than two samples."""
    curves = {(n, r): sample_curves(rows, n, r, phi_lo, phi_hi)
              for n in list(sizes) + [ref] for r in rates}
    for key, c in curves.items():
        if len(c) < 2:
            raise ValueError(f"n {key[0]} log10 rate {key[1]}: {len(c)} finished samples, "
                             "2 needed")
    samples = sorted(set().union(*(set(c) for c in curves.values())))
    out = {"samples": samples,
           "per_rate": {(n, r): delta(curves[(n, r)], curves[(ref, r)], samples)
                        for n in sizes for r in rates}}
    whole = deltas(curves, sizes, ref, rates, samples)
    leave = [deltas(curves, sizes, ref, rates, [s for s in samples if s != k])
             for k in samples]
    out["delta"] = {n: (whole[n], jackknife([d[n] for d in leave])) for n in sizes}
    if len(sizes) == 2:
        n1, n2 = sorted(sizes)
        out["ratio"] = (whole[n1] / whole[n2], jackknife([d[n1] / d[n2] for d in leave]))
    return out


def jackknife(values):
    """The delete-one jackknife error of the statistic whose leave-one-out values these are."""
    v = np.asarray(values)
    m = len(v)
    return math.sqrt((m - 1) / m * np.sum((v - v.mean()) ** 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("campaign", help="a campaign directory (its runs/*.h5)")
    ap.add_argument("--reference-n", type=int, required=True)
    ap.add_argument("--n", type=int, nargs="+", required=True, help="the sizes below it")
    ap.add_argument("--rates", type=float, nargs="+", required=True, help="log10 rates")
    ap.add_argument("--phi-min", type=float, required=True)
    ap.add_argument("--phi-max", type=float, required=True)
    args = ap.parse_args()
    if not args.phi_min < args.phi_max:
        fail(f"--phi-min {args.phi_min} must lie below --phi-max {args.phi_max}")
    try:
        rows = jamio.load_runs(args.campaign, as_frame=False)
        t = trend(rows, args.n, args.reference_n, args.rates, args.phi_min, args.phi_max)
    except (jamio.JamioError, ValueError) as e:
        fail(str(e))
    print(f"region phi [{args.phi_min}, {args.phi_max}], reference N = {args.reference_n}, "
          f"{len(t['samples'])} sample indices")
    for r in args.rates:
        print(f"  log10 rate {r:+.1f}: Delta " + ", ".join(
            f"N {n}: {100 * t['per_rate'][(n, r)]:+.1f}%" for n in args.n))
    for n, (d, err) in t["delta"].items():
        print(f"  rates averaged: Delta N {n} = {100 * d:+.2f}% +- {100 * err:.2f}%")
    if "ratio" in t:
        n1, n2 = sorted(args.n)
        ref = args.reference_n
        ln_n = math.log(ref / n1) / math.log(ref / n2)
        inv_n = (1 / n1 - 1 / ref) / (1 / n2 - 1 / ref)
        print(f"  R = Delta N {n1} / Delta N {n2} = {t['ratio'][0]:.2f} +- {t['ratio'][1]:.2f} "
              f"(jackknife over samples); linear in ln N: {ln_n:.2f}, as 1/N: {inv_n:.2f}")


if __name__ == "__main__":
    main()
