#!/usr/bin/env python3
"""Time against error of the overdamped integrators at slow rates, judged on ensembles.

For each (dim, N, rate, seed): one relaxed start (Heun, dt 0.1, energy 1e-14 per particle),
written as LAMMPS data; then every method compresses that same start from phi_init to
phi_stop (`jam sim --read-lammps-data ... --relax 0`). The reference is Heun at a dt small
enough that halving it changes the ensemble mean by less than 0.1% (checked here: the
"reference/2" method). Errors are of the ensemble-mean pressure and Z at packings below, near
and above phi_J, relative, with the standard error of the paired per-sample differences.

Usage: measure.py OUT.csv --dim 2 --n 1024 --rates 1e-5 1e-6 --seeds 8 [--jobs 2]
Every run is an argument vector (no shell); runs already in the work directory are reused.
"""
import argparse, csv, os, subprocess, sys, time
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

JAM = os.environ.get("JAM", os.path.join(os.path.dirname(__file__), "..", "..", "build", "jam"))


def run(argv, out):
    if os.path.exists(out):
        return None
    t0 = time.monotonic()
    subprocess.run([JAM] + argv + ["--out", out, "--quiet", "--checkpoint-interval", "0"],
                   check=True, stdout=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    with open(out + ".wall", "w") as f:
        f.write(f"{wall}\n")
    return wall


def wall_of(out):
    with open(out + ".wall") as f:
        return float(f.read())


def curve(path, phis):
    with h5py.File(path, "r") as f:
        phi = f["packing_fraction"][:]
        p = f["pressure"][:]
        z = f["contacts_per_particle"][:]
    return np.interp(phis, phi, p), np.interp(phis, phi, z)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--dim", type=int, default=2)
    ap.add_argument("--n", type=int, default=1024)
    ap.add_argument("--rates", type=float, nargs="+", default=[1e-5])
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--work", default="cheb-work")
    ap.add_argument("--methods", nargs="+", default=None)
    ap.add_argument("--reference", default="reference",
                    help="the method errors are measured against (heun-0.1 at rates where "
                         "the reference shows it converged, to spare the dt 0.025 runs)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    d = a.dim
    phi_init, phi_stop = (0.80, 0.86) if d == 2 else (0.60, 0.67)
    probes = [0.83, 0.84, 0.85] if d == 2 else [0.63, 0.645, 0.66]  # below, near, above phi_J
    methods = {
        "reference": ["--integrator", "heun", "--dt", "0.025"],
        "reference/2": ["--integrator", "heun", "--dt", "0.05"],
        "heun-0.1": ["--integrator", "heun", "--dt", "0.1"],
        "euler-0.05": ["--integrator", "euler", "--dt", "0.05"],
        "cheb-1e-2": ["--integrator", "chebyshev", "--tolerance", "1e-2"],
        "cheb-1e-3": ["--integrator", "chebyshev", "--tolerance", "1e-3"],
        "cheb-1e-4": ["--integrator", "chebyshev", "--tolerance", "1e-4"],
        "cheb-1e-4-bound": ["--integrator", "chebyshev", "--tolerance", "1e-4",
                            "--stiffest-mode", "bound"],
        "cheb-auto": ["--integrator", "chebyshev"],
        "cheb-auto-bound": ["--integrator", "chebyshev", "--stiffest-mode", "bound"],
        "cheb-auto-rms": ["--integrator", "chebyshev", "--error-norm", "rms"],
        "cheb-1e-5-rms": ["--integrator", "chebyshev", "--tolerance", "1e-5", "--error-norm", "rms"],
        "cheb-1e-5": ["--integrator", "chebyshev", "--tolerance", "1e-5"],
        "cheb-1e-6": ["--integrator", "chebyshev", "--tolerance", "1e-6"],
    }
    if a.methods:
        methods = {k: v for k, v in methods.items() if k in a.methods or k == a.reference}
    base = ["sim", "--dim", str(d)]
    jobs = []  # one start per seed, shared by every rate
    for s in range(a.seeds):
        start = os.path.join(a.work, f"start_d{d}_n{a.n}_s{s}.data")
        jobs.append((0, base + ["--n", str(a.n), "--phi-init", str(phi_init), "--phi-stop", str(phi_init * 1.0001),
                                "--seed", str(100 + s), "--write-lammps-data", start],
                     os.path.join(a.work, f"start_d{d}_n{a.n}_s{s}.h5")))
    with ThreadPoolExecutor(a.jobs) as pool:
        list(pool.map(lambda j: run(j[1], j[2]), [j for j in jobs if not os.path.exists(j[2])]))
    runs = []
    for rate in a.rates:
        for name, extra in methods.items():
            for s in range(a.seeds):
                start = os.path.join(a.work, f"start_d{d}_n{a.n}_s{s}.data")
                out = os.path.join(a.work, f"d{d}_n{a.n}_r{rate:g}_{name.replace('/', '_')}_s{s}.h5")
                runs.append((base + ["--read-lammps-data", start, "--relax", "0", "--phi-stop",
                                     str(phi_stop), "--rate", str(rate)] + extra, out))
    # Longest first (slow rates, the reference) so that two workers finish together.
    runs.sort(key=lambda r: -float(r[0][r[0].index("--rate") + 1]) ** -1)
    with ThreadPoolExecutor(a.jobs) as pool:
        list(pool.map(lambda r: run(*r), runs))
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["dim", "n", "rate", "method", "samples", "wall_median_s", "speedup_vs_heun",
                    "phi", "dp_rel", "dp_rel_se", "dz", "dz_se"])
        for rate in a.rates:
            def files(name):
                return [os.path.join(a.work, f"d{d}_n{a.n}_r{rate:g}_{name.replace('/', '_')}_s{s}.h5")
                        for s in range(a.seeds)]
            ref = [curve(p, probes) for p in files(a.reference)]
            p_ref = np.array([r[0] for r in ref])
            z_ref = np.array([r[1] for r in ref])
            heun_wall = np.median([wall_of(p) for p in files("heun-0.1")]) if "heun-0.1" in methods else np.nan
            for name in methods:
                if name == a.reference:
                    continue
                c = [curve(p, probes) for p in files(name)]
                p = np.array([x[0] for x in c])
                z = np.array([x[1] for x in c])
                wall = np.median([wall_of(q) for q in files(name)])
                for k, phi in enumerate(probes):
                    # relative error of the ensemble mean, and the standard error of the paired
                    # per-sample differences (the same starts)
                    diff = p[:, k] - p_ref[:, k]
                    mean_ref = p_ref[:, k].mean()
                    dz = z[:, k] - z_ref[:, k]
                    n = len(diff)
                    w.writerow([d, a.n, rate, name, n, f"{wall:.3f}", f"{heun_wall / wall:.3f}", phi,
                                f"{diff.mean() / mean_ref:.2e}",
                                f"{diff.std(ddof=1) / np.sqrt(n) / mean_ref:.2e}",
                                f"{dz.mean():.2e}", f"{dz.std(ddof=1) / np.sqrt(n):.2e}"])
    print(open(a.out).read())


if __name__ == "__main__":
    sys.exit(main())
