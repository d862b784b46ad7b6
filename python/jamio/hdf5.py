"""HDF5 values as Python values: string attributes (stored as fixed-length bytes) as str,
numpy scalars as int and float, datasets as numpy arrays; a group as a Group.

Shapes and types are checked before values, as jam's own reader does (sim/io/hdf5_file.hpp):
a file may come from a damaged copy or a hand edit, and h5py allocates whatever the file
declares. Every attribute jam writes is one number or one string, so an attribute is refused
unless it holds one value (a scalar, or an array of exactly one element, as jam's reader
takes it) of a number or string type, a fixed-length string of at most MOST_STRING_BYTES. A
dataset is refused unless it holds numbers or strings, its values fit in the file (or, stored
compressed, in what its compressed bytes can expand to) and in MOST_DATASET_BYTES.

Members are looked up without following an external link (member): it names another file,
which could be anything (a FIFO would block the open for ever) and is no part of the file
checked; a dataset whose values are stored in another file (external storage) or mapped from
other datasets (a virtual dataset) is refused for the same reason."""

import os

import h5py
import numpy as np

from .errors import cause, reading, require_file, shown


class Group(dict):
    """The datasets of one HDF5 group (name -> numpy array), with its attributes in `attrs` and
    each dataset's attribute `units` in `units` (dataset -> unit, for the datasets that have
    one)."""

    def __init__(self, data=(), attrs=None, units=None):
        super().__init__(data)
        self.attrs = dict(attrs or {})
        self.units = dict(units or {})

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


# The longest fixed-length string attribute read, in bytes (as jam's reader: the longest jam
# writes is a few hundred).
MOST_STRING_BYTES = 1 << 16
# The most bytes one dataset may hold, whatever its file declares: the largest jam writes (all
# samples of a long campaign's pressure) is tens of MB; a flipped bit in a shape must not
# become a multi-GB allocation.
MOST_DATASET_BYTES = 1 << 30
# The most a compressed dataset's bytes may expand to (deflate, the best of HDF5's filters,
# reaches about 1032:1).
MOST_EXPANSION = 1100


def _is_string(dtype):
    return h5py.check_string_dtype(dtype) is not None


def _kind(dtype):
    """What an HDF5 type is, in words, for a message."""
    if dtype.names:
        return "a compound type"
    if _is_string(dtype):
        return "a string"
    if h5py.check_vlen_dtype(dtype) is not None:
        return "a variable-length sequence"
    if h5py.check_ref_dtype(dtype) is not None:
        return "a reference"
    if dtype.subdtype is not None:
        return "an array type"
    return {"b": "a boolean", "i": "an integer", "u": "an integer", "f": "a number",
            "c": "a complex number", "V": "an opaque type"}.get(dtype.kind, f"type {dtype}")


def _plain_type(dtype):
    """Whether values of `dtype` are numbers (booleans included) or strings: what jam writes."""
    if _is_string(dtype):
        return True
    return not dtype.names and dtype.subdtype is None and dtype.kind in "biuf"


def _attribute(obj, key):
    """One attribute, its shape and type checked before its value is read."""
    where = f"attribute {shown(key)} of {shown(obj.name)}"
    attribute = obj.attrs.get_id(key)
    shape, dtype = attribute.shape, attribute.dtype
    count = 0 if shape is None else int(np.prod(shape, dtype=np.float64))  # None: no value
    if count != 1:
        raise ValueError(f"{where} holds {shape} values, expected one")
    if not _plain_type(dtype):
        raise ValueError(f"{where} is {_kind(dtype)}, expected a number or a string")
    if dtype.kind == "S" and dtype.itemsize > MOST_STRING_BYTES:
        raise ValueError(f"{where} is a string of {dtype.itemsize} bytes "
                         f"(at most {MOST_STRING_BYTES})")
    try:
        v = obj.attrs[key]
        if isinstance(v, np.ndarray):  # an array of one element: its element, as jam reads it
            v = v.reshape(-1)[0]
        return value(v)
    except (ValueError, TypeError, OverflowError) as e:
        raise ValueError(f"{where}: {cause(e)}") from e


def attrs(obj):
    """Every attribute of an HDF5 object, as Python values (each checked: _attribute)."""
    return {key: _attribute(obj, key) for key in obj.attrs}


