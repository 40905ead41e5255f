"""Assemble method outputs into the labelled cube, and write/read it (netCDF4 via h5netcdf).

A cube is built from its parts (cube_parts: every variable's dims, values and CF attributes from the
schema table, and the global attributes). `fsweep run` writes the parts straight through h5netcdf
(netcdf_bytes): building an xarray Dataset makes xarray import dask to ask whether any array is a
dask array, and writing one imports dask.distributed to pick a lock, ~0.5 s of a one-point run (issue
16's import floor). The Python API gets a Dataset of the same parts (build_dataset), and a Dataset is
written by the same writer; a test holds the file read back by xarray identical to the Dataset. How each
variable is stored (fill value, compression) is storage.encoding's one answer: the writer applies it and
every Dataset handed out (as_dataset, open_cube) carries it as `.encoding`, so a user's own to_netcdf
writes what `fsweep run` writes.
"""

from __future__ import annotations

import io
import os
import stat
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np

from friction_sweep.errors import FsweepError
from friction_sweep.printable import escape
from friction_sweep.storage import atomic, provenance
from friction_sweep.storage.encoding import COMPRESSION, encoding, h5netcdf_options
from friction_sweep.storage.outputs import file_kind
from friction_sweep.storage.schema import (
    ARRAY_COORDS,
    CONVENTIONS,
    COORDS,
    HISTORY_COORDS,
    HISTORY_DIM,
    LEGACY_HISTORY_DIM,
    PHYSICAL_COORDS,
    SCALAR_COORDS,
    STRUCTURE_COORDS,
    STRUCTURE_EXTRA_COORDS,
    STRUCTURE_VARIABLES,
    VARIABLES,
    cube_dims,
)

if TYPE_CHECKING:
    import xarray as xr

ENGINE: Final = "h5netcdf"

#: name -> (dims, values, attributes)
Entries = dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, Any]]]


class CubeParts(NamedTuple):
    coords: Entries
    data_vars: Entries
    attrs: dict[str, Any]


def cube_parts(arrays: dict, *, frequency_ratio, force_ratio, excitation: str, title: str, attrs: dict,
               history: str, physical: dict | None = None, physical_dims: bool = False,
               scalars: dict | None = None) -> CubeParts:
    """The given arrays, each labelled and given CF attributes from the schema table; `physical`: the
    physical coordinates (storage.physical) beside the grid's; `physical_dims`: a cube at constant base
    acceleration, whose dims are the physical coordinates (schema.cube_dims); `scalars`: the scalar
    coordinates (schema.SCALAR_COORDS: the scene's effects, the system's constants) by name. The arrays
    named in schema.ARRAY_COORDS (where each time history lies, the harmonics' numbers) become coordinates on
    their dims."""
    coords: Entries = {}
    for name, values in (("frequency_ratio", frequency_ratio), ("force_ratio", force_ratio),
                         *(physical or {}).items(), *(scalars or {}).items()):
        var = {**COORDS, **PHYSICAL_COORDS, **SCALAR_COORDS}[name]
        dims = cube_dims(name, var.dims, physical_dims)
        coords[name] = (dims, np.asarray(values, dtype=var.dtype), var.attrs(excitation))
    data_vars: Entries = {}
    for name, values in arrays.items():
        var = ARRAY_COORDS.get(name) or VARIABLES[name]  # KeyError: a method produced an undeclared variable
        dims = cube_dims(name, var.dims, physical_dims)
        (coords if name in ARRAY_COORDS else data_vars)[name] = (dims, np.asarray(values, dtype=var.dtype),
                                                                   var.attrs(excitation))
    return CubeParts(coords, data_vars, {"Conventions": CONVENTIONS, "title": title, "history": history, **attrs})


def structure_cube_parts(arrays: dict, *, coords: dict, excitation: str, title: str, attrs: dict,
                         history: str) -> CubeParts:
    """A structure cube's parts: `coords` (friction_scale, frequency, dof, contact) and `arrays` labelled and
    given CF attributes from the schema's structure table (schema.STRUCTURE_VARIABLES)."""
    labelled: list[Entries] = []
    for table, given in (({**STRUCTURE_COORDS, **STRUCTURE_EXTRA_COORDS}, coords), (STRUCTURE_VARIABLES, arrays)):
        entries: Entries = {}
        for name, values in given.items():
            var = table[name]  # KeyError here means an undeclared variable
            entries[name] = (var.dims, np.asarray(values, dtype=var.dtype), var.attrs(excitation))
        labelled.append(entries)
    return CubeParts(labelled[0], labelled[1],
                     {"Conventions": CONVENTIONS, "title": title, "history": history, **attrs})


