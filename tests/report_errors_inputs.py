"""The cases of tests/test_report_errors.py about what a report reads: corrupt, truncated,
mistyped and hostile inputs, special files, and values beyond what a report shows."""

import json
import os
import shutil

import h5py
import numpy as np

from report_errors_fixture import (HOSTILE, campaign, expect_error, expect_inert, report,
                                   report_text, tree)


def case_random_stats(work):
    """stats.h5 is random bytes: fails before anything is drawn or created."""
    camp = campaign(work)
    with open(os.path.join(camp, "stats.h5"), "wb") as f:
        f.write(np.random.default_rng(1).bytes(65536))
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["stats.h5", "not a readable stats file"], before, work)


def case_missing_dataset(work):
    """stats.h5 is HDF5 but an ensemble lacks the pressure the figures draw."""
    camp = campaign(work)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        first = sorted(f["ensembles"])[0]
        del f[f"ensembles/{first}/constant_phi/pressure_mean"]
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["stats.h5", "pressure_mean", "missing"], before, work)


def case_truncated_checks(work):
    """checks.h5 cut to half its length, as a full disk or a crash leaves it."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.h5")
    os.truncate(path, os.path.getsize(path) // 2)
    before = tree(work)
    r = report(camp, os.path.join(work, "reports", "r"))
    expect_error(r, ["checks.h5", "not a readable checks file"], before, work)


def case_markup_in_a_number_of_the_fit_is_refused(work):
    """`iterations`, `points`, `samples` (and every other number of the fit) holding markup:
    one line naming the attribute, no report (they once reached the page unescaped)."""
    camp = campaign(work)
    stats = os.path.join(camp, "stats.h5")
    for name in ("iterations", "points", "samples", "phi_min", "chi2_diag_per_dof"):
        with h5py.File(stats, "r+") as f:
            rep = f["fit/representative"]
            kept = rep.attrs[name]
            rep.attrs[name] = HOSTILE
        before = tree(work)
        # iterations, points and samples are whole numbers (reference/schema/stats.toml).
        words = "not a number" if name in ("phi_min", "chi2_diag_per_dof") else "not a whole"
        expect_error(report(camp, os.path.join(work, "r")),
                     [stats, f"attribute '{name}'", words], before, work)
        with h5py.File(stats, "r+") as f:
            f["fit/representative"].attrs[name] = kept


def case_a_huge_case_name_gives_a_small_summary(work):
    """A 20 MB case name: shown shortened with its length, not padded into every row (a 50 MB
    one once made a 2 GB summary.txt)."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    checks["verdicts"][0]["case"] = "x" * 20_000_000
    if "table" in checks["verdicts"][0]:  # the cell the tables show, written by jam
        checks["verdicts"][0]["table"]["case"] = "x" * 20_000_000
    with open(path, "w") as f:
        json.dump(checks, f)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    for name in ("summary.txt", "index.html"):
        size = os.path.getsize(os.path.join(out, name))
        if size > 2_000_000:
            raise AssertionError(f"{name} is {size} bytes")
    if "(20000000 characters)" not in report_text(out)[1]:
        raise AssertionError("the shortened case does not say its length")


