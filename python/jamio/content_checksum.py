"""The content checksum jam seals its HDF5 files with (sim/io/content_checksum.cpp), computed
the same way, so that load_stats refuses a stats.h5 changed since `jam stats` wrote it, as jam
does (seal_problem).

FNV-1a (64 bit) over the file's content in a fixed order: from the root, each group's
attributes (by name; the root's `checksum` left out), then its links (by name): a group as
"group <path>" and its own walk, a dataset as "dataset <path>", its dimensions (64-bit) and
values, then its attributes (named "<path>@<name>"). Each value set is preceded by its HDF5
class and read in one canonical type: integers as little-endian int64, floats as doubles,
fixed-length strings as their bytes without the trailing NULs; text is added with its length
first. Pure Python: about 8 MB/s, half a second for the largest stored stats.h5.
"""
import struct

import h5py
import numpy as np

_OFFSET = 0xcbf29ce484222325
_PRIME = 0x100000001b3
_MASK = (1 << 64) - 1
_MAX_DEPTH = 32  # as jam: its files nest groups three deep; deeper is damage


class _Fnv1a:
    def __init__(self):
        self.h = _OFFSET

    def add(self, data):
        h = self.h
        for b in data:
            h = ((h ^ b) * _PRIME) & _MASK
        self.h = h

    def add_sized(self, text):
        data = text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text
        self.add(struct.pack("<Q", len(data)))
        self.add(data)


def _values(hash_, tid, shape, read, what):
    """Adds the class and the values of one attribute or dataset, read by read(array, mtype)."""
    cls = tid.get_class()
    hash_.add(struct.pack("<i", cls))
    if cls == h5py.h5t.INTEGER:
        v = np.empty(shape, dtype="<i8")
        read(v, None)
        hash_.add(v.tobytes())
    elif cls == h5py.h5t.FLOAT:
        v = np.empty(shape, dtype="<f8")
        read(v, None)
        hash_.add(v.tobytes())
    elif cls == h5py.h5t.STRING and not tid.is_variable_str():
        v = np.empty(shape, dtype=f"S{tid.get_size()}")
        read(v, tid)  # the file's own type: the bytes as stored, padding included
        hash_.add_sized(v.tobytes().rstrip(b"\0"))
    else:
        raise ValueError(f"{what}: a kind of value the checksum does not cover")


def _attributes(hash_, obj, where, skip):
    names = []
    h5py.h5a.iterate(obj.id, lambda name, *_: names.append(name), index_type=h5py.h5.INDEX_NAME,
                     order=h5py.h5.ITER_INC)
    for raw in names:
        name = raw.decode("utf-8", "surrogateescape")
        if where == "/" and name in skip:
            continue
        aid = h5py.h5a.open(obj.id, raw)
        space = aid.get_space()
        shape = space.shape if space.get_simple_extent_type() != h5py.h5s.NULL else (0,)
        hash_.add_sized(f"attribute {where}{name}")
        _values(hash_, aid.get_type(), shape, lambda v, mtype: aid.read(v, mtype=mtype), name)


def _dataset(hash_, ds, path):
    dims = ds.id.get_space().shape
    hash_.add_sized(f"dataset {path}")
    hash_.add(struct.pack(f"<{len(dims)}Q", *dims))
    count = int(np.prod(dims)) if dims else 1
    if count and ds.id.get_storage_size() == 0:
        raise ValueError(f"{path}: {count} values declared but never written")

    def read(v, mtype):
        ds.id.read(h5py.h5s.ALL, h5py.h5s.ALL, v, mtype=mtype)

    _values(hash_, ds.id.get_type(), dims, read, path)
    _attributes(hash_, ds, path + "@", ())


def _group(hash_, group, where, skip, depth):
    if depth > _MAX_DEPTH:
        raise ValueError(f"{where}: groups nested deeper than the file can be sound")
    _attributes(hash_, group, where, skip)
    names = []
    group.id.links.iterate(names.append, idx_type=h5py.h5.INDEX_NAME, order=h5py.h5.ITER_INC)
    for raw in names:
        name = raw.decode("utf-8", "surrogateescape")
        path = where + name
        if not isinstance(group.get(name, getlink=True), h5py.HardLink):
            raise ValueError(f"{path}: a soft or external link, not written by jam")
        obj = group[name]
        if isinstance(obj, h5py.Group):
            hash_.add_sized(f"group {path}")
            _group(hash_, obj, path + "/", (), depth + 1)
        elif isinstance(obj, h5py.Dataset):
            _dataset(hash_, obj, path)
        else:
            raise ValueError(f"{path}: neither a group nor a dataset")


def content_checksum(f, skip=("checksum",)):
    """The checksum of the open h5py.File f as jam writes it: 16 lowercase hex digits."""
    hash_ = _Fnv1a()
    _group(hash_, f, "/", tuple(skip), 1)
    return f"{hash_.h:016x}"


def seal_problem(f):
    """"" when f's stored `checksum` matches its content; else what differs (jam's words). A
    file without one is not judged here (jam reads one so too)."""
    if "checksum" not in f.attrs:
        return ""
    stored = f.attrs["checksum"]
    stored = stored.decode("utf-8", "surrogateescape") if isinstance(stored, bytes) else str(stored)
    actual = content_checksum(f)
    return "" if actual == stored else f"checksum {actual} does not match the stored {stored}"
