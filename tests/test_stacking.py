"""Cubes stack (issue 33, item 3): each declared effect and each constant of the physical system is a scalar
coordinate with units, so that a family of cubes swept over one of them concatenates along it
(`xr.concat`, `xr.open_mfdataset(..., combine="by_coords")`), ordered by its value; every reader takes the
new coordinates, and a cube written before them still reads.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.storage import cube

GRID = {"frequency_ratio": [0.5, 1.5, 3.0], "force_ratio": [0.1, 0.3]}
RIG = {"mass": "2 kg", "stiffness": "40 kN/m", "base_amplitude": "1 mm"}
#: written out of order: the stack orders them
DAMPINGS = (0.1, 0.02, 0.05)


def sweep(effects: dict | None = None, system: dict | None = None, method: str = "event"):
    spec = {"scene": {"excitation": "base", **({"effects": effects} if effects else {})}, "grid": GRID,
            "method": method}
    if system:
        spec["system"] = system
    return fs.sweep(spec)


@pytest.fixture(scope="module")
def family(tmp_path_factory):
    """{zeta: path} of cubes written by `fsweep run`, one per damping ratio."""
    folder = tmp_path_factory.mktemp("family")
    paths = {}
    for zeta in DAMPINGS:
        spec = folder / f"zeta{zeta}.yaml"
        spec.write_text(f"scene: {{excitation: base, effects: {{viscous_damping: {zeta}, static_friction_ratio: 1.5}}}}\n"
                        "system: {mass: 2 kg, stiffness: 40 kN/m, base_amplitude: 1 mm}\n"
                        f"grid: {{frequency_ratio: {GRID['frequency_ratio']}, force_ratio: {GRID['force_ratio']}}}\n"
                        "method: event\noutputs: [transmissibility, phase, regime]\n")
        paths[zeta] = folder / f"zeta{zeta}.nc"
        res = CliRunner().invoke(main, ["run", str(spec), "-o", str(paths[zeta]), "-q"])
        assert res.exit_code == 0, res.output
    return paths


def test_effects_and_system_constants_are_scalar_coordinates_with_units(family):
    ds = fs.open_cube(family[0.05])
    expected = {  # the rig: m = 2 kg, k = 40 kN/m, Y = 1 mm
        "viscous_damping": (0.05, "1"), "static_friction_ratio": (1.5, "1"), "mass": (2.0, "kg"),
        "stiffness": (40e3, "N m-1"), "natural_frequency": (math.sqrt(40e3 / 2.0) / (2.0 * math.pi), "Hz"),
        "length_scale": (1e-3, "m"), "excitation_force": (40.0, "N"),
    }
    for name, (value, units) in expected.items():
        assert ds[name].dims == () and name in ds.coords, name
        assert ds[name].values.item() == pytest.approx(value, rel=1e-14), name
        assert ds[name].attrs["units"] == units and ds[name].attrs["long_name"], name
    assert "contact_stiffness" not in ds.coords and "base_acceleration" not in ds.coords  # not declared, not held
    with h5py.File(family[0.05], "r") as f:  # CF 5.7: a scalar coordinate named by the variables it labels
        assert "viscous_damping" in f["transmissibility"].attrs["coordinates"].split()


def test_a_family_concatenates_along_its_effect_in_order(family):
    cubes = [fs.open_cube(family[z]) for z in DAMPINGS]
    stacked = xr.concat(cubes, dim="viscous_damping", combine_attrs="drop_conflicts").sortby("viscous_damping")
    assert stacked["transmissibility"].dims == ("viscous_damping", "force_ratio", "frequency_ratio")
    np.testing.assert_array_equal(stacked["viscous_damping"].values, sorted(DAMPINGS))
    assert stacked["viscous_damping"].attrs["units"] == "1"
    for zeta in DAMPINGS:
        np.testing.assert_array_equal(stacked["transmissibility"].sel(viscous_damping=zeta).values,
                                      fs.open_cube(family[zeta])["transmissibility"].values)
    assert "effects" not in stacked.attrs  # the attribute differs between the cubes: not the first one's
    # a dashpot to the ground (a bare ratio's place) damps at every r: more damping, less transmission at r = 3
    far = stacked["transmissibility"].sel(frequency_ratio=3.0, force_ratio=0.1).values
    assert far[0] > far[1] > far[2]


def test_open_mfdataset_combines_a_family_by_coords(family):
    pytest.importorskip("dask")
    with xr.open_mfdataset([family[z] for z in DAMPINGS], engine="h5netcdf", combine="by_coords",
                           preprocess=lambda ds: ds.expand_dims("viscous_damping")) as stacked:
        np.testing.assert_array_equal(stacked["viscous_damping"].values, sorted(DAMPINGS))
        assert stacked["transmissibility"].sizes == {"viscous_damping": 3, "force_ratio": 2, "frequency_ratio": 3}
        np.testing.assert_array_equal(stacked["transmissibility"].isel(viscous_damping=0).values,
                                      fs.open_cube(family[0.02])["transmissibility"].values)


def test_every_reader_takes_the_scalar_coordinates(family, tmp_path):
    path = str(family[0.1])
    for args in (["info", path], ["check", path], ["plot", path, "-o", str(tmp_path / "p.png")]):
        res = CliRunner().invoke(main, args)
        assert res.exit_code == 0, (args, res.output)


def test_a_cube_from_before_the_scalar_coordinates_still_reads(family, tmp_path):
    new = fs.open_cube(family[0.02])
    scalars = [name for name, c in new.coords.items() if c.ndim == 0]
    assert scalars
    old = new.drop_vars(scalars)
    path = tmp_path / "old.nc"
    cube.write_atomic(old, path, overwrite=False)
    back = fs.open_cube(path)
    xr.testing.assert_identical(back, old)
    assert CliRunner().invoke(main, ["check", str(path)]).exit_code == 0


@pytest.mark.parametrize("name, value, words", [
    ("viscous_damping", 0.07, "method_settings records the effect as 0.02"),
    ("static_friction_ratio", 0.5, "outside the valid range"),
    ("stiffness", -1.0, "outside the valid range"),
])
def test_a_scalar_coordinate_no_run_writes_is_refused(family, tmp_path, name, value, words):
    path = tmp_path / "edited.nc"
    path.write_bytes(family[0.02].read_bytes())
    with h5py.File(path, "r+") as f:
        f[name][()] = value
    with pytest.raises(fs.FsweepError, match=name):
        fs.open_cube(path)
    res = CliRunner().invoke(main, ["info", str(path)])  # every problem listed
    assert res.exit_code == 2 and words in res.output, res.output


def test_the_apis_theory_cube_has_the_system_but_no_effects():
    ds = sweep(system=RIG, method="theory")
    assert {"natural_frequency", "mass", "stiffness", "length_scale", "excitation_force"} <= set(ds.coords)
    assert not {"viscous_damping", "static_friction_ratio", "contact_stiffness"} & set(ds.coords)
    assert not [name for name, c in sweep(method="theory").coords.items() if c.ndim == 0]  # no system, no effects
