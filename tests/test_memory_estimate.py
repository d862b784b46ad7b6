"""The run limits' memory estimate holds what a run really takes, and not much more.

sim/run/run_limits.cpp refuses a run whose estimated memory exceeds half the machine's, from the
bytes per particle measured for each integrator and dimension (sim/dynamics/integrator_list.hpp)
times a headroom, plus a figure per further thread (docs/stability-and-faults.md, "Limits of one
run"). Here each case is one whole `jam sim` process, its peak resident memory read by the
kernel (ru_maxrss of the waited child, in a fresh interpreter so that no other child enters the
maximum), at N = 2^18 less N = 256 (the process's own libraries and buffers, which the
per-particle term does not claim). jam's own estimate is read from its refusal of the same run at
N = 4e8 (printed to 3 digits). The measured bytes per particle must lie below the estimate's (an
estimate below would let a run be swapped out or killed instead of refused: the default
Chebyshev integrator took 296 B in 2D and 482 B in 3D where the old estimate said 256) and above
1/1.6 of it (an estimate far above would refuse runs the machine can hold).
"""
import re
import subprocess
import sys

import pytest

MEASURE = """
import resource, subprocess, sys
done = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
if done.returncode != 0:
    sys.exit(done.stderr)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)  # KiB on Linux
"""

LARGE = 1 << 18
SMALL = 256
REFUSED = 400_000_000


def sim_args(jam, out, n, dim, integrator, threads):
    phi = 0.80 if dim == 2 else 0.60
    argv = [str(jam), "sim", "--quiet", "--dim", str(dim), "--n", str(n), "--threads",
            str(threads), "--relax", "0", "--phi-init", str(phi), "--phi-stop", str(phi + 0.0005),
            "--phi-step", "0.0005", "--rate", "1e-2", "--out", str(out)]
    if integrator == "verlet":
        return argv + ["--dynamics", "inertial", "--dt", "0.001"]
    argv += ["--integrator", integrator]
    return argv + ([] if integrator == "chebyshev" else ["--dt", "0.005"])


def peak_kib(argv):
    """The peak resident memory of one whole process, in KiB."""
    done = subprocess.run([sys.executable, "-c", MEASURE, *argv], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    return int(done.stdout.strip())


def estimated_bytes_per_particle(jam, tmp_path, dim, integrator, threads):
    """jam's estimate, from its refusal of the run at N = REFUSED."""
    out = tmp_path / "refused.h5"
    done = subprocess.run(sim_args(jam, out, REFUSED, dim, integrator, threads),
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2, done.stderr
    assert not out.exists()
    found = re.search(r"an estimated ([0-9.e+]+) GB of memory", done.stderr)
    assert found, done.stderr
    return float(found.group(1)) * 1e9 / REFUSED


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("integrator", ["euler", "heun", "chebyshev", "verlet"])
def test_the_estimate_covers_the_measured_memory(jam, tmp_path, integrator, dim, threads):
    large = peak_kib(sim_args(jam, tmp_path / "large.h5", LARGE, dim, integrator, threads))
    small = peak_kib(sim_args(jam, tmp_path / "small.h5", SMALL, dim, integrator, threads))
    measured = (large - small) * 1024 / (LARGE - SMALL)
    estimated = estimated_bytes_per_particle(jam, tmp_path, dim, integrator, threads)
    assert measured < estimated, f"measured {measured:.0f} B per particle, estimated {estimated:.0f}"
    assert measured > estimated / 1.6, (
        f"measured {measured:.0f} B per particle, estimated {estimated:.0f}")