def build_dataset(arrays: dict, *, frequency_ratio, force_ratio, excitation: str, title: str, attrs: dict,
                  history: str) -> xr.Dataset:
    """A Dataset of the given arrays (cube_parts)."""
    return as_dataset(cube_parts(arrays, frequency_ratio=frequency_ratio, force_ratio=force_ratio,
                                 excitation=excitation, title=title, attrs=attrs, history=history))


def as_dataset(parts: CubeParts) -> xr.Dataset:
    import xarray as xr

    return with_encoding(xr.Dataset(parts.data_vars, coords=parts.coords, attrs=parts.attrs))


def with_encoding(ds: xr.Dataset) -> xr.Dataset:
    """`ds` with each variable's `.encoding` the one the cube writer applies (storage.encoding; none of
    the compression keys for a cube the writer stores plainly: compresses), in place."""
    plain = not compresses(_parts_of(ds))
    for name, var in ds.variables.items():
        enc = encoding(var.values, coordinate=name in ds.coords)
        var.encoding = {key: value for key, value in enc.items() if key not in COMPRESSION} if plain else enc
    return ds


def _parts_of(ds: xr.Dataset) -> CubeParts:
    def entries(variables) -> Entries:
        return {str(name): (tuple(map(str, v.dims)), v.values, dict(v.attrs)) for name, v in variables.items()}

    return CubeParts(entries(ds.coords), entries(ds.data_vars), dict(ds.attrs))


def netcdf_bytes(parts: CubeParts) -> bytes:
    """The cube as netCDF4 bytes, as xarray writes a Dataset carrying storage.encoding's encodings (fill
    values, compression); strings as variable-length; non-dimension coordinates (a cube's physical ones,
    or its ratios where the dims are physical) named in the `coordinates` attribute of each variable whose
    dims hold theirs, else in the global one, as xarray's CF encoding does. What a cube never holds
    (bytes, dimensions of two sizes) is refused, not written differently from xarray; a Dataset's own
    .encoding is not read (the parts' encoding is the one answer). A cube so uniform that its compressed
    variables would expand beyond what the reader loads per byte of file (storage.bounds.expands_too_far:
    a grid of millions of points, every one stuck, compresses ~600 times) is written uncompressed, as every
    cube was before issue 33, so that fsweep reads every cube it writes."""
    from friction_sweep.storage import bounds  # beside the writer: it imports the spec (pydantic)

    data, expanded = _written(parts, compress=True)
    return data if not bounds.expands_too_far(expanded, len(data)) else _written(parts, compress=False)[0]


def compresses(parts: CubeParts) -> bool:
    """Whether netcdf_bytes stores the cube's numeric variables compressed. Only a cube whose compressed
    variables hold more than bounds.COMPRESSION_SLACK can expand too far, so only such a cube is written (in
    memory) to find out."""
    from friction_sweep.storage import bounds

    expanded = sum(values.nbytes for is_coord, entries in ((True, parts.coords), (False, parts.data_vars))
                   for _, values, _ in entries.values() if encoding(values, coordinate=is_coord).get("zlib"))
    if not bounds.expands_too_far(expanded, 0):
        return True
    data, expanded = _written(parts, compress=True)
    return not bounds.expands_too_far(expanded, len(data))


def _written(parts: CubeParts, *, compress: bool) -> tuple[bytes, int]:
    """netcdf_bytes' file, compressed as storage.encoding says or not at all, and the bytes its compressed
    variables hold."""
    import h5netcdf
    import h5py

    sizes: dict[str, int] = {}
    for name, (dims, values, _) in (*parts.coords.items(), *parts.data_vars.items()):
        for dim, size in zip(dims, values.shape, strict=True):
            if sizes.setdefault(dim, size) != size:
                raise ValueError(f"{name}: dimension {dim} has size {size}, elsewhere {sizes[dim]}")
        if values.dtype.kind == "S" or (values.dtype.kind == "O" and not all(isinstance(x, str) for x in values.flat)):
            raise ValueError(f"{name}: only numbers and str are written")
    auxiliary = {name: set(dims) for name, (dims, _, _) in parts.coords.items() if dims != (name,)}
    referenced: set[str] = set()
    expanded = 0  # bytes of the compressed variables
    buffer = io.BytesIO()
    with h5netcdf.File(buffer, "w") as f:
        f.dimensions = sizes
        for is_coord, entries in ((True, parts.coords), (False, parts.data_vars)):
            for name, (dims, values, attrs) in entries.items():
                dtype: Any = values.dtype
                enc = encoding(values, coordinate=is_coord)
                if not compress:
                    enc = {key: value for key, value in enc.items() if key not in COMPRESSION}
                expanded += values.nbytes if enc.get("zlib") else 0
                options = h5netcdf_options(enc)
                if values.dtype.kind in "UO":
                    dtype, values = h5py.string_dtype(), values.astype(object)
                var = f.create_variable(name, dims, dtype, **options)
                var[...] = values
                for key, value in attrs.items():
                    var.attrs[key] = value
                names = sorted(c for c, c_dims in auxiliary.items() if c_dims <= set(dims))
                if names and not is_coord:
                    var.attrs["coordinates"] = " ".join(names)
                    referenced.update(names)
        for key, value in parts.attrs.items():
            f.attrs[key] = value
        unreferenced = sorted(set(auxiliary) - referenced)
        if unreferenced:
            f.attrs["coordinates"] = " ".join(unreferenced)
    return buffer.getvalue(), expanded


