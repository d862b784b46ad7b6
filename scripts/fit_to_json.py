#!/usr/bin/python3
"""Copies the scaling fit of a stats.h5 (its fit/representative attributes and the fit/scan
table, reference/schema.md) into a small JSON file, for stored results that keep a second fit
without a second copy of the averaged curves:

    scripts/fit_to_json.py runs/reduced-2d/stats.h5 fit-free.json "jam stats --order 3"

The optional third argument says how the fit was made (stored as "source").

Nothing is computed: every number is read as stored.
"""

import json
import math
import sys

import h5py

from script_files import fail, refuse_same, require_input, write_text


def plain(value):
    """HDF5 attribute -> JSON value (NaN and inf as null)."""
    if isinstance(value, bytes):
        return value.decode()
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: fit_to_json.py STATS_H5 OUT_JSON [HOW]")
    source, target = sys.argv[1], sys.argv[2]
    how = sys.argv[3] if len(sys.argv) == 4 else source
    require_input(source, "STATS_H5")
    refuse_same(target, "OUT_JSON", source, "STATS_H5")
    with h5py.File(source, "r") as f:
        if "fit" not in f:
            sys.exit(f"fit_to_json.py: {source}: no fit group")
        fit = f["fit"]
        out = {"source": how, "fit": {k: plain(v) for k, v in fit.attrs.items()}}
        if "representative" in fit:
            rep = fit["representative"]
            out["representative"] = {k: plain(v) for k, v in rep.attrs.items()}
            out["representative"]["coefficients"] = [plain(c) for c in rep["coefficients"][()]]
        if "scan" in fit:
            scan = fit["scan"]
            out["scan"] = {k: [plain(x) for x in scan[k][()]] for k in scan.keys()}
            out["scan_failures"] = plain(scan.attrs.get("failures", ""))
    try:
        text = json.dumps(out, indent=1, sort_keys=True) + "\n"
    except (TypeError, ValueError) as e:
        fail(f"STATS_H5 {source}: the fit holds a value JSON cannot hold ({e})")
    write_text(target, text)


if __name__ == "__main__":
    main()
