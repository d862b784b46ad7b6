#!/usr/bin/env python3
"""How stable is the samples_needed estimate of the pooled pressure verdicts?

Draws resamples of a stored result's runs (K of each ensemble's S samples, without
replacement), judges each with `jam check finite_size` and `jam check phi_init`, and compares,
verdict by verdict, the spread of two estimates over the resamples:

  - the verdict's own band (the former estimate, margin.hpp): n (excluded_above / M)^2 when
    |D| < M, from one verdict's permutation band;
  - the window scatter pooled over neighbouring rates (checks/window_scatter.hpp), the
    estimate jam gives now.

Prints, per check, the median over verdicts of the resamples' spread of ln(estimate) (its
standard deviation; 0.5 means a factor of about 1.65 either way) and writes the numbers as
JSON. Usage:

  scripts/samples_needed_stability.py reference/results/reduced-2d [--resamples 20] [--keep 8]
"""
import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from script_files import fail, refuse_same, write_text

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def resample(source, target, keep, rng):
    """A copy of stats.h5 whose ensembles keep `keep` of their samples (the same rows in
    every table of an ensemble)."""
    shutil.copyfile(source, target)
    with h5py.File(target, "r+") as f:
        for name, g in f["ensembles"].items():
            samples = int(g.attrs["samples"])
            rows = sorted(rng.sample(range(samples), min(keep, samples)))
            for part in ("constant_phi", "constant_z", "jamming"):
                if part not in g:
                    continue
                h = g[part]
                for key in list(h.keys()):
                    if key.endswith("_samples") or key == "sample_ids":
                        data = h[key][...]
                        # Rows of other length cannot be kept with the others: the copy would
                        # disagree with its own samples.
                        if data.ndim == 0 or data.shape[0] != samples:
                            fail(f"{source}: ensembles/{name}/{part}/{key} has shape "
                                 f"{data.shape}, but the ensemble has {samples} samples; "
                                 f"its rows cannot be resampled")
                        del h[key]
                        h.create_dataset(key, data=data[rows])
            g.attrs["samples"] = len(rows)
            if "jamming" in g:
                found = g["jamming/packing_fraction_samples"][...]
                g["jamming"].attrs["found"] = int(np.isfinite(found).sum())


def judged(jam, directory, check):
    out = os.path.join(directory, f"checks-{check}.json")
    subprocess.run([jam, "check", check, directory], stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    with open(out) as f:
        return json.load(f)["verdicts"]


def former_estimate(v):
    """margin.hpp's samples_to_decide for one pooled verdict, from its recorded values."""
    n = min(v["values"]["samples_a"], v["values"]["samples_b"])
    d, margin, bound = abs(v["values"]["difference"]), v["margin"], v["excluded_above"]
    threshold = v["threshold"]
    if d < margin:
        return max(math.ceil(n * (bound / margin) ** 2), n + 1)
    if threshold is None or not math.isfinite(threshold):
        return float("nan")
    return max(math.ceil(n * (threshold / d) ** 2), n + 1)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("result", help="a stored result directory (its stats.h5)")
    p.add_argument("--resamples", type=int, default=20)
    p.add_argument("--keep", type=int, default=8, help="samples kept per ensemble")
    p.add_argument("--jam", default=os.path.join(ROOT, "build", "jam"))
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", help="write the numbers here")
    a = p.parse_args()
    if a.json:
        refuse_same(a.json, "--json", os.path.join(a.result, "stats.h5"), "stats.h5")
    rng = random.Random(a.seed)
    estimates = {}  # (check, case) -> {"former": [...], "pooled": [...]}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.resamples):
            d = os.path.join(tmp, f"r{r}")
            os.mkdir(d)
            resample(os.path.join(a.result, "stats.h5"), os.path.join(d, "stats.h5"), a.keep, rng)
            for check in ("finite_size", "phi_init"):
                for v in judged(a.jam, d, check):
                    if v["check"] != check or "scatter_a" not in v.get("values", {}):
                        continue
                    e = estimates.setdefault((check, v["case"]), {"former": [], "pooled": []})
                    if v["status"] != "inconclusive":
                        continue  # both estimates are of undecided verdicts only
                    pooled = v["samples_needed"]
                    e["former"].append(former_estimate(v))
                    e["pooled"].append(pooled if pooled is not None else float("nan"))
            print(f"resample {r + 1} of {a.resamples}", file=sys.stderr)

    def spread(xs):
        xs = [math.log(x) for x in xs if x is not None and math.isfinite(x) and x > 0]
        return float(np.std(xs, ddof=1)) if len(xs) >= 5 else None

    summary = {}
    for kind in ("finite_size", "phi_init"):
        rows = [(spread(e["former"]), spread(e["pooled"])) for (c, _), e in estimates.items()
                if c == kind]
        rows = [(f, q) for f, q in rows if f is not None and q is not None]
        if not rows:
            continue
        former = float(np.median([f for f, _ in rows]))
        pooled = float(np.median([q for _, q in rows]))
        summary[kind] = {"verdicts": len(rows), "former_median_sd_ln": former,
                         "pooled_median_sd_ln": pooled}
        print(f"{kind}: {len(rows)} verdicts; median SD of ln(samples_needed) over "
              f"{a.resamples} resamples of {a.keep} samples: former {former:.2f}, "
              f"pooled {pooled:.2f}")
    if a.json:
        write_text(a.json, json.dumps({"result": a.result, "resamples": a.resamples,
                                       "keep": a.keep, "summary": summary}, indent=1))


if __name__ == "__main__":
    main()
