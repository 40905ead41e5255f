"""Cube files no run writes, for the hostile tables (tests/test_hostile.py, tests/test_cube_reader.py): a
sound cube edited in place, or an HDF5 file made to cost a reader (issue 28, classes 5, 11 and 18).

Each `make_*` takes the case's folder and writes `c.h5` there (from spec.yaml, which the case provides).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import h5netcdf
import h5py
import numpy as np
import xarray as xr
from click.testing import CliRunner

from friction_sweep.cli import main

CUBE = "c.h5"


def sound(d: Path) -> Path:
    """A cube `fsweep run` writes (theory, 2 x 40 points), at d/c.h5."""
    res = CliRunner().invoke(main, ["run", str(d / "spec.yaml"), "-o", str(d / CUBE), "-q"])
    assert res.exit_code == 0, res.output
    return d / CUBE


def edited(edit: Callable[[h5py.File], object]) -> Callable[[Path], None]:
    """A set-up: a sound cube, then `edit` on its HDF5 file opened for writing."""

    def setup(d: Path) -> None:
        with h5py.File(sound(d), "r+") as f:
            edit(f)

    return setup


def value(name: str, index, x) -> Callable[[Path], None]:
    """A sound cube whose `name` holds `x` at `index`."""

    def edit(f):
        f[name][index] = x

    return edited(edit)


def rewritten(change: Callable[[xr.Dataset], xr.Dataset]) -> Callable[[Path], None]:
    """A sound cube read by xarray, changed, and written again by xarray."""

    def setup(d: Path) -> None:
        path = sound(d)
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = change(ds.load())
        os.remove(path)
        ds.to_netcdf(path, engine="h5netcdf")

    return setup


def with_attribute(key: str, text: str, variable: str | None = None) -> Callable[[Path], None]:
    def edit(f):
        (f if variable is None else f[variable]).attrs[key] = text

    return edited(edit)


def declared(n_force: int, n_frequency: int, names=("transmissibility", "peak_transmissibility", "phase"),
             written: bool = False) -> Callable[[Path], None]:
    """A cube file of the given grid whose variables `names` are declared but (unless `written`) never
    written: its bytes are the coordinates' only (issue 28: 249 kB declaring three 10000 x 20000)."""

    def setup(d: Path) -> None:
        with h5netcdf.File(d / CUBE, "w") as f:
            f.dimensions = {"force_ratio": n_force, "frequency_ratio": n_frequency}
            f.create_variable("force_ratio", ("force_ratio",), "f8")[...] = np.linspace(0, 1, n_force)
            f.create_variable("frequency_ratio", ("frequency_ratio",), "f8")[...] = np.linspace(0.5, 2, n_frequency)
            for name in names:
                var = f.create_variable(name, ("force_ratio", "frequency_ratio"), "f8")
                if written:
                    var[...] = 1.0
            f.attrs["friction_sweep_version"] = "0.1.0"

    return setup


def compressed(n_force: int, n_frequency: int, names=("transmissibility", "peak_transmissibility", "phase"),
               value: float = 0.0) -> Callable[[Path], None]:
    """A cube file of the given grid whose variables `names` hold `value` everywhere, zlib-compressed (issue
    28 round 2: 982 kB holding 2000 x 5000 variables that expand to 555 MB in a reader)."""

    def setup(d: Path) -> None:
        with h5netcdf.File(d / CUBE, "w") as f:
            f.dimensions = {"force_ratio": n_force, "frequency_ratio": n_frequency}
            f.create_variable("force_ratio", ("force_ratio",), "f8")[...] = np.linspace(0, 1, n_force)
            f.create_variable("frequency_ratio", ("frequency_ratio",), "f8")[...] = np.linspace(0.5, 2, n_frequency)
            for name in names:
                f.create_variable(name, ("force_ratio", "frequency_ratio"), "f8", compression="gzip",
                                  compression_opts=1, chunks=(min(n_force, 1000), min(n_frequency, 1000)))[...] = value
            f.attrs["friction_sweep_version"] = "0.1.0"

    return setup


def _replace(f: h5py.File, name: str, make: Callable[[h5py.File, str], h5py.Dataset]) -> None:
    """Variable `name` of a sound cube made again by `make`, on the same dims (dimension scales attached,
    so that netCDF readers see it on its dims), its attributes kept."""
    old = f[name]
    attrs = {k: v for k, v in old.attrs.items() if k not in ("DIMENSION_LIST",)}
    scales = [old.dims[i][0] for i in range(old.ndim)]
    del f[name]
    new = make(f, name)
    for i, scale in enumerate(scales):
        new.dims[i].attach_scale(scale)
    for k, v in attrs.items():
        new.attrs[k] = v


def external(target: str, fifo: bool = False) -> Callable[[Path], None]:
    """A sound cube whose peak_phase keeps its values in the external file d/target (a FIFO: reading it
    waits for a writer forever)."""

    def setup(d: Path) -> None:
        path = sound(d)
        with h5py.File(path, "r") as f:
            shape, values = f["peak_phase"].shape, f["peak_phase"][...]
        if fifo:
            os.mkfifo(d / target)
        else:
            values.astype("<f8").tofile(d / target)
        with h5py.File(path, "r+") as f:
            _replace(f, "peak_phase", lambda f, name: f.create_dataset(
                name, shape, "<f8", external=[(target, 0, h5py.h5f.UNLIMITED)]))

    return setup


def virtual(d: Path) -> None:
    """A sound cube whose peak_phase is a virtual dataset mapping another file's values."""
    path = sound(d)
    with h5py.File(path, "r") as f:
        shape, values = f["peak_phase"].shape, f["peak_phase"][...]
    with h5py.File(d / "source.h5", "w") as g:
        g["data"] = values
    layout = h5py.VirtualLayout(shape, "<f8")
    layout[...] = h5py.VirtualSource(str(d / "source.h5"), "data", shape=shape)
    with h5py.File(path, "r+") as f:
        _replace(f, "peak_phase", lambda f, name: f.create_virtual_dataset(name, layout))


def linked(kind: str) -> Callable[[Path], None]:
    """A sound cube with a variable that is a link (soft, or external to another file), or a group."""

    def edit_in(d: Path) -> None:
        path = sound(d)
        with h5py.File(path, "r+") as f:
            if kind == "soft":
                f["transmissibility_moving"] = h5py.SoftLink("/transmissibility")
            elif kind == "external":
                with h5py.File(d / "other.h5", "w") as g:
                    g["data"] = np.zeros(3)
                f["stops_per_period_moving"] = h5py.ExternalLink(str(d / "other.h5"), "/data")
            else:
                f.create_group("extra").create_dataset("data", data=np.zeros(3))

    return edit_in


__all__ = ["CUBE", "sound", "edited", "value", "rewritten", "with_attribute", "declared", "compressed", "external",
           "virtual", "linked"]
