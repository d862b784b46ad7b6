"""The broken and hostile files of tests/test_jamio.py: what they are (made outside the venv,
by make_broken from the files jam wrote) and the cases that read them inside the venv, each
expecting one JamioError line naming the file (or a child process that neither hangs nor
exhausts memory). make_broken is imported by test_jamio.py, the cases by jamio_in_venv.py (one
parametrised test); not a suite of its own.
"""

import os
import shutil
import subprocess
import sys

import h5py
import numpy as np


def make_broken(data):
    """data/broken: random bytes as HDF5, a truncated checks.h5, invalid JSON."""
    out = os.path.join(data, "broken")
    os.mkdir(out)
    with open(os.path.join(out, "random.h5"), "wb") as f:
        f.write(np.random.default_rng(7).bytes(4096))
    truncated = os.path.join(out, "truncated")
    shutil.copytree(os.path.join(data, "schema1"), truncated)
    os.truncate(os.path.join(truncated, "checks.h5"),
                os.path.getsize(os.path.join(truncated, "checks.h5")) // 2)
    os.mkdir(os.path.join(out, "badjson"))
    with open(os.path.join(out, "badjson", "checks.json"), "w") as f:
        f.write('{"schema_version": 2, "verdicts": [\n{"check": }\n')
    # Hostile files: FIFOs where files belong, and run files whose shapes lie.
    os.mkfifo(os.path.join(out, "fifo.h5"))
    os.mkdir(os.path.join(out, "fifodir"))
    os.mkfifo(os.path.join(out, "fifodir", "checks.json"))
    os.mkfifo(os.path.join(out, "fifodir", "stats.h5"))
    for name, edit in (("array-attribute.h5",
                        lambda f: f.attrs.create("complete", np.ones(4000, "i8"))),
                       ("unwritten.h5",
                        lambda f: f.create_dataset("pressure_unwritten", shape=(300_000_000,),
                                                   dtype="f8", chunks=(1 << 16,)))):
        path = os.path.join(out, name)
        shutil.copy(os.path.join(data, "run.h5"), path)
        with h5py.File(path, "r+") as f:
            if name == "unwritten.h5":
                del f["pressure"]
                f.create_dataset("pressure", shape=(300_000_000,), dtype="f8", chunks=(1 << 16,))
            else:
                edit(f)
    make_hostile(data, out)


def _compound(f):
    m = len(f["packing_fraction"])
    del f["pressure"]
    f["pressure"] = np.zeros(m, dtype=[("a", "i4"), ("b", "f8")])


def _escape_named_compound(f):
    f["\x1b[31mred"] = np.zeros(3, dtype=[("a", "i4"), ("b", "f8")])


def _compressed_bomb(f):
    """pressure declared with 5e7 values (400 MB) in gzip chunks, one chunk written."""
    del f["pressure"]
    d = f.create_dataset("pressure", shape=(50_000_000,), dtype="f8", chunks=(1 << 16,),
                         compression="gzip")
    d[: 1 << 16] = 0.0


def _huge_shape(f):
    """pressure declared with 2e9 values (16 GB) in gzip chunks, one chunk written."""
    del f["pressure"]
    d = f.create_dataset("pressure", shape=(2_000_000_000,), dtype="f8", chunks=(1 << 16,),
                         compression="gzip")
    d[: 1 << 16] = 0.0


# Run files whose attributes or datasets are of the wrong shape or type, by name.
HOSTILE_RUNS = {
    "array-n.h5": lambda f: f.attrs.__setitem__("n", np.array([64, 64])),
    "string-n.h5": lambda f: f.attrs.__setitem__("n", np.bytes_(b"abc")),
    "nan-sample.h5": lambda f: f.attrs.__setitem__("sample", np.nan),
    "huge-seed.h5": lambda f: f.attrs.__setitem__("seed", 1e300),
    "compound-attribute.h5": lambda f: f.attrs.__setitem__(
        "phi_init", np.array((1, 2.0), dtype=[("a", "i4"), ("b", "f8")])),
    "compound-pressure.h5": _compound,
    "escape-name.h5": _escape_named_compound,
    "compressed-bomb.h5": _compressed_bomb,
    "huge-shape.h5": _huge_shape,
}


def _outside(data, hostile):
    """Files whose members are kept outside them, in data/run.h5 and the campaign's stats.h5
    (regular files: what a file names must be refused unopened, wherever it points), by name:
    pressure an external link, a soft link through an external link, external storage, a
    virtual dataset; a stats.h5 whose ensemble group is an external link."""
    run = os.path.join(data, "run.h5")
    stats = os.path.join(data, "campaign", "stats.h5")
    raw = os.path.join(hostile, "pressure.raw")

    def external_link(f):
        del f["pressure"]
        f["pressure"] = h5py.ExternalLink(run, "/pressure")

    def soft_link(f):
        del f["pressure"]
        f["elsewhere"] = h5py.ExternalLink(run, "/")
        f["pressure"] = h5py.SoftLink("/elsewhere/pressure")

    def external_storage(f):
        m = len(f["packing_fraction"])
        with open(raw, "wb") as out:
            out.write(np.zeros(m).tobytes())
        del f["pressure"]
        f.create_dataset("pressure", shape=(m,), dtype="f8", external=[(raw, 0, 8 * m)])

    def virtual_dataset(f):
        m = len(f["packing_fraction"])
        layout = h5py.VirtualLayout(shape=(m,), dtype="f8")
        layout[:] = h5py.VirtualSource(run, "pressure", shape=(m,))
        del f["pressure"]
        f.create_virtual_dataset("pressure", layout)

    def external_group(f):
        del f.attrs["checksum"]  # the link itself is the case, not the seal it breaks
        name = f"ensembles/{sorted(f['ensembles'])[0]}/constant_phi"
        del f[name]
        f[name] = h5py.ExternalLink(stats, "/" + name)
    return {"external-link.h5": (run, external_link), "soft-link-out.h5": (run, soft_link),
            "external-storage.h5": (run, external_storage),
            "virtual-pressure.h5": (run, virtual_dataset),
            "stats-external-link.h5": (stats, external_group)}


def make_hostile(data, out):
    """data/broken/hostile: run files of HOSTILE_RUNS, files reaching outside themselves
    (_outside), a checks.json nested 100,000 deep, a checks.json of 300 MB (sparse: it takes
    no disk), symbolic links to a FIFO and to /dev/zero where stats.h5 and checks.json
    belong."""
    hostile = os.path.join(out, "hostile")
    os.mkdir(hostile)
    runs = {name: (os.path.join(data, "run.h5"), edit) for name, edit in HOSTILE_RUNS.items()}
    for name, (original, edit) in {**runs, **_outside(data, hostile)}.items():
        path = os.path.join(hostile, name)
        shutil.copy(original, path)
        with h5py.File(path, "r+") as f:
            edit(f)
    for name, write in (("nested", lambda f: f.write("[" * 100_000 + "]" * 100_000)),
                        ("huge", lambda f: f.truncate(300 << 20))):
        os.mkdir(os.path.join(hostile, name))
        with open(os.path.join(hostile, name, "checks.json"), "w") as f:
            write(f)
    links = os.path.join(hostile, "links")
    os.mkdir(links)
    os.mkfifo(os.path.join(links, "fifo"))
    os.symlink("fifo", os.path.join(links, "stats.h5"))
    os.symlink("/dev/zero", os.path.join(links, "checks.json"))


def expect_error(load, path, words, missing=False):
    import jamio
    try:
        load(path)
    except jamio.JamioError as e:
        message = str(e)
        if not isinstance(e, ValueError) or e.missing != missing or "\n" in message:
            raise AssertionError(f"{path}: {type(e).__mro__}, missing={e.missing}: {message}")
        lacking = [w for w in words if w not in message]
        if lacking:
            raise AssertionError(f"{lacking} not in: {message}")
        return
    raise AssertionError(f"{load.__name__}({path}) raised nothing")


def case_errors(data, source):
    import jamio
    broken = os.path.join(data, "broken")
    random_h5 = os.path.join(broken, "random.h5")
    expect_error(jamio.load_run, random_h5, [random_h5, "not a readable run file"])
    expect_error(jamio.load_stats, random_h5, [random_h5, "not a readable stats file"])
    nowhere = os.path.join(broken, "nowhere.h5")
    expect_error(jamio.load_run, nowhere, [nowhere, "missing"], missing=True)
    expect_error(jamio.load_stats, broken, [os.path.join(broken, "stats.h5"), "missing"],
                 missing=True)
    truncated = os.path.join(broken, "truncated")
    expect_error(jamio.load_checks, truncated,
                 [os.path.join(truncated, "checks.h5"), "not a readable checks file"])
    bad = os.path.join(broken, "badjson")
    expect_error(jamio.load_checks, bad, [os.path.join(bad, "checks.json"), "line 2",
                                          "not valid JSON"])
    expect_error(jamio.load_runs, broken, [os.path.join(broken, "runs"), "missing"],
                 missing=True)
    expect_error(jamio.load_run, os.path.join(data, "campaign.toml"),
                 [os.path.join(data, "campaign.toml"), "not a readable run file"])
    expect_error(jamio.load_run, os.path.join(data, "campaign", "stats.h5"),
                 ["stats.h5", "not a readable run file", "packing_fraction"])


def case_hostile_files(data, source):
    """A FIFO where a run file, stats.h5 or checks.json belongs is refused at once (opening it
    would wait for ever); an attribute of 4000 values and a dataset declared with 3e8 values
    and never written are refused before they are read (no 2.4 GB allocation): each a
    JamioError naming the file. An alarm turns a regression to a hang into a failure."""
    import signal
    import jamio
    broken = os.path.join(data, "broken")

    def hung(*_):
        raise AssertionError("a read waited for 60 s")
    signal.signal(signal.SIGALRM, hung)
    signal.alarm(60)
    try:
        fifo = os.path.join(broken, "fifo.h5")
        expect_error(jamio.load_run, fifo, [fifo, "is a FIFO"])
        fifodir = os.path.join(broken, "fifodir")
        expect_error(jamio.load_stats, fifodir, [os.path.join(fifodir, "stats.h5"), "is a FIFO"])
        expect_error(jamio.load_checks, fifodir,
                     [os.path.join(fifodir, "checks.json"), "is a FIFO"])
        big = os.path.join(broken, "array-attribute.h5")
        expect_error(jamio.load_run, big, [big, "attribute 'complete'", "(4000,) values"])
        unwritten = os.path.join(broken, "unwritten.h5")
        expect_error(jamio.load_run, unwritten, [unwritten, "holds none"])
    finally:
        signal.alarm(0)


def in_a_child(load, path, seconds=30, memory=2 << 30):
    """load(path) in a child Python limited to `memory` bytes of address space and `seconds`:
    what it raised, as `type: message` (a read that allocates what a file claims, or waits for
    ever, fails the case and not the machine or the test run)."""
    code = ("import sys, jamio\n"
            "try:\n"
            f"    jamio.{load}(sys.argv[1])\n"
            "    print('nothing raised')\n"
            "except BaseException as e:\n"
            "    print(f'{type(e).__name__}: {e}')\n")

    def limit():
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    try:
        r = subprocess.run([sys.executable, "-c", code, path], capture_output=True, text=True,
                           timeout=seconds, preexec_fn=limit)
    except subprocess.TimeoutExpired:
        raise AssertionError(f"{load}({path}) did not return in {seconds} s") from None
    return (r.stdout + r.stderr).strip()


def expect_child_error(load, path, words):
    """load(path) in a child raises one line of JamioError holding `words`."""
    got = in_a_child(load, path)
    lacking = [w for w in words if w not in got]
    if not got.startswith("JamioError: ") or "\n" in got or lacking:
        raise AssertionError(f"{load}({path}): expected a JamioError with {lacking or words}, "
                             f"got: {got[:2000]}")
    return got


def case_array_valued_scalar_attribute(data, source):
    """A run file whose `n` is an array of two values: refused, naming the attribute (it was
    returned as an array); a compound where a number belongs, refused by its type."""
    hostile = os.path.join(data, "broken", "hostile")
    path = os.path.join(hostile, "array-n.h5")
    expect_child_error("load_run", path, [path, "attribute 'n'", "(2,) values, expected one"])
    path = os.path.join(hostile, "compound-attribute.h5")
    expect_child_error("load_run", path, [path, "attribute 'phi_init'", "compound type"])


def case_mistyped_run_attribute(data, source):
    """`n` stored as the string 'abc': a JamioError naming it, from load_run and load_runs (a
    plain ValueError escaped load_runs)."""
    hostile = os.path.join(data, "broken", "hostile")
    path = os.path.join(hostile, "string-n.h5")
    expect_child_error("load_run", path, [path, "attribute 'n'", "'abc'", "not a whole number"])
    campaign = os.path.join(hostile, "campaign")
    os.makedirs(os.path.join(campaign, "runs"), exist_ok=True)
    shutil.copy(path, os.path.join(campaign, "runs", "n64.h5"))
    expect_child_error("load_runs", campaign, ["n64.h5", "attribute 'n'", "not a whole number"])


def case_sample_and_seed_whole_numbers(data, source):
    """A sample of NaN (it passed as a number) and a seed of 1e300 (a whole number no int64
    holds): each refused, naming the attribute and its value."""
    hostile = os.path.join(data, "broken", "hostile")
    path = os.path.join(hostile, "nan-sample.h5")
    expect_child_error("load_run", path, [path, "attribute 'sample'", "nan", "not a whole number"])
    path = os.path.join(hostile, "huge-seed.h5")
    expect_child_error("load_run", path, [path, "attribute 'seed'", "1e+300",
                                          "not a whole number"])


def case_members_outside_the_file_refused(data, source):
    """pressure an external link to another run file, a soft link through an external link,
    values kept in another file (external storage, a virtual dataset), an ensemble's group an external link in stats.h5: each
    refused, naming the member, and nothing opened (followed, a FIFO there blocked the read for
    ever); in a child stopped after 30 s."""
    hostile = os.path.join(data, "broken", "hostile")
    for load in ("load_run", "validate_run"):
        path = os.path.join(hostile, "external-link.h5")
        expect_child_error(load, path, [path, "'/pressure' is an external link",
                                        os.path.join(data, "run.h5"), "not followed"])
        path = os.path.join(hostile, "soft-link-out.h5")
        expect_child_error(load, path, [path, "'/elsewhere' is an external link",
                                        "not followed"])
        path = os.path.join(hostile, "external-storage.h5")
        expect_child_error(load, path, [path, "dataset '/pressure'", "another file",
                                        "not read"])
        path = os.path.join(hostile, "virtual-pressure.h5")
        expect_child_error(load, path, [path, "dataset '/pressure'", "another file",
                                        "not read"])
    path = os.path.join(hostile, "stats-external-link.h5")
    expect_child_error("load_stats", path, [path, "/constant_phi' is an external link",
                                            "not followed"])


def case_compound_dataset_refused(data, source):
    """pressure of a compound type: refused by its type, not read (load_run returned it and
    load_runs raised a plain TypeError); a dataset named with an escape sequence is named with
    it made visible."""
    hostile = os.path.join(data, "broken", "hostile")
    path = os.path.join(hostile, "compound-pressure.h5")
    expect_child_error("load_run", path, [path, "dataset '/pressure'", "compound type"])
    campaign = os.path.join(hostile, "compound-campaign")
    os.makedirs(os.path.join(campaign, "runs"), exist_ok=True)
    shutil.copy(path, os.path.join(campaign, "runs", "n64.h5"))
    expect_child_error("load_runs", campaign, ["n64.h5", "compound type"])
    path = os.path.join(hostile, "escape-name.h5")
    got = expect_child_error("load_run", path, [path, "\\x1b[31mred", "compound type"])
    if "\x1b" in got:
        raise AssertionError(f"the escape sequence reached the message raw: {got!r}")


def case_huge_claimed_dataset(data, source):
    """Datasets declaring 400 MB from one compressed chunk and 16 GB: refused before reading,
    in a child limited to 2 GB of memory (they were read into what they declared)."""
    hostile = os.path.join(data, "broken", "hostile")
    path = os.path.join(hostile, "compressed-bomb.h5")
    expect_child_error("load_run", path, [path, "dataset '/pressure'", "compressed bytes"])
    path = os.path.join(hostile, "huge-shape.h5")
    expect_child_error("load_run", path, [path, "dataset '/pressure'", "16000000000 bytes"])


def case_checks_json_of_300_mb_refused_unread(data, source):
    """A checks.json of 300 MB is refused by its size before it is read (it was read whole);
    one nested 100,000 deep is a JamioError naming the file."""
    hostile = os.path.join(data, "broken", "hostile")
    huge = os.path.join(hostile, "huge")
    expect_child_error("load_checks", huge, [os.path.join(huge, "checks.json"),
                                             f"is {300 << 20} bytes", "not read"])
    nested = os.path.join(hostile, "nested")
    expect_child_error("load_checks", nested, [os.path.join(nested, "checks.json"),
                                               "not a readable verdict file"])


def case_links_to_a_fifo_or_device(data, source):
    """stats.h5 a symbolic link to a FIFO, checks.json one to /dev/zero: refused at once, in a
    child that is stopped after 30 s, so a regression to a hang cannot hang the test run."""
    links = os.path.join(data, "broken", "hostile", "links")
    expect_child_error("load_stats", links, [os.path.join(links, "stats.h5"), "is a FIFO"])
    expect_child_error("load_checks", links, [os.path.join(links, "checks.json"),
                                              "is a character device"])


HOSTILE_CASES = [case_errors, case_hostile_files, case_array_valued_scalar_attribute,
                 case_mistyped_run_attribute, case_sample_and_seed_whole_numbers,
                 case_members_outside_the_file_refused, case_compound_dataset_refused,
                 case_huge_claimed_dataset, case_checks_json_of_300_mb_refused_unread,
                 case_links_to_a_fifo_or_device]
