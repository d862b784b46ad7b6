"""A run's nominal coordinates and the output grid as exact values.

A run file records what its run reached. Its `phi_init` is the packing of the box at t = 0:
the campaign's 0.6 comes back as 0.5999999999999998 for one sample and 0.6 for the next, and a
chained run's is the packing it continued from. Each `packing_fraction` is where an output
point was taken: within round-off of its grid value when the integrator ends a step on it
(chebyshev), past it by less than one step's growth with fixed steps (output_times and
advance() in sim/run/compression_run.cpp). Grouping on those floats splits one grid point into
several. Here each run takes the campaign file's values, and each point the grid value it was
taken for, or a JamioError naming the run and the value.

Grid values are k * phi_step computed in decimal from phi_step as the campaign file writes it
(the shortest text that gives its float), then rounded once to a float: 351 * 0.002 is the
float 0.702, which prints as 0.702 and equals the literal, where 351 * 0.002 in binary is one
unit in the last place off for some k. The start phi_init and phi_stop are the file's values.
"""

from __future__ import annotations

import functools
import math
import re
from decimal import Decimal

import numpy as np

from .errors import JamioError, shown
from .open_run import SCHEMA

# The relative difference taken as round-off between a value and the one it stands for: jam's
# grid uses the same slack (output_times in sim/run/compression_run.cpp, interpolate() in
# stats/averages.cpp). Values a run reached differ from the grid by about 1e-16 relative.
ROUND_OFF = 1e-12
# Integrators that end a step on each output point (they choose their own steps), so their
# points are on the grid to round-off; the others take fixed steps of `dt`. From jam's own
# integrator list (sim/dynamics/integrator_list.hpp), as the schema file states it.
ENDS_STEPS_ON_GRID = tuple(name for name, i in SCHEMA.integrators.items() if i["adaptive"])


@functools.lru_cache(maxsize=1 << 16)  # a campaign's runs share their grid values
def grid_value(k, step):
    """k * step, computed in decimal from step's shortest text, rounded once to a float."""
    return float(Decimal(int(k)) * Decimal(repr(float(step))))


def _close(value, exact, allowed_above=0.0):
    """value within round-off below `exact`, or up to `allowed_above` (absolute) past it."""
    slack = ROUND_OFF * abs(exact)
    return -slack <= value - exact <= allowed_above + slack


def snap(values, step, path, what):
    """Grid values k * step for `values` that are multiples of step to round-off (stats.h5's
    grids, written as k * step in binary); a JamioError naming `what` and the first value that
    is not."""
    values = np.asarray(values, dtype=np.float64)
    out = np.empty_like(values)
    for i, v in enumerate(values):
        g = grid_value(round(v / step), step) if math.isfinite(v) else math.nan
        if not _close(v, g):
            raise JamioError(path, f"{what}[{i}] = {v!r} is not on the grid of step {step!r} "
                                   f"(nearest {g!r})")
        out[i] = g
    return out


def _planned(run):
    """The run's planned phi_init and rate: its fingerprint's (the campaign's values with 17
    digits) in a schema 2 file, which a chained run needs (its phi_init attribute is where it
    continued from), else its attributes."""
    fingerprint = run.attrs.get("fingerprint")
    words = dict(w.split("=", 1) for w in str(fingerprint or "").split() if "=" in w)
    try:
        return float(words["phi_init"]), float(words["rate"])
    except (KeyError, ValueError):
        return float(run.attrs["phi_init"]), float(run.attrs["compression_rate"])


def _nominal(run, value, candidates, what, absolute=False):
    """The campaign value `value` stands for (within round-off), or a JamioError."""
    for c in candidates:
        if abs(value - c) <= ROUND_OFF * (1.0 if absolute else abs(c)):
            return c
    raise JamioError(run.path, f"{what} {value!r} is none of the campaign's "
                               f"{list(candidates)}")


def _sample(run):
    sample = run.attrs.get("sample")
    if sample is not None:
        return int(sample)
    m = re.search(r"_s(\d+)$", run.name)  # files written before `sample`: the run's name
    if m is None:
        raise JamioError(run.path, "has no attribute 'sample' and its name ends in no _s<k>")
    return int(m[1])


def run_coordinates(run, design):
    """(n, phi_init, log10_rate, sample) of a run, the first three as the campaign file gives
    them."""
    n = int(run.attrs["n"])
    if n not in design.sizes:
        raise JamioError(run.path, f"n {n} is none of the campaign's sizes {list(design.sizes)}")
    phi_init, rate = _planned(run)
    if not rate > 0:
        raise JamioError(run.path, f"compression rate {rate!r} is not positive")
    return (n, _nominal(run, phi_init, design.phi_init, "phi_init"),
            _nominal(run, math.log10(rate), design.log10_rates, "log10 rate", absolute=True),
            _sample(run))


