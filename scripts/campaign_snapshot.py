#!/usr/bin/env python3
"""A campaign directory's products, kept where a lost machine cannot take them, and put back.

    scripts/campaign_snapshot.py save RUN_DIR DEST [--jam build/jam] [--max-partial-mb MB]
    scripts/campaign_snapshot.py restore DEST RUN_DIR

save copies into DEST (a directory that can be committed or copied off the machine):
  runs/          every done run file with its record (files already in DEST are kept);
  partial/       the checkpoints of the partial runs and the chained starts of the runs not
                 done yet, replaced as a whole (a newer checkpoint supersedes the one before);
  status.json    `jam campaign status RUN_DIR --json`;
  campaign.toml  the campaign file as RUN_DIR holds it;
  .jam-snapshot  the mark of a snapshot: save writes only into an empty (or new) directory or
                 a snapshot (one saved before the mark existed is recognized by its
                 status.json), and replaces partial/ only when it holds nothing but
                 checkpoints and chained starts, so that it never deletes a file it did not
                 write.
--max-partial-mb leaves out of partial/ any product larger than MB megabytes (a jamming-point
search's checkpoint holds every configuration the search may bisect over: about 500 MB at N =
32768 in 2D, too large to commit), and says which; its run then starts again from its
beginning (or its chained start) after a restore.
restore copies them back into RUN_DIR (runs/, runs/<name>.h5.checkpoint, chain/) and never
overwrites a file there; it refuses while a campaign runs in RUN_DIR (its lock, .lock).
`jam campaign run` then continues: done runs are not redone, partial ones resume from their
checkpoints, and a start that was not kept is left again by its parent, which runs only as far
as the start (docs/campaigns.md, chained starts). Every file jam writes carries its checksum
and identity, so a restored file is only ever taken by the run it belongs to.

Files are written under a temporary name and renamed when complete; the campaign may keep
running while save copies (jam replaces its files by renaming, so a copy is of one whole file).
Only regular files are copied: anything else (a FIFO would block the copy) is refused.
"""
import argparse
import fcntl
import json
import os
import shutil
import stat
import subprocess
import tempfile

from script_files import Staged, fail  # beside this script
from jamio.errors import JamioError  # script_files puts python/ on the path

MARK = ".jam-snapshot"
PARTIAL = (".h5.checkpoint", ".start.h5")  # what save puts in partial/


def copy_atomic(source, target):
    """Copies the regular file source to target through a temporary file in target's
    directory (FileNotFoundError when source is gone)."""
    os.makedirs(os.path.dirname(target), exist_ok=True)
    with Staged() as staged:
        try:
            staged.copy(source, target)
        except JamioError as e:
            if e.missing:
                raise FileNotFoundError(source) from None
            fail(str(e))
        staged.commit()


def campaign_status(jam, run_dir):
    result = subprocess.run([jam, "campaign", "status", run_dir, "--json"], capture_output=True,
                            text=True, check=False)
    if result.returncode == 2 or not result.stdout.strip():
        fail(f"RUN_DIR {run_dir}: not a campaign directory ({result.stderr.strip()})")
    return result.stdout, json.loads(result.stdout)


