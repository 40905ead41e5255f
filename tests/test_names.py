"""Names and labels of a cube that downstream tools take as they are (issue 33, item 4).

* No variable, dimension or coordinate is named like a CF global attribute: xarray resolves `ds.NAME` to a
  variable before an attribute, so a dim `history` made `ds.history` a DataArray instead of the provenance line.
* Where each time history lies (its frequency and force ratio) is a coordinate on the histories' dim.
* A `long_name` is one short line (xarray's plot labels are the long_name and units: a long one wraps); the
  detail is in `comment`.
* Every kind of cube passes the CF checker (strict) with these names and attributes.
* A cube written before these names (dim `history`, the ratios as data variables) is read with today's names.

Every kind of cube is built: the theory, a simulation with time histories, the Jenkins contact, static
friction (two starts), a physical system, and one at constant base acceleration (physical dims).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import STATIC
from test_encoding import cf_failures

import friction_sweep as fs
from friction_sweep.storage import cube, schema

#: the global attributes CF (§2.6.2) and the NetCDF User Guide's conventions give a file
CF_GLOBAL_ATTRIBUTES = ("title", "history", "institution", "source", "comment", "references", "Conventions")
#: xarray's plot label is "long_name [units]"; beyond this it wraps (matplotlib's default figure width)
LONG_NAME_MAX = 60
POINTS = [[0.5, 0.3], [1.5, 0.3], [0.8, 0.9]]
SMALL = {"frequency_ratio": [0.5, 1.5], "force_ratio": [0.3, 0.9]}

SPECS = {
    "theory": {"scene": {"excitation": "force"}, "grid": SMALL,
               "method": "theory", "outputs": ["transmissibility", "phase", "regime", "friction_energy",
                                               "transmitted_force"]},
    "event_time_history": {"scene": {"excitation": "joined"}, "grid": SMALL, "method": "event",
                           "outputs": ["transmissibility", "phase", "regime", "stability", "time_history"],
                           "time_history": {"points": POINTS, "samples_per_period": 16}},
    "harmonics": {"scene": {"excitation": "base"}, "grid": SMALL, "method": "auto",
                  "outputs": ["transmissibility", "phase", "regime", "harmonics"], "settings": {"harmonics": 5}},
    "jenkins": {"scene": {"excitation": "base", "effects": {"contact_stiffness": 10}}, "grid": SMALL,
                "method": "event", "outputs": ["transmissibility", "regime", "time_history"],
                "time_history": {"points": POINTS[:1], "samples_per_period": 16}},
    "static_friction": {"scene": {"excitation": "base", "effects": STATIC}, "grid": SMALL, "method": "event",
                        "outputs": ["transmissibility", "phase", "regime", "friction_energy"]},
    "physical_system": {"scene": {"excitation": "base"},
                        "system": {"mass": "2 kg", "stiffness": "40 kN/m", "base_amplitude": "1 mm"},
                        "grid": {"frequency": ["10 Hz", "40 Hz"], "friction_force": ["12 N"]}, "method": "event",
                        "outputs": ["transmissibility", "regime", "time_history"],
                        "time_history": {"points": [[0.5, 0.3], [1.5, 0.3]], "samples_per_period": 16}},
    "structure_harmonics": {"scene": {"excitation": "force"},
                            "structure": {"masses": {"blade": 1.0, "damper": 0.1},
                                          "springs": [["ground", "blade", 1.0], ["blade", "damper", 2.0]],
                                          "contacts": [{"name": "platform", "between": ["damper", "ground"],
                                                        "friction": 0.3, "static_friction_ratio": 1.2}],
                                          "forcing": {"blade": 1.0}},
                            "grid": {"frequency": [0.5, 1.5], "friction_scale": [1.0]}, "method": "event",
                            "outputs": ["amplitude", "phase", "regime", "harmonics"], "settings": {"harmonics": 3}},
    "constant_acceleration": {"scene": {"excitation": "base"},
                              "system": {"mass": "2 kg", "stiffness": "40 kN/m", "base_acceleration": "0.5 g"},
                              "grid": {"frequency": ["10 Hz", "40 Hz"], "friction_force": ["1 N", "2 N"]},
                              "method": "theory"},
}


@pytest.fixture(scope="module", params=sorted(SPECS))
def written(request, tmp_path_factory, compiled):
    """(kind, the API's Dataset, the cube as `fsweep run` writes it read back by open_cube)."""
    ds = fs.sweep(SPECS[request.param])
    path = tmp_path_factory.mktemp(request.param) / "cube.h5"
    cube.write_atomic(ds, path, overwrite=False)
    return request.param, ds, cube.open_cube(path), path


def _names(ds: xr.Dataset) -> set[str]:
    return {*map(str, ds.variables), *map(str, ds.dims), *map(str, ds.coords)}


def test_no_name_is_a_cf_global_attribute(written):
    kind, ds, back, path = written
    with xr.open_dataset(path, engine=cube.ENGINE) as raw:  # the file itself, not open_cube's mapping
        for d in (ds, back, raw):
            clash = _names(d) & set(CF_GLOBAL_ATTRIBUTES)
            assert not clash, (kind, clash)
            # attribute access reaches the provenance line, not a variable
            assert isinstance(d.history, str) and d.history == d.attrs["history"]
            assert d.title == d.attrs["title"] and d.Conventions == d.attrs["Conventions"]


def test_no_schema_name_is_a_cf_global_attribute():
    """Also the names no built cube above happens to hold (every table of the schema, every dim)."""
    tables = (schema.COORDS, schema.PHYSICAL_COORDS, schema.SCALAR_COORDS, schema.ARRAY_COORDS, schema.VARIABLES)
    names = {n for table in tables for n in table} | {d for table in tables for v in table.values() for d in v.dims}
    names |= set(schema.ACCELERATION_DIMS.values())
    assert not names & set(CF_GLOBAL_ATTRIBUTES)


def test_where_a_history_lies_is_a_coordinate_on_its_dim(written):
    kind, ds, back, path = written
    spec = SPECS[kind]
    if "time_history" not in spec.get("outputs", ()):
        assert schema.HISTORY_DIM not in ds.dims
        return
    points = np.asarray(spec["time_history"]["points"], dtype=float)
    with xr.open_dataset(path, engine=cube.ENGINE) as raw:
        for d in (ds, back, raw):
            for name, column in (("history_frequency_ratio", 0), ("history_force_ratio", 1)):
                assert name in d.coords and name not in d.data_vars, (kind, name)
                assert d[name].dims == (schema.HISTORY_DIM,)
                np.testing.assert_array_equal(d[name].values, points[:, column])
            assert d["history_displacement"].dims == (schema.HISTORY_DIM, "sample")
            # selecting a history carries where it lies
            one = d["history_displacement"].isel({schema.HISTORY_DIM: -1})
            assert float(one["history_frequency_ratio"]) == points[-1, 0]


def test_every_long_name_is_one_short_line(written):
    kind, ds, back, _ = written
    for d in (ds, back):
        for name, var in d.variables.items():
            long_name = var.attrs.get("long_name")
            if long_name is None:  # a dim's scale without a coordinate has none
                continue
            assert "\n" not in long_name and len(long_name) <= LONG_NAME_MAX, (kind, name, long_name)


@pytest.mark.parametrize("excitation", ["base", "force", "joined"])
def test_every_schema_long_name_is_one_short_line_with_the_detail_in_comment(excitation):
    tables = (schema.COORDS, schema.PHYSICAL_COORDS, schema.SCALAR_COORDS, schema.ARRAY_COORDS, schema.VARIABLES)
    for table in tables:
        for name, var in table.items():
            attrs = var.attrs(excitation)
            assert "\n" not in attrs["long_name"] and len(attrs["long_name"]) <= LONG_NAME_MAX, (name, attrs)
            assert "{" not in attrs.get("comment", "") and "{" not in attrs["long_name"], (name, attrs)
    # the detail moved, not lost: e.g. every case where the Floquet multiplier is NaN, the moving start's meaning
    assert "not_simulated" in schema.VARIABLES["floquet_multiplier"].attrs(excitation)["comment"]
    moving = schema.VARIABLES["transmissibility" + schema.MOVING_SUFFIX].attrs(excitation)
    assert "moving start" in moving["long_name"] and "kinetic friction alone" in moving["comment"]


def test_every_kind_of_cube_passes_the_cf_checker(written, tmp_path):
    """The names and attributes CF readers take as they are: the histories' coordinates, the comments. No `axis`
    X or Y on the grid: CF's X and Y are space, and the checker then asks for longitude and latitude units."""
    kind, _, _, path = written
    nc = tmp_path / "cube.nc"  # the checker goes by the extension
    nc.write_bytes(path.read_bytes())
    assert cf_failures(nc) == [], kind


def _legacy(path, out):
    """The cube at `path` as a cube from before issue 33 stores it: the histories' dim named `history`, their
    frequency and force ratios data variables (netCDF has no coordinate flag: a variable is a coordinate of
    another through its `coordinates` attribute, which the old writer never gave them)."""
    import h5py

    out.write_bytes(path.read_bytes())
    with h5py.File(out, "r+") as f:
        for var in f.values():
            coordinates = var.attrs.get("coordinates")
            if coordinates is not None:
                text = coordinates.decode() if isinstance(coordinates, bytes) else str(coordinates)
                kept = [c for c in text.split() if c not in schema.HISTORY_COORDS]
                if kept:
                    var.attrs["coordinates"] = " ".join(kept)
                else:
                    del var.attrs["coordinates"]
        f.move(schema.HISTORY_DIM, schema.LEGACY_HISTORY_DIM)  # the dimension scale: its name is the dim's
    return out


def test_a_cube_from_before_the_rename_is_read_with_todays_names(written, tmp_path):
    kind, ds, back, path = written
    if "time_history" not in SPECS[kind].get("outputs", ()):
        pytest.skip("no time history: nothing was named differently")
    old = _legacy(path, tmp_path / "old.h5")
    with xr.open_dataset(old, engine=cube.ENGINE) as raw:  # the file is laid out as an old cube is
        assert schema.LEGACY_HISTORY_DIM in raw.dims and "history_frequency_ratio" in raw.data_vars
    read = cube.open_cube(old)
    xr.testing.assert_identical(read, back)
    assert read.history == back.attrs["history"]