def _step_growth(run, rate, dim):
    """The most a point may lie past its grid value, relative: none when the integrator ends
    its steps on the grid; one step of `dt` at `rate` with fixed steps (phi grows by
    exp(D rate dt) per step)."""
    if run.attrs.get("integrator") in ENDS_STEPS_ON_GRID:
        return 0.0, "the integrator ends a step on each grid value"
    dt = float(run.attrs.get("dt", math.nan))
    growth = math.expm1(dim * rate * dt)
    return growth, f"one step of dt {dt:g} at rate {rate:.3g}"


def _off_grid(run, i, v, g, allowed, why):
    limit = (f"at most {allowed:.3g} past its grid value" if allowed > 0
             else "on its grid value to round-off")
    return JamioError(run.path, f"packing_fraction[{i}] = {v!r} is off the campaign's output "
                                f"grid: {v - g:+.3g} from grid value {g!r}, where a point lies "
                                f"{limit} ({why})")


NO_DESIGN = "and the campaign file gives none"


def positive_attribute(path, attributes, name, missing):
    """attributes[name] of the file `path` as a float, a number > 0 (a grid's step or end); a
    JamioError naming it otherwise (`missing`: what the error says when it is absent)."""
    v = attributes.get(name)
    if v is None:
        raise JamioError(path, f"has no attribute '{name}' ({missing})")
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
        raise JamioError(path, f"attribute '{name}' is {shown(v)}, expected a number > 0")
    return float(v)


def run_grid(run, design, phi_init, log10_rate):
    """The grid value of each output point of `run`: the start (phi_init, or a chained rate's
    chain_phi_init), then multiples of phi_step, then phi_stop."""
    v = np.asarray(run["packing_fraction"], dtype=np.float64)
    step = design.phi_step or positive_attribute(run.path, run.attrs, "phi_step", NO_DESIGN)
    stop = design.phi_stop or positive_attribute(run.path, run.attrs, "phi_stop", NO_DESIGN)
    dim = int(run.attrs.get("dim", design.dim))
    growth, why = _step_growth(run, 10.0 ** log10_rate, dim)
    chain = design.chain_phi_init.get(log10_rate)
    # A chained run starts where a faster run of its sample took its point: past the grid by
    # up to one of that run's steps (the campaign's fastest rate bounds it).
    start, start_growth, start_why = (phi_init, 0.0, "the start is the campaign's phi_init")
    if chain is not None:
        start = chain
        start_growth, start_why = _step_growth(run, 10.0 ** max(design.log10_rates), dim)
    out = np.empty_like(v)
    for i, x in enumerate(v):
        if i == 0:
            g, allowed, reason = start, start_growth * start, start_why
        elif i == len(v) - 1:
            g, allowed, reason = stop, 0.0, "the last point is phi_stop"
        else:
            g = grid_value(math.floor(x * (1 + ROUND_OFF) / step), step)
            allowed, reason = growth * g, why
        if not math.isfinite(x) or not _close(x, g, allowed):
            raise _off_grid(run, i, x, g, allowed, reason)
        out[i] = g
    same = np.flatnonzero(np.diff(out) <= 0)
    if same.size:
        i = int(same[0]) + 1
        raise JamioError(run.path, f"packing_fraction[{i}] = {v[i]!r} falls on grid value "
                                   f"{out[i]!r}, which an earlier point already has")
    return out


def external_grid(path, values, step, phi_init):
    """The `phi` of each output point of an open run (external campaigns, whose points need
    not lie on any grid): the grid value k * step when the point is one to round-off, else the
    ensemble's nominal phi_init when it is that, else the packing fraction as the run wrote it.
    Runs that share a grid then share its values; a JamioError naming the run when two points
    come to the same value."""
    v = np.asarray(values, dtype=np.float64)
    out = v.copy()
    # Only points near k * step in binary can be a grid value (a run of another code has
    # thousands of points, most of them off the grid).
    near = np.abs(v - np.round(v / step) * step) <= 4 * ROUND_OFF * np.abs(v)
    for i in np.flatnonzero(near | (np.abs(v - phi_init) <= 4 * ROUND_OFF * abs(phi_init))):
        x = float(v[i])
        g = grid_value(round(x / step), step)
        if _close(x, g):
            out[i] = g
        elif _close(x, phi_init):
            out[i] = phi_init
    same = np.flatnonzero(np.diff(out) <= 0)
    if same.size:
        i = int(same[0]) + 1
        raise JamioError(path, f"packing_fraction[{i}] = {v[i]!r} comes to {out[i]!r}, which "
                               "an earlier point already has")
    return out
