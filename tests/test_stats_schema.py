"""stats.h5 has one schema (reference/schema/stats.toml) and two readers that check it: jam
(stats/stats_schema.cpp, through `jam validate --stats`; the checks' reader and `jam stats
--refit` check the same on opening) and jamio (python/jamio/stats_schema.py, behind
jamio.load_stats). The same corpus goes to both: every stored reference/results/*/*stats.h5, a
small one made here, and files the test plants, each one field off. The test fails when they
disagree on any file (one accepts what the other refuses, or they name another field), and
each case states which it is, so that a rule lost from the schema, or from both readers, fails
too. Planted files have their `checksum` taken out: the schema is judged, not the seal (one
case keeps it: a value changed after the seal is refused by both).

    /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/test_stats_schema.py \
        --jam build/jam --source .
"""

import copy
import re
import shutil
import subprocess

import h5py
import numpy as np
import pytest

import jamio
import schema_agreement
from jamio import stats_schema

CAMPAIGN = """name = "schema"
dim = 2
sizes = [16]
phi_init = [0.7]
log10_rates = [-1.5, -2.0, -2.5]
samples = 3
phi_stop = 0.86
phi_step = 0.002
dt = 0.02
seed = 3
output = "{output}"
"""

E = "ensembles/n16_phi0.7000_r-2.00"  # an ensemble of the fresh file
REP = "fit/representative"  # of the stored reduced-3d file
FAMILY = "fit/families/n256_phi0.4000"  # one of its families