def _check_size(dataset):
    """Refuses, before reading, a dataset of another type than numbers or strings, one whose
    values are kept in another file (external storage, a virtual dataset), or one that cannot
    hold what it declares: declared but never written (no storage), more bytes than the
    whole file (uncompressed) or than its compressed bytes can expand to, or more than
    MOST_DATASET_BYTES."""
    where = f"dataset {shown(dataset.name)}"
    if not _plain_type(dataset.dtype):
        raise ValueError(f"{where} is {_kind(dataset.dtype)}, expected numbers or strings")
    layout = dataset.id.get_create_plist()
    if layout.get_external_count() or dataset.is_virtual:
        raise ValueError(f"{where} keeps its values in another file (external storage or a "
                         "virtual dataset); not read")
    declared = dataset.size * dataset.dtype.itemsize
    if declared == 0:
        return
    stored = dataset.id.get_storage_size()
    if stored == 0:
        raise ValueError(f"{where} declares {dataset.shape} values and holds none")
    if declared > MOST_DATASET_BYTES:
        raise ValueError(f"{where} declares {dataset.shape} values, {declared} bytes "
                         f"(at most {MOST_DATASET_BYTES})")
    file_size = os.path.getsize(dataset.file.filename)
    if stored > file_size:
        raise ValueError(f"{where} claims {stored} stored bytes in a file of {file_size}")
    filtered = bool(layout.get_nfilters())
    if not filtered and declared > file_size:
        raise ValueError(f"{where} declares {declared} bytes in a file of {file_size}")
    if filtered and declared > MOST_EXPANSION * stored:
        raise ValueError(f"{where} declares {declared} bytes from {stored} compressed bytes")


def array(dataset):
    """A dataset as a numpy array (strings decoded to str); its type and size checked first."""
    _check_size(dataset)
    try:
        data = np.asarray(dataset[()])
        if data.dtype.kind == "S":
            return np.char.decode(data, "utf-8")
        if data.dtype.kind == "O":
            return np.array([_text(x) for x in data.ravel()], dtype=object).reshape(data.shape)
        return data
    except (ValueError, TypeError, OverflowError) as e:
        raise ValueError(f"dataset {shown(dataset.name)}: {cause(e)}") from e


def units(datasets):
    """The attribute `units` of each dataset that has one (name -> str); only that attribute
    is read, checked as every attribute is."""
    return {k: _attribute(v, "units") for k, v in datasets.items() if "units" in v.attrs}


# The most soft links followed to reach one member: HDF5's own limit (H5Pset_nlinks).
MOST_SOFT_LINKS = 16


def member(parent, name, _followed=None):
    """parent[name] (a Dataset or Group), or None when `parent` has no member `name`; an
    external link is a ValueError naming it, never opened (h5py would open the file it names,
    and a FIFO there blocks for ever). A soft link is followed a step at a time, each step
    looked up the same way: its path may lead through an external link elsewhere in the file."""
    followed = [0] if _followed is None else _followed
    link = parent.get(name, getlink=True)  # the link itself: nothing it names is opened
    where = f"{parent.name.rstrip('/')}/{name}"
    if isinstance(link, h5py.ExternalLink):
        raise ValueError(f"{shown(where)} is an external link to {shown(link.filename)}, "
                         "not followed")
    if not isinstance(link, h5py.SoftLink):
        return None if link is None else parent.get(name)
    followed[0] += 1
    if followed[0] > MOST_SOFT_LINKS:
        raise ValueError(f"{shown(where)}: more than {MOST_SOFT_LINKS} soft links to follow")
    target = parent.file["/"] if link.path.startswith("/") else parent
    for part in (p for p in link.path.split("/") if p not in ("", ".")):
        if not isinstance(target, h5py.Group):
            return None
        target = member(target, part, followed)
    return target


def members(parent):
    """Every member of the group `parent` by name, each looked up by member (external links
    refused); a ValueError naming `parent` when it is not a group."""
    if not isinstance(parent, h5py.Group):
        raise ValueError(f"{shown(parent.name)} is not a group")
    return {name: member(parent, name) for name in parent}


def group(g):
    """The datasets directly inside `g`, its attributes and the datasets' units (subgroups are
    not included)."""
    datasets = {k: v for k, v in members(g).items() if isinstance(v, h5py.Dataset)}
    return Group({k: array(v) for k, v in datasets.items()}, attrs(g), units(datasets))


def optional_group(parent, name):
    """group(parent[name]), or None when `parent` has no such group."""
    g = member(parent, name)
    return group(g) if isinstance(g, h5py.Group) else None


def require(attributes, where, numbers=(), integers=(), strings=()):
    """Checks the types of the attributes a reader relies on (those present): each name in
    `numbers` an int or float (not a bool), in `integers` a whole number that fits in int64
    (not NaN, not 2.7: a reader's int() would cut it to another value), in `strings` a str;
    a ValueError naming the attribute and its value otherwise."""
    for name in numbers + integers + strings:
        if name not in attributes:
            continue
        v = attributes[name]
        if name in strings:
            ok, expected = isinstance(v, str), "a string"
        else:
            ok = isinstance(v, (int, float)) and not isinstance(v, bool)
            expected = "a number"
            if name in integers:
                ok = ok and -2 ** 63 <= v < 2 ** 63 and float(v).is_integer()
                expected = "a whole number"
        if not ok:
            raise ValueError(f"attribute '{name}' of {shown(where)} is {shown(v)}, "
                             f"not {expected}")
    return attributes


def read_hdf5(path, what, read):
    """Opens `path` (HDF5) and returns read(file); any failure is a JamioError naming it."""
    path = str(path)
    require_file(path, what)
    with reading(path, what):
        with h5py.File(path, "r") as f:
            return read(f)
