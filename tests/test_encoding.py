"""One encoding for every cube (issue 33, item 1): the file `fsweep run` writes and the file a user's own
`ds.to_netcdf(path)` writes of the API's Dataset are stored alike (no _FillValue on a coordinate,
compressed) and pass the CF checker; an older uncompressed cube still reads and is handed on with that
encoding.

The IOOS compliance-checker (the `test` extra) runs where installed; the CF rule the API's Dataset broke
(CF 2.5.1: no _FillValue on a coordinate variable) and the compression are checked with h5py everywhere.
"""

from __future__ import annotations

import json
import warnings

import h5py
import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.storage.encoding import COMPRESSION

#: a physical theory sweep: grid coordinates, auxiliary physical coordinates, flags, floats with NaN
SPEC = {"scene": {"excitation": "base"},
        "system": {"mass": "2 kg", "stiffness": "40 kN/m", "base_amplitude": "1 mm"},
        "grid": {"frequency_ratio": [0.3, 0.5, 1.5, 2.0], "force_ratio": [0.1, 0.3, 0.9]},
        "method": "theory"}
ENGINES = ["h5netcdf", pytest.param("netcdf4", marks=pytest.mark.skipif(
    __import__("importlib").util.find_spec("netCDF4") is None, reason="netCDF4 not installed"))]


def cli_cube(tmp_path, name: str = "cli.nc"):
    from ruamel.yaml import YAML

    spec = tmp_path / "spec.yaml"
    with spec.open("w") as fh:
        YAML(typ="safe").dump(SPEC, fh)
    out = tmp_path / name
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "-q"])
    assert res.exit_code == 0, res.output
    return out


def cf_failures(path) -> list[str]:
    """The CF 1.10 checker's failures on the file at `path` (strict: every check counts)."""
    runner = pytest.importorskip("compliance_checker.runner")
    with warnings.catch_warnings():  # loading every checker imports its deprecated IOOS SOS suite too
        warnings.simplefilter("ignore", DeprecationWarning)
        runner.CheckSuite().load_all_available_checkers()
    report = path.with_suffix(".json")
    runner.ComplianceChecker.run_checker(str(path), ["cf:1.10"], 0, "strict", output_filename=str(report),
                                         output_format="json")
    result = json.loads(report.read_text())["cf:1.10"]
    return [msg for check in result["all_priorities"] if check["value"][0] < check["value"][1]
            for msg in check["msgs"]]


def storage(path) -> dict[str, tuple]:
    """Per variable: (has a _FillValue attribute, compression, shuffle)."""
    with h5py.File(path, "r") as f:
        return {name: ("_FillValue" in f[name].attrs, f[name].compression, f[name].shuffle) for name in f}


@pytest.fixture(scope="module")
def api_dataset():
    return fs.sweep(SPEC)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_apis_own_to_netcdf_keeps_coordinates_free_of_fill_values(tmp_path, api_dataset, engine):
    """CF 2.5.1: a coordinate variable must not have _FillValue; xarray adds NaN to every float unless
    the Dataset's encoding says otherwise (the API's Dataset carried none)."""
    path = tmp_path / "mine.nc"
    api_dataset.to_netcdf(path, engine=engine)
    stored = storage(path)
    for name in api_dataset.coords:
        assert not stored[name][0], name
    for name, var in api_dataset.data_vars.items():
        assert stored[name][0] == (var.dtype.kind == "f"), name
    with xr.open_dataset(path, engine="h5netcdf") as back:
        xr.testing.assert_identical(back.load(), api_dataset)


@pytest.mark.parametrize("engine", ENGINES)
def test_the_apis_to_netcdf_passes_the_cf_checker(tmp_path, api_dataset, engine):
    path = tmp_path / "mine.nc"
    api_dataset.to_netcdf(path, engine=engine)
    assert cf_failures(path) == []


def test_a_cli_cube_passes_the_cf_checker(tmp_path):
    assert cf_failures(cli_cube(tmp_path)) == []


