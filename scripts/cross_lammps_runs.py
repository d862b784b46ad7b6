#!/usr/bin/env python3
"""Runs one ensemble of LAMMPS compressions from LAMMPS's own random starts
(reference/lammps/compress_random.in), one lmp process at a time, for a cross-simulator
comparison: the thermo logs are read later by an importer.

    scripts/cross_lammps_runs.py --out /work/runs/cross-lammps/right --n 1024 --dim 2 \\
        --phi-init 0.75 --phi-stop 0.87 --rates -4 -5 --samples 10 --first-seed 1000 \\
        --q 0.1 --dt 0.016 --d-big 1.4 --stiffness 1

Sample k has seed first_seed + k. Its random start is relaxed once (mode relax:
DIR/starts/s<k>.data, log DIR/starts/s<k>.log) and compressed from there at every rate (mode
compress: DIR/r<log10 rate>/s<k>.log, e.g. r-4/s3.log; one thermo block, time 0 at phi_init).
Also written: DIR/contact.table (make_table.py for d_big and the stiffness, inner radius 1e-4 d
since random starts overlap deeply) and DIR/ensemble.json (the parameters, the argument vector
of every lmp process and its wall seconds; rewritten after each process).

Logs and starts are written as NAME.partial and renamed only when lmp exits 0 and its log ends
with "Total wall time": complete ones are skipped when the script runs again, so a killed
ensemble is resumed by repeating the command; a directory holding another ensemble's parameters
is refused. A failed process leaves NAME.failed and the script goes on (exit status 1 at the
end). Prints one line per compression: runs done, wall seconds, ETA. The thermo interval is
--every steps, or else chosen per rate so that the output spacing in phi is at most
--phi-spacing (0.00025) at phi_stop.
"""

import argparse
import datetime
import hashlib
import json
import math
import os
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

from script_files import fail

ROOT = Path(__file__).resolve().parent.parent
INPUT = ROOT / "reference" / "lammps" / "compress_random.in"
MAKE_TABLE = ROOT / "reference" / "lammps" / "make_table.py"
COMPLETE = b"Total wall time"
# Paths under --out reach LAMMPS as -var values substituted into read_data, write_data and
# pair_coeff, and LAMMPS splits words, reads quotes and substitutes $ after substitution.
UNSAFE_IN_OUT = "$#'\"`"
# The parameters that define an ensemble: a directory holding runs of other values is refused.
PHYSICS = ("n", "dim", "phi_init", "phi_stop", "q", "dt", "d_big", "stiffness", "relax_energy",
           "skin", "first_seed", "table_inner", "input_sha256")


def rate_label(log10_rate):
    return f"r{log10_rate:g}"


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def complete(log):
    """A log of a finished lmp process (it ends with "Total wall time")."""
    if not log.is_file():
        return False
    with open(log, "rb") as f:
        f.seek(0, os.SEEK_END)
        f.seek(max(0, f.tell() - 4096))
        return COMPLETE in f.read()


def write_atomic(path, text):
    tmp = path.with_name(path.name + ".partial")
    tmp.write_text(text)
    os.replace(tmp, path)


def partial(path):
    return path.with_name(path.name + ".partial")


def steps_for(a, rate):
    """The input's step count: ceil(ln(phi_stop/phi_init) / (D rate dt))."""
    return math.ceil(math.log(a.phi_stop / a.phi_init) / (a.dim * rate * a.dt))


def every_for(a, rate):
    if a.every is not None:
        return a.every
    return max(1, round(a.phi_spacing / (a.dim * rate * a.dt * a.phi_stop)))


class Child:
    """The running lmp process, so that SIGTERM/SIGINT end it too (its log stays .partial)."""
    process = None


def on_signal(signum, frame):
    if Child.process is not None and Child.process.poll() is None:
        Child.process.terminate()
        try:
            Child.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            Child.process.kill()
    sys.exit(128 + signum)


