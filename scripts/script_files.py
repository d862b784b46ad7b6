"""Files the scripts read and write, shared by them (imported from the scripts' own directory):

    fail(message)                      `<script>: <message>` on stderr, exit status 2
    require_input(path, field)         a regular file, else fail (jamio's check: a FIFO would
                                       hang the HDF5 open that follows)
    open_input(path, field)            the same, opened for reading (binary)
    refuse_same(output, field, input, input_field)
                                       fail when the output path is the input file
    Staged, write_text                 outputs written whole or not at all (Staged.copy:
                                       a regular file's copy)

An output is written under a temporary name in its own directory (the same file system, so the
rename is atomic) and renamed into place when complete: a failure part-way leaves the old file
as it was, and nothing that could be mistaken for a result. The temporary names, the rename and
the cleanup are jamio's (python/jamio/output.py), as for jamio's writers and the report.
"""
import os
import shutil
import sys

# jamio of the same source tree (python/ beside scripts/).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "python"))


def fail(message):
    from jamio.errors import visible  # names from files and paths, one line on the terminal
    script = os.path.splitext(os.path.basename(sys.argv[0]))[0]
    print(visible(f"{script}: {message}"), file=sys.stderr)
    sys.exit(2)


def open_input(path, field):
    """`path` opened for reading (binary): a regular file, else one line naming `field` and the
    path, exit 2."""
    from jamio.errors import JamioError, open_regular
    try:
        return open_regular(path, "file")
    except JamioError as e:
        fail(f"{field} {e}")


def require_input(path, field):
    """Checks `path` is a regular file before a library (h5py) opens it by name."""
    open_input(path, field).close()


def refuse_same(output, field, source, source_field):
    if os.path.exists(output) and os.path.exists(source) and os.path.samefile(output, source):
        fail(f"{field} {output}: is the input {source_field} {source}; write it elsewhere")


class Staged:
    """Files written under temporary names beside their targets; commit() renames them into
    place once every one is written, so a failure while they are written changes no target.
    Leaving the `with` block removes those not renamed."""

    def __init__(self):
        self.pending = []  # (temporary, target)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        from jamio.output import remove
        for temporary, _ in self.pending:
            remove(temporary)
        self.pending = []

    def _open(self, target):
        from jamio.output import claim_temporary
        temporary = claim_temporary(target)  # a new file's mode, not mkstemp's 0600
        self.pending.append((temporary, target))
        return temporary, open(temporary, "wb")

    def text(self, target, text):
        _, out = self._open(target)
        with out:
            out.write(text.encode())

    def copy(self, source, target):
        """Copies the regular file `source` (jamio's open_regular: JamioError, with `missing`
        when it does not exist; a FIFO, which would block the copy, refused) with its mode and
        times."""
        from jamio.errors import open_regular
        with open_regular(source, "file") as inp:
            temporary, out = self._open(target)
            with out:
                shutil.copyfileobj(inp, out)
            shutil.copystat(source, temporary)

    def commit(self):
        from jamio.output import publish
        while self.pending:
            temporary, target = self.pending[0]
            publish(temporary, target, overwrite=True)
            self.pending.pop(0)


def write_text(target, text):
    with Staged() as staged:
        staged.text(target, text)
        staged.commit()
