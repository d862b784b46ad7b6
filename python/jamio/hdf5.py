"""HDF5 values as Python values: string attributes (stored as fixed-length bytes) as str,
numpy scalars as int and float, datasets as numpy arrays; a group as a Group."""

import os

import h5py
import numpy as np

from .errors import reading, require_file


class Group(dict):
    """The datasets of one HDF5 group (name -> numpy array), with its attributes in `attrs`."""

    def __init__(self, data=(), attrs=None):
        super().__init__(data)
        self.attrs = dict(attrs or {})

    def __repr__(self):
        return f"Group({list(self)}, attrs={list(self.attrs)})"


def _text(value):
    return value.decode("utf-8") if isinstance(value, bytes) else value


def value(v):
    """One attribute value: bytes -> str, numpy scalar -> int/float/bool, arrays of bytes ->
    arrays of str; other arrays unchanged."""
    if isinstance(v, (bytes, np.bytes_)):
        return bytes(v).decode("utf-8")
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray) and v.dtype.kind in "SO":
        return np.array([_text(x) for x in v.ravel()], dtype=object).reshape(v.shape)
    return v


# The most values one attribute may hold: jam writes scalars and short strings, and a damaged
# or hostile file must not make jamio allocate what its header claims.
MOST_ATTRIBUTE_VALUES = 1024


def attrs(obj):
    """Every attribute of an HDF5 object, as Python values; an attribute of more than
    MOST_ATTRIBUTE_VALUES values is refused before it is read."""
    out = {}
    for key in obj.attrs:
        shape = obj.attrs.get_id(key).shape
        if int(np.prod(shape, dtype=np.float64)) > MOST_ATTRIBUTE_VALUES:
            raise ValueError(f"attribute '{key}' of {obj.name} holds {shape} values "
                             f"(at most {MOST_ATTRIBUTE_VALUES})")
        out[key] = value(obj.attrs[key])
    return out


def _check_size(dataset):
    """Refuses, before reading, a dataset that cannot hold what it declares: declared but never
    written (no storage), or, uncompressed, more bytes than the whole file has."""
    declared = dataset.size * dataset.dtype.itemsize
    if declared == 0:
        return
    stored = dataset.id.get_storage_size()
    if stored == 0:
        raise ValueError(f"dataset {dataset.name} declares {dataset.shape} values and holds none")
    file_size = os.path.getsize(dataset.file.filename)
    if dataset.compression is None and declared > file_size:
        raise ValueError(f"dataset {dataset.name} declares {declared} bytes in a file of "
                         f"{file_size}")


def array(dataset):
    """A dataset as a numpy array (strings decoded to str); its size checked first."""
    _check_size(dataset)
    data = np.asarray(dataset[()])
    if data.dtype.kind == "S":
        return np.char.decode(data, "utf-8")
    if data.dtype.kind == "O":
        return np.array([_text(x) for x in data.ravel()], dtype=object).reshape(data.shape)
    return data


def group(g):
    """The datasets directly inside `g` and its attributes (subgroups are not included)."""
    return Group({k: array(v) for k, v in g.items() if isinstance(v, h5py.Dataset)}, attrs(g))


def optional_group(parent, name):
    """group(parent[name]), or None when `parent` has no such group."""
    return group(parent[name]) if isinstance(parent.get(name), h5py.Group) else None


def read_hdf5(path, what, read):
    """Opens `path` (HDF5) and returns read(file); any failure is a JamioError naming it."""
    path = str(path)
    require_file(path, what)
    with reading(path, what):
        with h5py.File(path, "r") as f:
            return read(f)