def case_mistyped_checks_fields(work):
    """A checks.json field of the wrong type: one line naming the file, the verdict, the field
    and the value, exit 2, no report (these once gave tracebacks)."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        original = json.load(f)
    for field, value, says in (("statistic", "abc", "field 'statistic' is 'abc', not a number"),
                               ("case", 42, "field 'case' is 42, not a string"),
                               ("margin", [1, 2], "field 'margin' is [1, 2], not a number"),
                               ("status", "maybe", "field 'status' is 'maybe'"),
                               ("expected_failure", "yes",
                                "field 'expected_failure' is 'yes', not true or false"),
                               ("values", "none", "field 'values' is 'none', not an object")):
        checks = json.loads(json.dumps(original))
        checks["verdicts"][3][field] = value
        with open(path, "w") as f:
            json.dump(checks, f)
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r")), [path, "verdict 3", says], before,
                     work)


HOSTILE_ALL = '<script>alert(1)</script>"onerror=alert(2) \x00\x1b[31m $\\frac{1}$'


def hostile_bytes(text):
    """text as a fixed-length HDF5 string (a variable-length one cannot hold a NUL)."""
    return np.bytes_(text.encode("utf-8"))


def write_lammps_curves(camp):
    """Curves for the LAMMPS verdicts in checks.h5, so the LAMMPS figure (whose panels are
    titled with the case) is drawn."""
    grid = np.linspace(0.80, 0.86, 20)
    with h5py.File(os.path.join(camp, "checks.h5"), "r+") as f:
        for g in f["verdicts"].values():
            if g.attrs["check"] == "lammps":
                for key in ("grid", "pressure_jam", "pressure_lammps", "delta", "sigma"):
                    g[key] = 0.01 * grid + 0.001


def make_every_field_hostile(camp):
    """HOSTILE_ALL in every string of checks.json, checks.h5, stats.h5, manifest.toml and
    campaign.toml that the report reads; check names changed alike in checks.json, its
    registry and checks.h5, so every figure is still drawn."""
    write_lammps_curves(camp)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        checks = json.load(f)
    for key in ("campaign", "code_version", "created"):
        checks[key] = HOSTILE_ALL
    for entry in checks["checks"]:
        entry["name"] += HOSTILE_ALL
        entry["margin_reason"] = HOSTILE_ALL
    for v in checks["verdicts"]:
        v["check"] += HOSTILE_ALL
        for key in ("case", "reason", "statistic_name"):
            v[key] = v[key] + HOSTILE_ALL
        # `values` holds numbers only (reference/schema/checks.toml): a string there is refused
        # by name (mistyped_stats_and_values_fields), so none is planted here.
    with open(path, "w") as f:
        json.dump(checks, f)
    with h5py.File(os.path.join(camp, "checks.h5"), "r+") as f:
        f.attrs["version"] = hostile_bytes(HOSTILE_ALL)
        for g in f["verdicts"].values():
            for key in ("check", "case"):
                g.attrs[key] = hostile_bytes(g.attrs[key] + HOSTILE_ALL)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        # Both kinds of HDF5 string: variable-length (h5py's for a str; it cannot hold a NUL,
        # so it gets the text without one) on the file and on every other attribute of the
        # representative fit, fixed-length (hostile_bytes) on the rest.
        for key in ("campaign", "version"):
            f.attrs[key] = HOSTILE_ALL.replace("\x00", "")
        for key in ("rates_note", "failure"):
            f["fit"].attrs[key] = hostile_bytes(HOSTILE_ALL)
        # `quality` is ok or poor (reference/schema/stats.toml): another value is refused by
        # name, so none is planted there.
        for k, key in enumerate(("quality_reason", "fixed", "start", "chosen_because",
                                 "error_method")):
            f["fit/representative"].attrs[key] = (HOSTILE_ALL.replace("\x00", "") if k % 2
                                                  else hostile_bytes(HOSTILE_ALL))
        f["fit/scan"].attrs["failures"] = hostile_bytes("row 1: " + HOSTILE_ALL)
    with open(os.path.join(camp, "manifest.toml"), "w") as f:
        f.write(f"campaign_file = {json.dumps(HOSTILE_ALL)}\n"
                f"code_version = {json.dumps(HOSTILE_ALL)}\n")
    with open(os.path.join(camp, "campaign.toml"), "a") as f:
        f.write("# " + HOSTILE_ALL + "\n")


def expect_inert_svg(path):
    """An SVG that is well-formed XML, with no script element, no on* attribute and no
    control character."""
    import xml.etree.ElementTree as ET
    with open(path, "rb") as f:
        data = f.read()
    if b"\x00" in data or b"\x1b" in data:
        raise AssertionError(f"{path}: a control character reached it raw")
    try:
        root = ET.fromstring(data)
    except ET.ParseError as e:
        raise AssertionError(f"{path}: not well-formed XML ({e})") from e
    for element in root.iter():
        if element.tag.rsplit("}", 1)[-1] == "script":
            raise AssertionError(f"{path}: holds a script element")
        handlers = [a for a in element.attrib if a.lower().startswith("on")]
        if handlers:
            raise AssertionError(f"{path}: an element has the handlers {handlers}")


def case_hostile_values_in_every_field(work):
    """<script>, "onerror=, NUL, ESC[31m and TeX in every string of stats.h5, checks.json,
    checks.h5, manifest.toml and campaign.toml, with the LAMMPS figure drawn: the page holds
    them escaped, every SVG is well-formed XML without scripts or handlers, the summary, the
    CSV files, stdout and stderr hold no raw control character (the LAMMPS figure's SVG held a
    raw NUL and ESC, matplotlib's warnings printed the ESC raw; a <script> once ran in
    Chromium). The TeX `$\\frac{1}$` that matplotlib cannot parse titles the LAMMPS panels as
    text (it stopped the report with a mathtext ValueError)."""
    camp = campaign(work)
    make_every_field_hostile(camp)
    out = os.path.join(work, "r")
    r = report(camp, out, quiet=False)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    page, summary = report_text(out)
    expect_inert(page, "index.html")
    if '"onerror' in page:
        raise AssertionError("index.html: a quote from a file reached it unescaped")
    for name, text in (("summary.txt", summary), ("standard output", r.stdout),
                       ("standard error", r.stderr)):
        expect_inert(text, name, markup=False)
    if "lammps.svg" not in os.listdir(out):
        raise AssertionError("the LAMMPS figure was not drawn (nothing tested)")
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name)
        if name.endswith(".svg"):
            expect_inert_svg(path)
        elif name.endswith(".csv"):
            with open(path, encoding="utf-8") as f:
                expect_inert(f.read(), name, markup=False)
    if page.count("&lt;script&gt;") < 10 or "\\x1b[31m" not in summary:
        raise AssertionError("the hostile values are not shown (nothing tested)")


def edit_json(key, value, where="verdict"):
    """An edit of checks.json: `key` of every verdict's values (where 'values'), of every
    registry entry (where 'checks') set to `value`."""
    def edit(camp):
        path = os.path.join(camp, "checks.json")
        with open(path) as f:
            checks = json.load(f)
        for x in (checks["checks"] if where == "checks" else checks["verdicts"]):
            (x.setdefault("values", {}) if where == "values" else x)[key] = value
        with open(path, "w") as f:
            json.dump(checks, f)
    return edit


def edit_h5(name, obj, key, value):
    """An edit of the HDF5 file `name`: attribute `key` of `obj` set to `value` (obj '*' for
    every ensemble)."""
    def edit(camp):
        with h5py.File(os.path.join(camp, name), "r+") as f:
            targets = list(f["ensembles"].values()) if obj == "*" else [f[obj]]
            for t in targets:
                t.attrs[key] = hostile_bytes(value) if isinstance(value, str) else value
    return edit


def edit_dataset(path, value):
    def edit(camp):
        with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
            first = sorted(f["ensembles"])[0]
            full = f"ensembles/{first}/{path}"
            del f[full]
            f[full] = value
    return edit


def expect_each_refused(work, camp, cases):
    """Each (edit, words) of `cases` made to a fresh copy of the campaign `camp`: the report
    refuses it in one line holding `words`, and leaves the tree as it was."""
    for edit, words in cases:
        shutil.rmtree(camp)
        camp = campaign(work)
        edit(camp)
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r")), words, before, work)


def case_mistyped_stats_and_values_fields(work):
    """A field of stats.h5, checks.h5, checks.json's values and registry, or manifest.toml of
    the wrong type: one line naming the file, the field and the value, exit 2, no report
    (these gave 'cannot draw the report (ValueError: Unknown format code ...)', or were shown)."""
    camp = campaign(work)
    stats, checks_h5 = os.path.join(camp, "stats.h5"), os.path.join(camp, "checks.h5")
    checks_json = os.path.join(camp, "checks.json")
    manifest = os.path.join(camp, "manifest.toml")
    cases = [
        (edit_json("phi_init", "0.4", "values"), [checks_json, "verdict 0",
                                                  "field 'values.phi_init' is '0.4'"]),
        (edit_json("log10_rate", [1], "values"), [checks_json, "'values.log10_rate' is [1]"]),
        (edit_json("margin_unit", "percent", "checks"),
         [checks_json, "checks 0", "field 'margin_unit' is 'percent'"]),
        (edit_json("name", 7, "checks"), [checks_json, "checks 0", "field 'name' is 7"]),
        (edit_json("unit", 5), [checks_json, "verdict 0", "field 'unit' is 5"]),
        (edit_h5("stats.h5", "/", "wall_time", "1 s"),
         [stats, "attribute 'wall_time'", "'1 s'", "not a number"]),
        (edit_h5("stats.h5", "/", "runs", 2.5), [stats, "attribute 'runs'", "2.5"]),
        (edit_h5("stats.h5", "/", "dim", 7), [stats, "attribute 'dim'", "7", "not 2 or 3"]),
        (edit_h5("stats.h5", "/paper", "phi_j", "0.84"),
         [stats, "attribute 'phi_j' of '/paper'", "'0.84'"]),
        (edit_h5("stats.h5", "/fit", "phi_init", "0.4"),
         [stats, "attribute 'phi_init' of '/fit'", "'0.4'"]),
        (edit_h5("stats.h5", "*", "n", "1024"), [stats, "attribute 'n' of '/ensembles/",
                                                 "'1024'", "not a whole number"]),
        (edit_h5("stats.h5", "/fit/representative", "iterations", np.arange(3)),
         [stats, "attribute 'iterations'", "(3,) values, expected one"]),
        (edit_dataset("constant_phi/pressure_mean", np.array([b"a", b"b"])),
         [stats, "pressure_mean", "is a string, expected floating point"]),
        (edit_h5("checks.h5", "/", "wall_time", "1 s"),
         [checks_h5, "attribute 'wall_time'", "'1 s'"]),
        (lambda c: open(manifest, "w").write('[runs.a]\nstatus = "done"\n'
                                             'wall_seconds = "9 s"\n'),
         [manifest, "field 'runs.a.wall_seconds' is '9 s', not a number"]),
    ]
    expect_each_refused(work, camp, cases)


def case_fifo_and_device_inputs_refused(work):
    """A FIFO at campaign.toml, manifest.toml, stats.h5, checks.json or checks.h5 (directly or
    through a symbolic link), /dev/zero at manifest.toml: one line naming it, at once (a FIFO
    campaign.toml hung the report). Each report is stopped after 30 s."""
    for name, make in (("campaign.toml", "fifo"), ("manifest.toml", "fifo"),
                       ("stats.h5", "link to fifo"), ("checks.json", "fifo"),
                       ("checks.h5", "fifo"), ("manifest.toml", "/dev/zero"),
                       ("campaign.toml", "/dev/zero")):
        shutil.rmtree(os.path.join(work, "campaign"), ignore_errors=True)
        camp = campaign(work)
        path = os.path.join(camp, name)
        if os.path.lexists(path):
            os.remove(path)
        if make == "fifo":
            os.mkfifo(path)
        elif make == "link to fifo":
            os.mkfifo(os.path.join(work, "elsewhere"))
            os.symlink(os.path.join(work, "elsewhere"), path)
        else:
            os.symlink(make, path)
        kind = "a character device" if make == "/dev/zero" else "a FIFO"
        before = tree(work)
        expect_error(report(camp, os.path.join(work, "r"), timeout=30),
                     [path, f"is {kind}"], before, work)
        if os.path.lexists(os.path.join(work, "elsewhere")):
            os.remove(os.path.join(work, "elsewhere"))


def case_error_line_is_visible_and_short(work):
    """An ensemble named with an escape sequence and 5000 characters, lacking what the figures
    draw: the error line shows the escape as text and stays short (the name reached the
    terminal raw)."""
    camp = campaign(work)
    with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
        first = sorted(f["ensembles"])[0]
        name = "\x1b[31m\x1b]0;pwned\x07" + "x" * 5000
        f.move(f"ensembles/{first}", f"ensembles/{name}")
        del f[f"ensembles/{name}/constant_phi/pressure_mean"]
    before = tree(work)
    line = expect_error(report(camp, os.path.join(work, "r")),
                        ["stats.h5", "\\x1b[31m", "pressure_mean"], before, work)
    if "\x1b" in line or "\x07" in line:
        raise AssertionError(f"a control character reached the terminal raw: {line!r}")
    if len(line) > 2200:
        raise AssertionError(f"the error line is {len(line)} characters")


def case_verdicts_beyond_what_a_report_shows(work):
    """25,000 verdicts (a campaign's checks give hundreds): refused in one line before anything
    is drawn, so no page or summary of gigabytes; 3,000 give a summary that lists 2,000 and
    says how many more the page has."""
    camp = campaign(work)
    path = os.path.join(camp, "checks.json")
    with open(path) as f:
        original = json.load(f)
    checks = dict(original, verdicts=(original["verdicts"] * 25_000)[:25_000])
    with open(path, "w") as f:
        json.dump(checks, f)
    os.remove(os.path.join(camp, "checks.h5"))
    before = tree(work)
    expect_error(report(camp, os.path.join(work, "r")),
                 [path, "25000 verdicts", "more than a report shows"], before, work)
    checks = dict(original, verdicts=(original["verdicts"] * 3_000)[:3_000])
    with open(path, "w") as f:
        json.dump(checks, f)
    out = os.path.join(work, "r")
    r = report(camp, out)
    if r.returncode != 0:
        raise AssertionError(f"exit {r.returncode}: {r.stderr}")
    summary = report_text(out)[1]
    # 2,000 verdicts listed, each a line of numbers and a few of case and reason (folded to
    # 100 columns; a reason of at most 120 characters).
    rows = [line for line in summary.splitlines()
            if line.startswith("  ") and line.split()[0] in ("pass", "fail", "inconclusive")]
    if "... and 1000 more verdicts" not in summary or len(rows) != 2000 or \
            len(summary.splitlines()) > 2000 * 5 + 200:
        raise AssertionError(f"the summary of 3000 verdicts has {len(rows)} verdict rows in "
                             f"{len(summary.splitlines())} lines")



def checks_h5_edit(edit):
    """An edit of checks.h5's verdict groups: edit(verdicts group)."""
    def apply(camp):
        with h5py.File(os.path.join(camp, "checks.h5"), "r+") as f:
            edit(f["verdicts"])
    return apply


def pairs_of_two_columns(verdicts):
    g = verdicts[next(k for k in sorted(verdicts) if k.endswith("_sample_pairs"))]
    g["grid"] = np.linspace(0.80, 0.86, 50)
    g["pair_0"] = np.zeros((50, 2))


def index_twice(verdicts):
    first = sorted(verdicts)[1]
    verdicts.copy(verdicts[first], first.lstrip("0"))


def scan_edit(name, value):
    def apply(camp):
        with h5py.File(os.path.join(camp, "stats.h5"), "r+") as f:
            del f[f"fit/scan/{name}"]
            f[f"fit/scan/{name}"] = value
    return apply


def case_curves_and_scan_of_the_wrong_shape(work):
    """A sample-pairs curve of two columns (drawn as two lines, written to the CSV as '[a b]'
    cells), a scan's `chosen` of one value (broadcast: every row starred representative), a
    verdict group whose index is negative or given twice (shown on another verdict, or
    silently replaced): one line naming the file and the field, exit 2, no report."""
    camp = campaign(work)
    stats, checks_h5 = os.path.join(camp, "stats.h5"), os.path.join(camp, "checks.h5")
    cases = [
        (checks_h5_edit(pairs_of_two_columns),
         [checks_h5, "pair_0", "2-dimensional", "expected one dimension of numbers"]),
        (scan_edit("chosen", np.ones(1)), [stats, "/scan/chosen' has 1 values, expected"]),
        (scan_edit("quality_ok", np.ones(1)), [stats, "/scan/quality_ok' has 1 values"]),
        (checks_h5_edit(lambda v: v.move(sorted(v)[0], "-1_finite_size")),
         [checks_h5, "-1_finite_size", "not named <index>_<check>"]),
        (checks_h5_edit(index_twice), [checks_h5, "not named <index>_<check>"]),
    ]
    expect_each_refused(work, camp, cases)


INPUT_CASES = [case_random_stats, case_missing_dataset, case_truncated_checks, case_markup_in_a_number_of_the_fit_is_refused, case_a_huge_case_name_gives_a_small_summary, case_mistyped_checks_fields, case_hostile_values_in_every_field, case_mistyped_stats_and_values_fields, case_fifo_and_device_inputs_refused, case_error_line_is_visible_and_short, case_verdicts_beyond_what_a_report_shows, case_curves_and_scan_of_the_wrong_shape]
