"""What a cube file may make a reader load: checked with h5py on the file's metadata, before xarray
reads a single value.

An HDF5 file is a description of data as much as data: a 249 kB file can declare variables of 10^8
values each that were never written (reading them materialises gigabytes of fill values), store a
variable's values in an external file (a FIFO there blocks the reader forever), map it onto other files
(a virtual dataset), or link elsewhere. A cube fsweep writes does none of that, so `check` refuses:

* anything at the root but datasets reached by hard links (groups, soft or external links);
* a dataset with external storage or a virtual layout, an extensible shape, or values that are not
  plain numbers (strings, compounds, references: no cube variable holds them), but for a structure
  cube's names (its `dof` and `contact` coordinates: one dimension of at most spec.structure.MAX_NAMES
  variable-length strings, whose bytes a file stores in itself: reading them costs at most its size);
* a dataset of more values than the largest array fsweep writes (MAX_VALUES: a grid of
  spec.grid.MAX_POINTS, or a time history of spec.model.MAX_HISTORY_SAMPLES samples), more datasets
  than a cube can hold (MAX_DATASETS), or more bytes in all than MAX_CUBE_BYTES;
* a dataset that declares values it does not store: every variable a run writes is written whole, so
  its allocated storage holds all its bytes (compressed: some bytes); only the netCDF dimension scales
  of dims without a coordinate (history_point, sample) are left unwritten, as netCDF itself does;
* compressed (filtered) datasets that would expand to more than MAX_COMPRESSION times the file's size
  (plus COMPRESSION_SLACK; a 982 kB file expanded to 555 MB): what a reader loads stays a small multiple
  of the file's size;
* a dataset or the root with more than MAX_ATTRIBUTES attributes.

Each refusal is a `Refused` with the reason; `check` reads no value, so its cost is the metadata's.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.spec.grid import MAX_POINTS
from friction_sweep.spec.model import MAX_HISTORY_SAMPLES
from friction_sweep.spec.structure import MAX_NAMES
from friction_sweep.storage.schema import (
    ARRAY_COORDS,
    COORDS,
    HISTORY_DIM,
    PHYSICAL_COORDS,
    SCALAR_COORDS,
    STRUCTURE_COORDS,
    STRUCTURE_EXTRA_COORDS,
    STRUCTURE_VARIABLES,
    VARIABLES,
)

#: the most values one array of a cube holds: its grid's points, or a time history's samples
MAX_VALUES = max(MAX_POINTS, MAX_HISTORY_SAMPLES)
#: every variable and coordinate the schema knows, and a dimension scale for each dim it names
MAX_DATASETS = max(len(VARIABLES) + len(COORDS) + len(PHYSICAL_COORDS) + len(SCALAR_COORDS) + len(ARRAY_COORDS),
                   len(STRUCTURE_VARIABLES) + len(STRUCTURE_COORDS) + len(STRUCTURE_EXTRA_COORDS)) + 8
#: the largest cube a run can write: every schema variable at its largest (grid variables at MAX_POINTS
#: points, histories at MAX_HISTORY_SAMPLES), each coordinate a grid axis at its longest
MAX_CUBE_BYTES = sum(np.dtype(v.dtype).itemsize * (MAX_HISTORY_SAMPLES if HISTORY_DIM in v.dims else MAX_POINTS)
                     for v in (*VARIABLES.values(), *COORDS.values(), *PHYSICAL_COORDS.values(),
                               *ARRAY_COORDS.values()))
#: the most bytes a file's compressed (filtered) variables may expand to per byte of the file. fsweep writes
#: its cubes compressed (storage.encoding), a few times smaller than their values (the paper's planes 3-4
#: times: a grid's varied floats barely compress, its flags and constant variables do), so a reader loads at
#: most this multiple of the file's size (plus COMPRESSION_SLACK); beyond it a file is a decompression bomb
MAX_COMPRESSION = 64
#: what compressed variables may hold beyond MAX_COMPRESSION x the file's size (a small cube's chunk headers
#: and constant variables weigh more than their data)
COMPRESSION_SLACK = 16 << 20
#: a variable has a dozen CF attributes, the root a few dozen
MAX_ATTRIBUTES = 256
#: how netCDF (and h5netcdf) marks a dimension scale that is not a variable: never written, never loaded
_DIMENSION_ONLY = b"This is a netCDF dimension but not a netCDF variable."


class Refused(ValueError):
    """The file holds something no cube holds, or more than a reader may load."""


def check(f) -> None:
    """Refuse (raise Refused) what the open h5py File `f` must not make a reader load."""
    import h5py

    _attributes(f, "the file")
    names = list(f)
    if len(names) > MAX_DATASETS:
        raise Refused(f"{len(names)} objects at its root; a cube has at most {MAX_DATASETS}")
    total = expanded = 0
    for name in names:
        link = f.get(name, getlink=True)
        if not isinstance(link, h5py.HardLink):
            raise Refused(f"{name!r} is a link ({type(link).__name__}); a cube holds its variables, never links")
        obj = f[name]
        if not isinstance(obj, h5py.Dataset):
            raise Refused(f"{name!r} is a {type(obj).__name__.lower()}; a cube holds variables only")
        nbytes, filtered = _dataset(name, obj)
        total += nbytes
        expanded += filtered
        if total > MAX_CUBE_BYTES:
            raise Refused(f"its variables declare more than {_bytes(MAX_CUBE_BYTES)}, more than the largest "
                          "cube fsweep writes")
    size = f.id.get_filesize()
    if expands_too_far(expanded, size):
        raise Refused(f"its compressed variables expand to {expanded} bytes, {expanded / size:.0f} times the file's "
                      f"{size}; fsweep reads compressed cubes up to {MAX_COMPRESSION} times their size (decompress "
                      "it: nccopy -d0)")


def expands_too_far(expanded: int, size: int) -> bool:
    """Whether compressed variables of `expanded` bytes in all, in a file of `size` bytes, expand beyond
    what a reader loads (MAX_COMPRESSION times the file, plus COMPRESSION_SLACK): the reader refuses such a
    file, and the cube writer stores such a cube uncompressed instead (storage.cube.netcdf_bytes)."""
    return expanded > MAX_COMPRESSION * size + COMPRESSION_SLACK


#: the coordinates of names (a structure cube's masses and contacts)
_NAMES = tuple(name for name, v in STRUCTURE_COORDS.items() if v.dtype is str)


def _dataset(name: str, ds) -> tuple[int, int]:
    """The bytes the dataset `ds` makes a reader load, all and those it decompresses (Refused where it must
    not be read)."""
    import h5py

    if ds.is_virtual:
        raise Refused(f"variable {name!r} is a virtual dataset (its values live in other files)")
    if ds.external:
        raise Refused(f"variable {name!r} keeps its values in an external file ({ds.external[0][0]!r}); a cube "
                      "holds its own values")
    dtype = ds.dtype
    if name in _NAMES and ds.ndim == 1 and ds.shape[0] <= MAX_NAMES and ds.maxshape == ds.shape \
            and h5py.check_string_dtype(dtype) is not None and h5py.check_string_dtype(dtype).length is None:
        _attributes(ds, f"variable {name!r}")
        return 0, 0  # a structure's names: their bytes are in the file, read at most once
    if dtype.kind not in "iuf" or dtype.itemsize > 8 or dtype.fields is not None or dtype.subdtype is not None:
        raise Refused(f"variable {name!r} holds {_kind(dtype)}, not numbers")
    if ds.shape is None:
        raise Refused(f"variable {name!r} has no shape")
    if ds.maxshape != ds.shape:
        raise Refused(f"variable {name!r} is extensible (max shape {ds.maxshape}); a cube's are fixed")
    values = math.prod(ds.shape)
    if values > MAX_VALUES:
        raise Refused(f"variable {name!r} declares {values} values ({' x '.join(map(str, ds.shape))}); fsweep "
                      f"writes at most {MAX_VALUES} in one variable")
    _attributes(ds, f"variable {name!r}")
    nbytes = values * dtype.itemsize
    stored = ds.id.get_storage_size()
    if _dimension_only(ds):
        return 0, 0  # h5netcdf reads its shape as a dimension's size, never its values
    filtered = bool(ds.id.get_create_plist().get_nfilters())  # compressed: fewer bytes stored than held
    if nbytes and (stored == 0 or (not filtered and stored < nbytes)):
        raise Refused(f"variable {name!r} declares {values} values but stores {stored} of their {nbytes} bytes; "
                      "a cube stores every value it holds")
    return nbytes, (nbytes if filtered else 0)


def _dimension_only(ds) -> bool:
    text = ds.attrs.get("NAME", b"")
    return isinstance(text, bytes) and text.startswith(_DIMENSION_ONLY) and ds.ndim == 1


def _attributes(obj, what: str) -> None:
    n = obj.attrs.__len__()
    if n > MAX_ATTRIBUTES:
        raise Refused(f"{what} has {n} attributes; a cube's have at most {MAX_ATTRIBUTES}")


def _kind(dtype) -> str:
    if dtype.kind == "O" or dtype.kind in "SU":
        return "strings" if dtype.kind in "SU" or dtype.metadata and "vlen" in dtype.metadata else "objects"
    if dtype.fields is not None:
        return "records (a compound type)"
    return f"{dtype} values"


def _bytes(n: int) -> str:
    return f"{n / 2**30:.1f} GiB"


__all__ = ["MAX_VALUES", "MAX_DATASETS", "MAX_CUBE_BYTES", "MAX_COMPRESSION", "COMPRESSION_SLACK",
           "MAX_ATTRIBUTES", "Refused", "check", "expands_too_far"]