def lammps_version(lmp):
    try:
        out = subprocess.run([lmp, "-h"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        sys.exit(f"cross_lammps_runs: cannot run {lmp}: {e}")
    for line in out.splitlines():  # "Large-scale ... Simulator - 29 Sep 2021 - Update 2"
        if "Simulator - " in line:
            return f"LAMMPS ({line.split('Simulator - ', 1)[1].strip()})"
    return ""


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, required=True, help="ensemble directory")
    p.add_argument("--n", type=int, default=1024)
    p.add_argument("--dim", type=int, choices=(2, 3), default=2)
    p.add_argument("--phi-init", type=float, default=0.75)
    p.add_argument("--phi-stop", type=float, default=0.87)
    p.add_argument("--rates", type=float, nargs="+", required=True,
                   help="log10 of the compression rates, e.g. -4 -5 (run in this order)")
    p.add_argument("--samples", type=int, default=10)
    p.add_argument("--first-sample", type=int, default=0)
    p.add_argument("--first-seed", type=int, default=1000, help="seed of sample k: first_seed + k")
    p.add_argument("--q", type=float, required=True, help="quality factor (0.1: overdamped to 1e-4)")
    p.add_argument("--dt", type=float, required=True, help="time step, below 4 Q^2 / D")
    p.add_argument("--d-big", type=float, default=1.4, help="big diameter of the contacts")
    p.add_argument("--stiffness", type=float, default=1.0, help="contact stiffness k_e")
    p.add_argument("--every", type=int, help="thermo interval in steps (all rates)")
    p.add_argument("--phi-spacing", type=float, default=0.00025,
                   help="largest output spacing in phi when --every is not given")
    p.add_argument("--relax-energy", type=float, default=1e-14,
                   help="relax each start until the energy per particle is below this")
    p.add_argument("--skin", type=float, default=0.3)
    p.add_argument("--table-inner", type=float, default=1e-4,
                   help="inner radius of the contact table, a fraction of d_ij")
    p.add_argument("--lmp", default="lmp")
    a = p.parse_args()
    out = str(a.out.resolve())
    if any(c.isspace() or c in UNSAFE_IN_OUT for c in out):
        given = repr(str(a.out)) + ("" if out == str(a.out) else f" ({out!r})")
        fail(f"--out {given}: holds whitespace or one of {UNSAFE_IN_OUT}, which LAMMPS would "
             f"split or substitute in its commands; choose a path without them")
    if a.n < 2 or a.n % 2 or not 0 < a.phi_init < a.phi_stop < 1 or a.samples < 1:
        sys.exit("cross_lammps_runs: need even n >= 2, 0 < phi_init < phi_stop < 1, samples >= 1")
    if a.first_seed + a.first_sample < 1 or a.first_sample < 0:
        sys.exit("cross_lammps_runs: samples must be >= 0 and seeds >= 1 (LAMMPS)")
    if not 0 < a.dt < 4 * a.q ** 2 / a.dim:
        sys.exit(f"cross_lammps_runs: dt {a.dt} is not below the drag bound 4 Q^2/D = "
                 f"{4 * a.q ** 2 / a.dim:g}")
    if a.every is not None and a.every < 1:
        sys.exit("cross_lammps_runs: --every must be >= 1")
    return a


class Ensemble:
    def __init__(self, a):
        self.a = a
        self.out = a.out.resolve()
        self.out.mkdir(parents=True, exist_ok=True)
        (self.out / "starts").mkdir(exist_ok=True)
        self.manifest = self.out / "ensemble.json"
        self.params = {
            "n": a.n, "dim": a.dim, "phi_init": a.phi_init, "phi_stop": a.phi_stop, "q": a.q,
            "dt": a.dt, "d_big": a.d_big, "stiffness": a.stiffness,
            "relax_energy": a.relax_energy, "skin": a.skin, "first_seed": a.first_seed,
            "table_inner": a.table_inner, "input": str(INPUT), "input_sha256": sha256(INPUT),
        }
        self.runs, self.starts = {}, {}
        if self.manifest.is_file():
            old = json.loads(self.manifest.read_text())
            differ = [k for k in PHYSICS if old["parameters"].get(k) != self.params[k]]
            if differ:
                sys.exit(f"cross_lammps_runs: {self.manifest} holds another ensemble (differs "
                         f"in {', '.join(differ)}); use another --out")
            self.runs = {(r["log10_rate"], r["sample"]): r for r in old.get("runs", [])}
            self.starts = {r["sample"]: r for r in old.get("starts", [])}
            self.rates = old.get("rates", {})
        else:
            self.rates = {}
        self.table = self.out / "contact.table"
        made = subprocess.run([sys.executable, str(MAKE_TABLE), repr(a.d_big), repr(a.stiffness),
                               repr(a.table_inner)], capture_output=True, text=True)
        if made.returncode != 0:
            sys.exit(f"cross_lammps_runs: make_table.py failed: {made.stderr.strip()}")
        if not self.table.is_file() or self.table.read_text() != made.stdout:
            write_atomic(self.table, made.stdout)
        self.params.update({"table": str(self.table), "table_sha256": sha256(self.table),
                            "lammps": lammps_version(a.lmp), "lmp": a.lmp,
                            "phi_spacing": None if a.every else a.phi_spacing})
        for x in a.rates:
            self.rates[rate_label(x)] = {"log10_rate": x, "rate": 10.0 ** x,
                                         "steps": steps_for(a, 10.0 ** x),
                                         "every": every_for(a, 10.0 ** x)}
        self.common = {"n": a.n, "dim": a.dim, "phi_init": repr(a.phi_init), "q": repr(a.q),
                       "dt": repr(a.dt), "d_big": repr(a.d_big), "table": str(self.table),
                       "skin": repr(a.skin)}

    def save(self):
        doc = {
            "what": "LAMMPS compressions from LAMMPS's own random starts "
                    "(reference/lammps/compress_random.in), by scripts/cross_lammps_runs.py",
            "parameters": self.params,
            "rates": self.rates,
            "starts": [self.starts[k] for k in sorted(self.starts)],
            "runs": [self.runs[key] for key in sorted(self.runs, key=lambda t: (-t[0], t[1]))],
        }
        write_atomic(self.manifest, json.dumps(doc, indent=1) + "\n")

    def lmp(self, mode, log, variables, renames):
        """Runs lmp in `mode` with its log at log.partial; when it completes, renames the log
        and each file of `renames` from its .partial name. Returns (record, failure text)."""
        command = [self.a.lmp, "-in", str(INPUT), "-log", str(partial(log)), "-screen", "none",
                   "-nocite", "-var", "mode", mode]
        for name, value in {**self.common, **variables}.items():
            command += ["-var", name, str(value)]
        began = time.monotonic()
        Child.process = subprocess.Popen(command, cwd=log.parent, stdin=subprocess.DEVNULL,
                                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                         env={**os.environ, "OMP_NUM_THREADS": "1"})
        output = Child.process.communicate()[0].decode(errors="replace")
        code = Child.process.returncode
        Child.process = None
        wall = time.monotonic() - began
        record = {"log": str(log), "wall_seconds": round(wall, 3), "exit_code": code,
                  "finished": datetime.datetime.now().isoformat(timespec="seconds")}
        ok = code == 0 and complete(partial(log)) and all(partial(f).is_file() for f in renames)
        if ok:
            for f in (*renames, log):
                os.replace(partial(f), f)
            final = {str(partial(f)): str(f) for f in (*renames, log)}
            record["command"] = [final.get(c, c) for c in command]
            record["status"] = "complete"
            return record, None
        if partial(log).is_file():
            os.replace(partial(log), log.with_name(log.name + ".failed"))
        record["command"] = command
        record["status"] = "failed"
        last = (output.strip().splitlines() or ["(no output)"])[-1]
        return record, f"FAILED (exit {code}; {log.name}.failed): {last}"

    def start(self, k):
        """The relaxed start of sample k, made if missing; None if relaxing it failed.
        Returns (path, wall seconds spent making it now or None)."""
        data = self.out / "starts" / f"s{k}.data"
        log = self.out / "starts" / f"s{k}.log"
        seed = self.a.first_seed + k
        if data.is_file() and complete(log):
            self.starts.setdefault(k, {"sample": k, "seed": seed, "data": str(data),
                                       "log": str(log), "status": "complete",
                                       "wall_seconds": None})
            return data, None
        record, failure = self.lmp("relax", log, {"seed": seed,
                                                  "relax_energy": repr(self.a.relax_energy),
                                                  "start": str(partial(data))}, [data])
        record.update({"sample": k, "seed": seed, "data": str(data)})
        self.starts[k] = record
        self.save()
        if failure is not None:
            print(f"relax s{k} seed {seed}: {failure}", flush=True)
            return None, record["wall_seconds"]
        return data, record["wall_seconds"]

    def eta(self, todo):
        """Seconds left: per rate the median wall of its done runs (other rates scaled by their
        steps), plus the median relaxation for each start still to make."""
        done = {}
        for r in self.runs.values():
            if r.get("status") == "complete" and r.get("wall_seconds"):
                done.setdefault(r["log10_rate"], []).append(r["wall_seconds"])
        if not done:
            return None
        per_step = statistics.median(statistics.median(w) / steps_for(self.a, 10.0 ** x)
                                     for x, w in done.items())
        relax = [r["wall_seconds"] for r in self.starts.values() if r.get("wall_seconds")]
        missing = {k for _, _, k in todo if self.starts.get(k, {}).get("status") != "complete"}
        return (sum(statistics.median(done[x]) if x in done
                    else per_step * steps_for(self.a, rate) for x, rate, _ in todo)
                + len(missing) * (statistics.median(relax) if relax else 0.0))

    def run(self):
        a = self.a
        plan = [(x, 10.0 ** x, k) for x in a.rates
                for k in range(a.first_sample, a.first_sample + a.samples)]
        self.save()
        failures = 0
        for index, (log10_rate, rate, k) in enumerate(plan):
            head = f"[{index + 1}/{len(plan)}] {rate_label(log10_rate)} s{k} seed {a.first_seed + k}"
            folder = self.out / rate_label(log10_rate)
            folder.mkdir(exist_ok=True)
            log = folder / f"s{k}.log"
            key = (log10_rate, k)
            if complete(log):
                self.runs.setdefault(key, {"log10_rate": log10_rate, "rate": rate, "sample": k,
                                           "seed": a.first_seed + k, "log": str(log),
                                           "status": "complete", "wall_seconds": None})
                print(f"{head}: complete log exists, skipped", flush=True)
                continue
            data, relax_wall = self.start(k)
            if data is None:
                failures += 1
                continue
            every = every_for(a, rate)
            record, failure = self.lmp("compress", log, {
                "phi_stop": repr(a.phi_stop), "rate": repr(rate), "every": every,
                "start": str(data)}, [])
            record.update({"log10_rate": log10_rate, "rate": rate, "sample": k,
                           "seed": a.first_seed + k, "steps": steps_for(a, rate),
                           "every": every, "start": str(data)})
            self.runs[key] = record
            self.save()
            if failure is not None:
                failures += 1
                status = failure
            else:
                status = f"{record['wall_seconds']:.1f} s"
            if relax_wall is not None:
                status += f" (+ {relax_wall:.1f} s relaxing the start)"
            left = self.eta(plan[index + 1:])
            done = sum(1 for r in self.runs.values() if r.get("status") == "complete")
            print(f"{head}: {status}; {done} runs complete in {self.out.name}; ETA "
                  f"{'?' if left is None else f'{left / 60:.1f} min'} "
                  f"({datetime.datetime.now():%H:%M:%S})", flush=True)
        self.save()
        print(f"done: {self.out} ({failures} failed)", flush=True)
        return 1 if failures else 0


def main():
    a = parse_args()
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    return Ensemble(a).run()


if __name__ == "__main__":
    sys.exit(main())