def test_cubes_are_compressed_and_stored_as_the_apis_to_netcdf_stores_them(tmp_path, api_dataset):
    """Every numeric array compressed (deflate after the shuffle), by `fsweep run` and by the user's own
    to_netcdf of the API's Dataset alike; the values read back bit for bit."""
    ours = cli_cube(tmp_path)
    theirs = tmp_path / "mine.nc"
    api_dataset.to_netcdf(theirs, engine="h5netcdf")
    stored = storage(ours)
    assert stored == storage(theirs)
    for name, var in api_dataset.variables.items():  # a scalar (the system's constants) cannot be chunked
        assert stored[name][1:] == (("gzip", True) if var.ndim else (None, False)), name
    back = fs.open_cube(ours)
    for name, var in api_dataset.variables.items():
        np.testing.assert_array_equal(back[name].values, var.values, strict=True)


def test_an_uncompressed_cube_still_reads_and_is_handed_on_with_the_encoding(tmp_path, api_dataset):
    """A cube written before the encoding (contiguous, NaN fills on physical coordinates) opens as
    before; the Dataset handed out writes the file a new run writes."""
    old = tmp_path / "old.h5"
    with xr.open_dataset(cli_cube(tmp_path), engine="h5netcdf") as ds:
        ds.load().to_netcdf(old, engine="h5netcdf", encoding={name: {"zlib": False, "_FillValue": np.nan}
                                                               for name, v in ds.variables.items()
                                                               if v.dtype.kind == "f"})
    assert storage(old)["force_ratio"] == (True, None, False)
    back = fs.open_cube(old)
    xr.testing.assert_equal(back, api_dataset)  # the values (the provenance names another spec source)
    again = tmp_path / "again.nc"
    back.to_netcdf(again, engine="h5netcdf")
    assert storage(again) == storage(tmp_path / "cli.nc")


def test_a_cube_too_uniform_to_compress_within_the_readers_bound_is_written_plainly(tmp_path):
    """A grid where every point is stuck compresses ~600 times: compressed, its variables would expand
    beyond what the reader loads per byte of file (storage.bounds), so the writer stores it uncompressed
    and fsweep reads every cube it writes."""
    from friction_sweep.storage import bounds, cube, provenance

    r, beta = np.linspace(0.05, 5.0, 2000), np.linspace(1.0, 2.0, 1000)
    zeros = np.zeros((beta.size, r.size))
    parts = cube.cube_parts({"transmissibility": zeros, "peak_transmissibility": zeros, "stops_per_period": zeros},
                            frequency_ratio=r, force_ratio=beta, excitation="base", title="t", history="test",
                            attrs=provenance.attributes(spec_text="", spec_path="s.yaml", excitation="base",
                                                        method="theory", settings={}))
    squeezed = tmp_path / "squeezed.nc"  # compressed anyway: the reader refuses it
    api = cube.as_dataset(parts)
    api.to_netcdf(squeezed, engine="h5netcdf", encoding={name: dict(COMPRESSION) for name in api.data_vars})
    with pytest.raises(fs.FsweepError, match=f"up to {bounds.MAX_COMPRESSION} times their size"):
        fs.open_cube(squeezed)
    assert not cube.compresses(parts)
    path = tmp_path / "stuck.nc"
    cube.write_atomic(parts, path, overwrite=False)
    assert storage(path)["transmissibility"][1] is None
    back = fs.open_cube(path)
    np.testing.assert_array_equal(back["transmissibility"].values, zeros)
    # the API's Dataset and a cube read back carry the writer's choice, so a user's own to_netcdf writes a
    # file fsweep reads (the same storage as the cube's)
    for ds, name in ((api, "api.nc"), (back, "again.nc")):
        assert "zlib" not in ds["transmissibility"].encoding
        ds.to_netcdf(tmp_path / name, engine="h5netcdf")
        assert storage(tmp_path / name) == storage(path)
        fs.open_cube(tmp_path / name)
