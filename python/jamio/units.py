"""The units of what jam writes, for the tables jamio builds and for files that do not state
them: run files of schema 1 and stats.h5 written before its datasets carried `units`.

Every number jam writes is in the paper's units (docs/model.md): lengths in d_s (the small
diameter), energies in k_e (the contact stiffness: U = (k_e/2)(1 - r/d)^2 for a harmonic
contact), times in t0 = (D/2) k_d V_s d_s^2 / k_e; a pressure is then in k_e/d_s^D (an energy
per volume), a rate in 1/t0. The strings are the ones jam writes (sim/io/run_file.cpp,
stats/stats_file.cpp), so a unit from a file and one from this table compare equal.
"""

from __future__ import annotations

NUMBER = "1"  # dimensionless: packing fractions, Z, fractions, counts, sample numbers
PRESSURE = "k_e/d_s^D"
ENERGY = "k_e"
TIME = "t0"
RATE = "1/t0"
LOG10_RATE = "log10(1/t0)"  # log10 of the rate in units of 1/t0

# Run files' datasets (as sim/io/run_file.cpp labels them) and the coordinates of the tables.
RUN_UNITS = {
    "packing_fraction": NUMBER, "pressure": PRESSURE, "contacts_per_particle": NUMBER,
    "energy_per_particle": ENERGY, "time": TIME, "contacts_per_particle_no_rattlers": NUMBER,
    "rattler_fraction": NUMBER, "stress": PRESSURE,
}
COORDINATE_UNITS = {
    "n": NUMBER, "phi_init": NUMBER, "log10_rate": LOG10_RATE, "compression_rate": RATE,
    "sample": NUMBER, "seed": NUMBER, "phi": NUMBER, "z": NUMBER, "samples": NUMBER,
}

# stats.h5 datasets named by what they hold (stats/stats_file.cpp): the collapse's axes
# x = (phi - phi_J)/rate^(1/(z nu)) and p/rate^q carry the fit's exponents.
STATS_UNITS = {
    "sample_ids": NUMBER, "compression_rate": RATE, "rate_max": RATE,
    "x": "t0^(1/(z nu))", "scaled_pressure": "k_e/d_s^D t0^q",
    "scaled_pressure_error": "k_e/d_s^D t0^q",
}
# Suffixes of the averaged observables' datasets that keep the observable's unit.
_SAME_UNIT = ("_mean", "_error", "_samples")


def unit_of(name):
    """The unit of a dataset or column named `name` (a run file's series, a stats.h5 dataset
    such as `pressure_mean` or `pressure_relative_error`, a table's coordinate); NUMBER for
    the stats.h5 datasets that are numbers (exponents, chi^2, flags, coefficients)."""
    for table in (COORDINATE_UNITS, RUN_UNITS, STATS_UNITS):
        if name in table:
            return table[name]
    if name.endswith("_relative_error"):
        return NUMBER
    for suffix in _SAME_UNIT:
        if name.endswith(suffix) and name[: -len(suffix)] in RUN_UNITS:
            return RUN_UNITS[name[: -len(suffix)]]
    return NUMBER


def column_units(columns, stated=None):
    """(units, source) for a table's columns: each numeric column's unit as the file states it
    (`stated`: name -> unit), else from this table; `source` says which, in words."""
    stated = stated or {}
    units = {c: stated.get(c, unit_of(c)) for c in columns if c != "run"}
    from_table = sorted(c for c in units if c not in stated and c not in COORDINATE_UNITS)
    if not from_table:
        source = "the files"
    elif len(from_table) == len([c for c in units if c not in COORDINATE_UNITS]):
        source = "jamio's table (the files state no units: written before they did)"
    else:
        source = f"the files; jamio's table for {', '.join(from_table)}"
    return units, source
