"""Assemble method outputs into the labelled cube, and write/read it (netCDF4 via h5netcdf)."""

from __future__ import annotations

from collections.abc import Hashable
from pathlib import Path
from typing import Any, Final

import numpy as np
import xarray as xr

from friction_sweep.storage import atomic, provenance
from friction_sweep.storage.schema import CONVENTIONS, COORDS, VARIABLES

ENGINE: Final = "h5netcdf"


def build_dataset(arrays: dict, *, frequency_ratio, force_ratio, excitation: str, title: str, attrs: dict,
                  history: str) -> xr.Dataset:
    """A Dataset of the given arrays, each labelled and given CF attributes from the schema table."""
    coords: dict[str, tuple] = {}
    for name, values in (("frequency_ratio", frequency_ratio), ("force_ratio", force_ratio)):
        var = COORDS[name]
        coords[name] = (var.dims, np.asarray(values, dtype=var.dtype), var.attrs(excitation))
    data_vars: dict[str, tuple] = {}
    for name, values in arrays.items():
        var = VARIABLES[name]  # KeyError here means a method produced an undeclared variable
        data_vars[name] = (var.dims, np.asarray(values, dtype=var.dtype), var.attrs(excitation))
    ds = xr.Dataset(data_vars, coords=coords)
    ds.attrs.update({"Conventions": CONVENTIONS, "title": title, "history": history})
    ds.attrs.update(attrs)
    return ds


def _encoding(ds: xr.Dataset) -> dict[Hashable, dict[str, Any]]:
    # explicit fill values: NaN for floats, none for the flag variable (every code is meaningful)
    enc: dict[Hashable, dict[str, Any]] = {}
    for name, var in ds.variables.items():
        if np.issubdtype(var.dtype, np.floating):
            enc[name] = {"_FillValue": np.nan if name not in ds.coords else None}
        else:
            enc[name] = {"_FillValue": None}
    return enc


def write_atomic(ds: xr.Dataset, path: Path, *, overwrite: bool) -> None:
    """Write the cube whole or not at all (storage.atomic); without `overwrite` an existing target is
    never replaced. Serialised in memory first: h5py writing straight to a full disk crashes the
    process, where writing its bytes fails cleanly with OSError."""
    atomic.write_bytes(path, ds.to_netcdf(engine=ENGINE, encoding=_encoding(ds)), overwrite=overwrite)


def open_cube(path) -> xr.Dataset:
    """Open a result cube (loaded into memory, the file closed)."""
    with xr.open_dataset(path, engine=ENGINE) as ds:
        return ds.load()


__all__ = ["ENGINE", "build_dataset", "write_atomic", "open_cube", "provenance"]