def write_atomic(cube: CubeParts | xr.Dataset, path: Path, *, overwrite: bool) -> None:
    """Write the cube (its parts, or a Dataset) whole or not at all (storage.atomic); without `overwrite`
    an existing target is never replaced. Serialised in memory first: h5py writing straight to a full
    disk crashes the process, where writing its bytes fails cleanly with OSError."""
    parts = cube if isinstance(cube, CubeParts) else _parts_of(cube)
    atomic.write_bytes(path, netcdf_bytes(parts), overwrite=overwrite)


class UnsoundCube(FsweepError):
    """A cube that opens but holds what no run writes; `problems`: every audit finding (storage.audit).
    The message names the first, and how many more there are."""

    def __init__(self, path, problems: list):
        self.problems = problems
        more = f" (and {len(problems) - 1} more problems: fsweep info lists them)" if len(problems) > 1 else ""
        super().__init__(f"{escape(path)}: {problems[0]}{more}")


def legacy_names(ds: xr.Dataset) -> xr.Dataset:
    """`ds` with a cube's names from before issue 33 mapped to today's: the time-history dim `history`
    (which shadowed the CF global attribute `history`) is schema.HISTORY_DIM, and the histories' frequency and
    force ratios, then data variables, are coordinates on it. A cube of today's names is returned as it is."""
    if LEGACY_HISTORY_DIM not in ds.dims or HISTORY_DIM in ds.dims:
        return ds
    ds = ds.rename_dims({LEGACY_HISTORY_DIM: HISTORY_DIM})
    return ds.set_coords([name for name in HISTORY_COORDS if name in ds.data_vars])


def open_cube(path) -> xr.Dataset:
    """The result cube at `path`, loaded into memory (the file closed), audited: the one reader of
    `fsweep info`, `check`, `plot` and the Python API. FsweepError where `path` is not a regular file or
    cannot be read, the file is one no reader may load (storage.bounds: checked on its metadata before a
    value is read), it is not a friction_sweep cube, and UnsoundCube where it holds values or provenance
    attributes no run writes (storage.audit, storage.attributes). A cube written before issue 33 is read
    with today's names (legacy_names)."""
    import h5py
    import xarray as xr

    from friction_sweep.storage import audit, bounds

    try:
        name = os.fspath(path)
    except TypeError:
        raise FsweepError(f"a cube's path must be a str or os.PathLike, not {type(path).__name__}") from None
    shown = escape(name)
    try:
        # O_NONBLOCK: a FIFO opens at once (to be refused below) instead of waiting for a writer
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError) as err:  # ValueError: a NUL in the name
        raise FsweepError(f"{shown}: {getattr(err, 'strerror', None) or err}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise FsweepError(f"{shown} is not a regular file: it is {file_kind(mode)}")
    with os.fdopen(fd, "rb") as fh:
        try:
            with h5py.File(fh, "r") as f:
                bounds.check(f)
            fh.seek(0)
            # phony_dims: a dataset without dimension scales gets named dims (the audit refuses them) quietly
            with xr.open_dataset(fh, engine=ENGINE, phony_dims="access") as ds:
                ds = with_encoding(legacy_names(ds.load()))  # the file's own encoding (an older cube's:
                # uncompressed) is not handed on
        except bounds.Refused as err:
            raise FsweepError(f"{shown} is not a cube fsweep reads: {escape(err)}") from None
        except Exception as err:  # any reader failure means: not a cube we can read
            raise FsweepError(f"{shown} is not a readable result cube: {escape(' '.join(str(err).split()))}") from None
    if "friction_sweep_version" not in ds.attrs:
        raise FsweepError(f"{shown} is not a friction_sweep result cube (no provenance attributes)")
    problems = audit.provenance(ds) + audit.audit(ds)
    if not problems:  # pairs of values are compared once each value is sound
        problems = audit.together(ds)
    if problems:
        raise UnsoundCube(name, problems)
    return ds


__all__ = ["ENGINE", "CubeParts", "UnsoundCube", "cube_parts", "structure_cube_parts", "build_dataset", "as_dataset",
           "with_encoding", "compresses", "netcdf_bytes", "legacy_names", "write_atomic", "open_cube", "provenance"]