def run(jam, *args):
    r = subprocess.run([str(jam), *map(str, args)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, f"jam {' '.join(map(str, args))}: {r.stdout}{r.stderr}"


@pytest.fixture(scope="module")
def fresh(jam, tmp_path_factory):
    """stats.h5 of a campaign of 9 tiny runs (three rates: the fit's scan is written)."""
    work = tmp_path_factory.mktemp("stats-schema")
    (work / "s.toml").write_text(CAMPAIGN.format(output=work / "out"))
    run(jam, "campaign", "run", "--quiet", "--jobs", "1", work / "s.toml")
    run(jam, "stats", work / "out")
    return work / "out" / "stats.h5"


def jam_says(jam, path):
    return schema_agreement.jam_says(jam, "stats", path)


def jamio_says(path):
    return schema_agreement.jamio_says(jamio.load_stats, jamio.JamioError, path)


def named(message):
    """(kind, object, name) a refusal names, paths without their leading slash (jam writes
    'ensembles/a', jamio '/ensembles/a'); None where it names none."""
    m = re.search(r"(attribute|dataset|group) '([^']*)'(?: of '([^']*)')?", message)
    if m:
        kind, name, obj = m.groups()
        return kind, (obj or "/").strip("/"), name.strip("/")
    m = re.search(r"'([^']*)' is not a group", message)
    return ("group", "", m.group(1).strip("/")) if m else None


def disagreement(jam_answer, jamio_answer, valid):
    """Why the two answers (ok, message) do not agree with each other and with `valid`, or
    None when they do."""
    (jam_ok, jam_words), (py_ok, py_words) = jam_answer, jamio_answer
    both = f"jam: {jam_words} | jamio: {py_words}"
    if jam_ok != py_ok:
        return "one accepts what the other refuses: " + both
    if jam_ok != valid:
        return f"both {'accept' if jam_ok else 'refuse'}, the case says otherwise: " + both
    if not valid and (named(jam_words) is None or named(jam_words) != named(py_words)):
        return "they name another field: " + both
    return None


# --- The planted files: each a copy of a valid one, changed by one edit with h5py. ---

def set_attr(obj, name, value):
    def edit(f):
        f[obj].attrs[name] = value
    return edit


def del_attr(obj, name):
    def edit(f):
        del f[obj].attrs[name]
    return edit


def replace(path, data):
    def edit(f):
        del f[path]
        f[path] = data
    return edit


def delete(path):
    def edit(f):
        del f[path]
    return edit


def change(path, function):
    """The dataset at `path` replaced by function(its values)."""
    def edit(f):
        values = function(f[path][()].copy())
        units = f[path].attrs.get("units")
        del f[path]
        f[path] = values
        if units is not None:
            f[path].attrs["units"] = units
    return edit


def at(index, value):
    def function(a):
        a.reshape(-1)[index] = value
        return a
    return function


def strip_units(f):
    f.visititems(lambda n, o: o.attrs.__delitem__("units")
                 if isinstance(o, h5py.Dataset) and "units" in o.attrs else None)


# (name, valid, base: "fresh" or "reduced-3d", edit)
CASES = [
    ("as_written_no_checksum", True, "fresh", lambda f: None),
    ("no_schema_version", True, "fresh", del_attr("/", "schema_version")),
    ("no_dataset_units", True, "fresh", strip_units),
    ("no_coverage", True, "fresh", delete(E + "/coverage")),
    ("no_constant_z", True, "fresh", delete(E + "/constant_z")),
    ("no_fit", True, "fresh", delete("fit")),
    ("unknown_attribute_kept", True, "fresh", set_attr("/", "added_later", 5)),
    ("unknown_group_kept", True, "fresh", lambda f: f.create_group("added_later/x")),
    ("integer_float_attribute", True, "fresh", set_attr("/", "z_step", np.int64(1))),
    ("failed_family_with_failure_only", True, "reduced-3d",
     lambda f: [f[FAMILY].attrs.__delitem__(k) for k in list(f[FAMILY].attrs)
                if k not in ("n", "family_phi_init")]
     + [f[FAMILY].attrs.__setitem__("failure", "too few points")]),
    ("schema_version_2", False, "fresh", set_attr("/", "schema_version", 2)),
    ("schema_version_text", False, "fresh", set_attr("/", "schema_version", "1")),
    ("campaign_missing", False, "fresh", del_attr("/", "campaign")),
    ("version_missing", False, "fresh", del_attr("/", "version")),
    ("dim_4", False, "fresh", set_attr("/", "dim", 4)),
    ("dim_text", False, "fresh", set_attr("/", "dim", "2")),
    ("dim_real", False, "fresh", set_attr("/", "dim", 2.0)),
    ("dim_array", False, "fresh", set_attr("/", "dim", np.array([2, 2]))),
    ("runs_negative", False, "fresh", set_attr("/", "runs", -1)),
    ("pooled_sizes_2", False, "fresh", set_attr("/", "pooled_sizes", 2)),
    ("phi_step_nan", False, "fresh", set_attr("/", "phi_step", np.nan)),
    ("ensembles_missing", False, "fresh", delete("ensembles")),
    ("ensemble_a_dataset", False, "fresh", lambda f: f.create_dataset("ensembles/extra",
                                                                      data=[1.0])),
    ("n_missing", False, "fresh", del_attr(E, "n")),
    ("n_text", False, "fresh", set_attr(E, "n", "16")),
    ("phi_init_nan", False, "fresh", set_attr(E, "phi_init", np.nan)),
    ("constant_phi_missing", False, "fresh", delete(E + "/constant_phi")),
    ("pressure_samples_missing", False, "fresh", delete(E + "/constant_phi/pressure_samples")),
    ("pressure_mean_missing", False, "fresh", delete(E + "/constant_phi/pressure_mean")),
    ("pressure_samples_transposed", False, "fresh",
     change(E + "/constant_phi/pressure_samples", lambda a: a.T.copy())),
    ("pressure_samples_a_column_short", False, "fresh",
     change(E + "/constant_phi/pressure_samples", lambda a: a[:, :-1].copy())),
    ("pressure_samples_flat", False, "fresh",
     change(E + "/constant_phi/pressure_samples", lambda a: a.reshape(-1))),
    ("sample_ids_one_more", False, "fresh",
     change(E + "/constant_phi/sample_ids", lambda a: np.append(a, 9.0))),
    ("pressure_mean_integers", False, "fresh",
     change(E + "/constant_phi/pressure_mean", lambda a: a.astype(np.int64))),
    ("pressure_mean_text", False, "fresh",
     replace(E + "/constant_phi/pressure_mean", np.array([b"a", b"b"]))),
    ("pressure_mean_scalar", False, "fresh", replace(E + "/constant_phi/pressure_mean", 1.0)),
    ("grid_nan", False, "fresh", change(E + "/constant_phi/packing_fraction", at(3, np.nan))),
    ("pressure_samples_nan", False, "fresh",
     change(E + "/constant_phi/pressure_samples", at(5, np.nan))),
    ("z_pressure_samples_inf", False, "fresh",
     change(E + "/constant_z/pressure_samples", at(0, np.inf))),
    ("sample_id_fraction", False, "fresh",
     change(E + "/constant_phi/sample_ids", at(1, 1.5))),
    ("sample_id_nan", False, "fresh", change(E + "/constant_phi/sample_ids", at(0, np.nan))),
    ("constant_z_without_grid", False, "fresh", delete(E + "/constant_z/contacts_per_particle")),
    ("coverage_step_short", False, "fresh",
     change(E + "/coverage/packing_fraction_step", lambda a: a[:-1].copy())),
    ("pressure_unit_wrong", False, "fresh",
     set_attr(E + "/constant_phi/pressure_mean", "units", "1")),
    ("scan_chosen_2", False, "fresh", change("fit/scan/chosen", at(0, 2.0))),
    ("scan_rate_max_nan", False, "fresh", change("fit/scan/rate_max", at(1, np.nan))),
    ("scan_column_short", False, "fresh", change("fit_z/scan/q", lambda a: a[:-1].copy())),
    ("quality_maybe", False, "reduced-3d", set_attr(REP, "quality", "maybe")),
    ("representative_phi_j_missing", False, "reduced-3d", del_attr(REP, "phi_j")),
    ("plateau_3", False, "reduced-3d", set_attr(REP, "plateau", 3)),
    ("in_fit_half", False, "reduced-3d", change(REP + "/collapse/in_fit", at(2, 0.5))),
    ("collapse_x_short", False, "reduced-3d",
     change(REP + "/collapse/x", lambda a: a[:-1].copy())),
    ("family_beta_missing", False, "reduced-3d", del_attr(FAMILY, "beta")),
    ("papers_protocol_how_missing", False, "reduced-3d", del_attr("fit/papers_protocol", "how")),
    ("paper_phi_j_text", False, "reduced-3d", set_attr("paper", "phi_j", "0.84")),
]


def planted(source, fresh, tmp_path, name, base, edit):
    path = tmp_path / f"{name}.h5"
    shutil.copy(fresh if base == "fresh" else
                source / "reference/results" / base / "stats.h5", path)
    with h5py.File(path, "r+") as f:
        del f.attrs["checksum"]
        edit(f)
    return path


@pytest.mark.parametrize("name,valid,base,edit", CASES, ids=[c[0] for c in CASES])
def test_jam_and_jamio_agree_on_the_corpus(jam, source, fresh, tmp_path, name, valid, base,
                                           edit):
    path = planted(source, fresh, tmp_path, name, base, edit)
    why = disagreement(jam_says(jam, path), jamio_says(path), valid)
    assert why is None, why


def test_every_stored_stats_file_and_a_fresh_one_follow_the_schema(jam, source, fresh):
    files = sorted((source / "reference/results").glob("*/*stats.h5")) + [fresh]
    assert len(files) >= 6
    for path in files:
        why = disagreement(jam_says(jam, path), jamio_says(path), True)
        assert why is None, f"{path}: {why}"


def test_a_planted_disagreement_fails(jam, source, fresh, tmp_path, monkeypatch):
    """jamio given a schema that allows dim 4 disagrees with jam on such a file, and the
    comparison says so; so does a jamio that names another field."""
    path = planted(source, fresh, tmp_path, "dim_4", "fresh", set_attr("/", "dim", 4))
    loose = copy.deepcopy(stats_schema.SCHEMA)
    for rule in loose["group"][0]["attributes"]:
        if rule["name"] == "dim":
            rule["allowed"] = [2, 3, 4]
    monkeypatch.setattr(stats_schema, "SCHEMA", loose)
    why = disagreement(jam_says(jam, path), jamio_says(path), False)
    assert why is not None and "one accepts" in why, why
    other = (False, "dataset 'ensembles/x/constant_phi/pressure_mean' missing")
    why = disagreement(jam_says(jam, path), other, False)
    assert why is not None and "another field" in why, why


def test_jamio_computes_the_seal_jam_stored(jam, source, fresh, tmp_path):
    """python/jamio/content_checksum.py walks a file as jam does: its checksum of every stored
    sealed stats.h5 and of a fresh one is the one jam stored; a pressure changed by a part in
    1e12 (a change no schema sees) breaks the seal, and jam and jamio both refuse the file."""
    from jamio.content_checksum import content_checksum
    sealed = 0
    for stored in sorted((source / "reference/results").glob("*/*stats.h5")) + [fresh]:
        with h5py.File(stored, "r") as f:
            if "checksum" in f.attrs:
                sealed += 1
                assert content_checksum(f) == f.attrs["checksum"].decode(), stored
    assert sealed >= 4
    path = tmp_path / "edited.h5"
    shutil.copy(fresh, path)
    with h5py.File(path, "r+") as f:
        table = next(g for g in f["ensembles"].values())["constant_phi/pressure_mean"]
        table[0] = table[0] * (1 + 1e-12)
    for ok, why in (jam_says(jam, path), jamio_says(path)):
        assert not ok and "does not match the stored" in why, why


def test_jam_writes_the_version_the_schema_calls_current(fresh):
    schema = stats_schema.SCHEMA
    with h5py.File(fresh, "r") as f:
        assert f.attrs["schema_version"] == schema["file"]["current"]
    root = {r["name"]: r for r in schema["group"][0]["attributes"]}
    assert root["schema_version"]["allowed"] == schema["file"]["versions"]


def test_every_dimension_used_is_declared():
    schema = stats_schema.SCHEMA
    rules = [d for g in schema["group"] for d in g.get("datasets", [])]
    rules += [d for s in schema["sets"].values() for d in s.get("datasets", [])]
    used = {n for d in rules for n in d["shape"]}
    assert used == set(schema["dimensions"]), used ^ set(schema["dimensions"])
