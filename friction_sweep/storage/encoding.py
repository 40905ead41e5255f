"""How each variable of a cube is stored on disk, in xarray's encoding keys: the one answer that the cube
writer (storage.cube.netcdf_bytes) applies and that the API's Dataset carries as each variable's
`.encoding`, so that a user's own `ds.to_netcdf(path)` writes the file `fsweep run` writes.

* _FillValue: NaN for float data variables (xarray's default: NaN marks "no value"); none for integers
  (every flag code is meaningful), strings and every coordinate (CF 2.5.1: a coordinate variable must not
  have one, and no cube coordinate holds a missing value).
* compression: zlib (deflate) level COMPLEVEL after the byte shuffle, for numeric arrays of at least one
  value; chunks as HDF5's library picks them (h5py's heuristic, under 1 MiB). On the demo cube (22692
  points) this gives 2.62 MB -> 1.05 MB for ~20 ms more CPU per write; on the paper's planes (74896
  points) 4.97 MB -> 1.36 and 1.60 MB for ~30 ms (level 1: 1-3 % larger, ~5 ms faster; level 9: 1 %
  smaller, twice the time; without the shuffle: 20 % larger). Values read back bit for bit.
  Scalars and strings are stored plainly (a scalar cannot be chunked; netCDF refuses to compress
  variable-length strings).
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np

#: deflate level: the measured knee of size against write time (module docstring)
COMPLEVEL: Final = 4
#: the compression keys of a numeric array's encoding (netCDF4 and h5netcdf both read these)
COMPRESSION: Final = {"zlib": True, "complevel": COMPLEVEL, "shuffle": True}


def encoding(values: np.ndarray, *, coordinate: bool) -> dict[str, Any]:
    """The encoding of one cube variable holding `values` (a coordinate or a data variable)."""
    kind = np.asarray(values).dtype.kind
    enc: dict[str, Any] = {"_FillValue": np.nan if kind == "f" and not coordinate else None}
    if kind in "fiu" and np.ndim(values) and np.size(values):
        enc.update(COMPRESSION)
    return enc


def h5netcdf_options(enc: dict[str, Any]) -> dict[str, Any]:
    """An encoding as h5netcdf's create_variable keywords (what xarray's h5netcdf backend passes)."""
    options: dict[str, Any] = {"fillvalue": enc.get("_FillValue")}
    if enc.get("zlib"):
        options.update(compression="gzip", compression_opts=enc["complevel"], shuffle=enc["shuffle"])
    return options


__all__ = ["COMPLEVEL", "COMPRESSION", "encoding", "h5netcdf_options"]