def saved_before_the_mark(dest):
    """Whether dest is a snapshot saved before save marked them: its status.json is one."""
    try:
        with open(os.path.join(dest, "status.json"), "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                return False
            return isinstance(json.load(f).get("run"), dict)
    except (OSError, ValueError, AttributeError):
        return False


def check_dest(dest):
    """Refuses a DEST whose files save would replace without having written them."""
    mark = os.path.join(dest, MARK)
    if not os.path.isfile(mark):
        if os.listdir(dest) and not saved_before_the_mark(dest):
            fail(f"DEST {dest}: not empty and not a snapshot (no {MARK}): save writes into "
                 f"an empty directory or a snapshot only")
    for name in ("partial", "partial.old"):
        path = os.path.join(dest, name)
        if not os.path.lexists(path):
            continue
        if os.path.islink(path) or not os.path.isdir(path):
            fail(f"DEST {dest}: {name} is not a directory save made")
        foreign = sorted(e for e in os.listdir(path) if not e.endswith(PARTIAL))
        if foreign:
            fail(f"DEST {dest}: {name}/ holds {foreign[0]}, which save did not write: "
                 f"refusing to replace it")


def save(run_dir, dest, jam, max_partial_bytes=None):
    check_dest(dest)
    text, status = campaign_status(jam, run_dir)
    runs = status["run"]
    # A status with corrupt runs is not one to replace a snapshot's partial products by: run
    # from another directory, a campaign's relative paths (chain_starts_from: the parent's
    # chained starts) do not hold and every chained run reads as another run's.
    corrupt = sorted(name for name, run in runs.items() if run["status"] == "corrupt")
    if corrupt:
        detail = runs[corrupt[0]].get("detail", "")
        fail(f"RUN_DIR {run_dir}: {len(corrupt)} runs corrupt by `jam campaign status` (the "
             f"first, {corrupt[0]}: {detail}); nothing saved: run from the directory where the "
             f"campaign's relative paths hold, or move the corrupt files aside")
    copied = kept = 0
    for name, run in sorted(runs.items()):
        if run["status"] != "done":
            continue
        for suffix in (".h5", ".record"):
            source = os.path.join(run_dir, "runs", name + suffix)
            target = os.path.join(dest, "runs", name + suffix)
            if not os.path.exists(source):
                continue
            if os.path.exists(target):
                kept += 1
            else:
                copy_atomic(source, target)
                copied += 1
    # The partial products: a new set in a temporary directory, then swapped in whole.
    staging = tempfile.mkdtemp(prefix=".partial-", dir=dest)
    partial, left_out = [], []
    for name, run in sorted(runs.items()):
        if run["status"] == "done":
            continue
        for source in (os.path.join(run_dir, "runs", name + ".h5.checkpoint"),
                       os.path.join(run_dir, "chain", name + ".start.h5")):
            try:
                size = os.stat(source).st_size
                if max_partial_bytes is not None and size > max_partial_bytes:
                    left_out.append(f"{os.path.basename(source)} ({size / 1e6:.0f} MB)")
                    continue
                copy_atomic(source, os.path.join(staging, os.path.basename(source)))
                partial.append(os.path.basename(source))
            except FileNotFoundError:
                pass  # none, or gone since the status (the run finished: the next save has it)
    old = os.path.join(dest, "partial")
    retired = old + ".old"
    shutil.rmtree(retired, ignore_errors=True)
    if os.path.isdir(old):
        os.rename(old, retired)
    os.rename(staging, old)
    shutil.rmtree(retired, ignore_errors=True)
    with tempfile.NamedTemporaryFile("w", dir=dest, prefix=".status-", delete=False) as f:
        f.write(text)
    os.replace(f.name, os.path.join(dest, "status.json"))
    copy_atomic(os.path.join(run_dir, "campaign.toml"), os.path.join(dest, "campaign.toml"))
    if not os.path.isfile(os.path.join(dest, MARK)):
        with tempfile.NamedTemporaryFile("w", dir=dest, prefix=".mark-", delete=False) as f:
            f.write("a snapshot of a campaign directory: scripts/campaign_snapshot.py save "
                    "replaces its partial/, status.json and campaign.toml\n")
        os.replace(f.name, os.path.join(dest, MARK))
    done = sum(1 for r in runs.values() if r["status"] == "done")
    print(f"campaign_snapshot: {dest}: {done}/{len(runs)} runs done ({copied} files copied, "
          f"{kept} kept), {len(partial)} partial products")
    if left_out:
        print(f"campaign_snapshot: left out, larger than --max-partial-mb (their runs start "
              f"again after a restore): {', '.join(left_out)}")


def restore(dest, run_dir):
    if not os.path.isdir(os.path.join(dest, "runs")):
        fail(f"DEST {dest}: holds no runs/ (not a snapshot)")
    os.makedirs(run_dir, exist_ok=True)
    lock_path = os.path.join(run_dir, ".lock")
    try:  # without blocking: a FIFO there would hang a plain open
        fd = os.open(lock_path, os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_NONBLOCK, 0o644)
    except OSError as e:
        fail(f"RUN_DIR {run_dir}: cannot open its lock {lock_path}: {e.strerror}")
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        fail(f"RUN_DIR {run_dir}: its lock {lock_path} is not a regular file")
    with os.fdopen(fd, "a") as lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            fail(f"RUN_DIR {run_dir}: a campaign is running there (its .lock is held)")
        copied = skipped = 0

        def put(source, target):
            nonlocal copied, skipped
            if os.path.exists(target):
                skipped += 1
            else:
                copy_atomic(source, target)
                copied += 1

        toml = os.path.join(dest, "campaign.toml")
        if os.path.isfile(toml):
            put(toml, os.path.join(run_dir, "campaign.toml"))
        for entry in sorted(os.listdir(os.path.join(dest, "runs"))):
            put(os.path.join(dest, "runs", entry), os.path.join(run_dir, "runs", entry))
        partial = os.path.join(dest, "partial")
        for entry in sorted(os.listdir(partial)) if os.path.isdir(partial) else []:
            source = os.path.join(partial, entry)
            if entry.endswith(".h5.checkpoint"):
                # A checkpoint only where its run is not done.
                if os.path.exists(os.path.join(run_dir, "runs", entry[:-len(".checkpoint")])):
                    continue
                put(source, os.path.join(run_dir, "runs", entry))
            elif entry.endswith(".start.h5"):
                put(source, os.path.join(run_dir, "chain", entry))
    print(f"campaign_snapshot: {run_dir}: {copied} files restored, {skipped} already there "
          f"(kept)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    s = sub.add_parser("save", help="copy a campaign directory's products into DEST")
    s.add_argument("run_dir")
    s.add_argument("dest")
    s.add_argument("--jam", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                 "..", "build", "jam"))
    s.add_argument("--max-partial-mb", type=float, default=None,
                   help="leave out of partial/ any product larger than this (megabytes)")
    r = sub.add_parser("restore", help="put a snapshot back into a campaign directory")
    r.add_argument("dest")
    r.add_argument("run_dir")
    a = parser.parse_args()
    if a.command == "save":
        if not os.path.isdir(a.run_dir):
            fail(f"RUN_DIR {a.run_dir}: no such directory")
        os.makedirs(a.dest, exist_ok=True)
        limit = a.max_partial_mb
        if limit is not None and not (limit >= 0 and limit != float("inf")):
            fail(f"--max-partial-mb {limit}: must be a size in megabytes, 0 or more")
        save(a.run_dir, a.dest, a.jam, None if limit is None else limit * 1e6)
    else:
        restore(a.dest, a.run_dir)


if __name__ == "__main__":
    main()
