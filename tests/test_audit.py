"""friction_sweep.storage.audit: a sound cube of every kind passes; every corrupted value is reported, with
its count, an example and where it sits (issue 14, item 7: `fsweep info` trusted a damaged cube)."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import OUTPUTS, in_dir, write_spec

from friction_sweep import methods
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.storage import audit, cube, schema
from friction_sweep.theory.phase import wrap_lag_degrees

R = np.array([0.5, 1.0, 2.0])  # r = 1 with beta <= pi/4 is unbounded: NaN, never inf
BETA = np.array([0.1, 0.5, 1.0])  # beta = 1 is stuck (base): amplitudes 0, phases NaN
HISTORY_POINTS = [[0.5, 0.1], [1.0, 0.1]]  # the second is unbounded: no orbit, a NaN row


def make_cube(method, excitation="base", effects=None, histories=False, r=R, beta=BETA):
    m = methods.get(method)
    arrays = m.compute_tile(excitation, r, beta, OUTPUTS, effects=effects)
    if histories:
        pts = np.asarray(HISTORY_POINTS)
        arrays.update(m.time_histories(excitation, pts, 16, effects), history_frequency_ratio=pts[:, 0],
                      history_force_ratio=pts[:, 1])
    return cube.build_dataset(arrays, frequency_ratio=r, force_ratio=beta, excitation=excitation,
                              title="audit test", attrs={}, history="test")


@pytest.fixture(scope="module")
def static():
    """Event, base, static friction 1.5: every state variable twice, steady_states, time histories."""
    return make_cube("event", effects={"static_friction_ratio": 1.5}, histories=True)


def only(problems, variable):
    found = [p for p in problems if p.variable == variable]
    assert len(found) == 1, problems
    assert all(p.variable == variable for p in problems), problems
    return found[0]


# --- sound cubes: nothing to report -----------------------------------------------------------------------


def test_a_cube_written_by_the_cli_passes(tmp_path):
    write_spec(tmp_path)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["run", "spec.yaml", "--quiet"])
    assert res.exit_code == 0, res.output
    assert audit.audit(cube.open_cube(tmp_path / "out.h5")) == []


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_theory_cubes_pass(excitation):
    r = np.round(np.linspace(0.2, 3.0, 29), 12)
    beta = np.array([0.0, 0.3, np.pi / 4, 0.9, 1.0, 1.5])
    ds = make_cube("theory", excitation, r=np.union1d(r, [1.0]), beta=beta)
    assert audit.audit(ds) == []


@pytest.mark.parametrize("effects", [None, {"static_friction_ratio": 1.5}, {"viscous_damping": 0.05}],
                         ids=["plain", "static", "damped"])
@pytest.mark.slow
def test_event_cubes_pass_with_their_nan_points(effects):
    ds = make_cube("event", effects=effects, histories=True)
    assert audit.audit(ds) == []
    # what legitimately has no number: the unbounded point is NaN (not inf), stuck phases are NaN
    t = ds["transmissibility"].sel(frequency_ratio=1.0, force_ratio=0.1)
    if effects is None:
        assert ds["regime"].sel(frequency_ratio=1.0, force_ratio=0.1) == Regime.UNBOUNDED
        assert np.isnan(t) and np.isnan(ds["orbit_period"].sel(frequency_ratio=1.0, force_ratio=0.1))
        assert ds["history_orbit_period"].values[1] == 0 and np.isnan(ds["history_displacement"].values[1]).all()
    assert np.isnan(ds["phase"].sel(force_ratio=1.0)).all()
    for name in ds.data_vars:
        if ds[name].dtype.kind == "f":
            assert not np.isinf(ds[name].values).any(), name


def test_auto_and_joined_cubes_pass():
    assert audit.audit(make_cube("auto")) == []
    assert audit.audit(make_cube("event", "joined", effects={"static_friction_ratio": 1.5})) == []


def test_the_wrap_can_give_270_and_that_is_valid(static):
    lag = wrap_lag_degrees(np.radians(-90.00000000000001))
    assert lag == 270.0  # the wrap's rounding: [-90, 270) holds only in exact arithmetic
    ds = static.copy(deep=True)
    ds["phase"][0, 0] = lag
    ds["peak_phase"][0, 0] = -90.0
    assert audit.audit(ds) == []


# --- corrupted values: each reported once, with count, example and place -----------------------------------


BAD = [
    # variable, value, words in the message
    ("transmissibility", -1.86e230, "outside the valid range [0, 1e+15]"),
    ("transmissibility", -0.5, "outside the valid range [0, 1e+15]"),
    ("transmissibility", 1e230, "outside the valid range [0, 1e+15]"),
    ("transmissibility", math.inf, "are infinite"),
    ("peak_transmissibility", -math.inf, "are infinite"),
    ("transmissibility_moving", -1.0, "outside the valid range [0, 1e+15]"),
    ("phase", 400.0, "outside the valid range [-90, 270]"),
    ("peak_phase", -90.5, "outside the valid range [-90, 270]"),
    ("phase_moving", 1e300, "outside the valid range [-90, 270]"),
    ("regime", 93, "are not valid regime codes"),
    ("regime", -1, "are not valid regime codes"),
    ("regime_moving", 5, "are not valid regime codes"),
    ("steady_state", 9, "are not valid steady_state codes"),  # 8 is unbalanced
    ("steady_states", 3, "outside the valid range [0, 2]"),
    ("stuck_fraction", 2.0, "outside the valid range [0, 1]"),
    ("stuck_fraction", -1e-3, "outside the valid range [0, 1]"),
    ("stops_per_period", -1.0, "outside the valid range [0, 9.0072e+15]"),
    ("periods", 1e200, "outside the valid range [0, 9.0072e+15]"),
    ("orbit_period", 1.5, "are not whole numbers"),
    ("orbit_period", 0.0, "outside the valid range [1, 9.0072e+15]"),
]


@pytest.mark.parametrize("name, value, words", BAD, ids=[f"{n}={v}" for n, v, _ in BAD])
def test_a_corrupted_grid_value_is_reported(static, name, value, words):
    ds = static.copy(deep=True)
    ds[name][1, 2] = value  # force_ratio 0.5, frequency_ratio 2.0: a sound continuous point
    assert ds[name].values[1, 2] == value
    p = only(audit.audit(ds), name)
    assert (p.count, p.total) == (1, 9)
    assert p.example == value and p.index == (1, 2)
    assert dict(p.where) == {"force_ratio": 0.5, "frequency_ratio": 2.0}
    assert words in str(p)
    assert str(p).startswith(f"{name}: 1 of 9 values ")
    assert str(p).endswith(" at frequency_ratio=2, force_ratio=0.5)")


def test_the_cli_message_reads_as_in_the_issue(static):
    ds = static.copy(deep=True)
    ds["regime"][0, 0] = 93
    ds["regime"][2, 1] = 93
    (p,) = audit.audit(ds)
    assert str(p) == ("regime: 2 of 9 values are not valid regime codes (e.g. 93 at frequency_ratio=0.5, "
                      "force_ratio=0.1)")


@pytest.mark.parametrize("name, value, words", [
    ("history_displacement", 1e200, "outside the valid range [-1e+15, 1e+15]"),
    ("history_excitation", 1.5, "outside the valid range [-1, 1]"),
    ("history_regime", 9, "are not valid regime codes"),
    ("history_orbit_period", 0.5, "are not whole numbers"),
    ("history_time", -math.inf, "are infinite"),
])
def test_a_corrupted_history_value_is_reported(static, name, value, words):
    ds = static.copy(deep=True)
    idx = (0, 3) if ds[name].ndim == 2 else (0,)
    ds[name][idx] = value
    p = only(audit.audit(ds), name)
    assert p.count == 1 and p.example == value and p.where == ()
    assert words in str(p)
    assert str(p).endswith(" at history_point[0], sample[3])" if len(idx) == 2 else " at history_point[0])")


def test_other_variables_are_checked(static):
    auto = make_cube("auto")
    auto["method_used"][0, 0] = 2
    assert "are not valid method_used codes" in str(only(audit.audit(auto), "method_used"))
    joined = make_cube("theory", "joined")
    joined["relative_peak_phase"][0, 0] = -180.0
    joined["relative_peak_amplitude"][0, 2] = -2.0
    assert {p.variable for p in audit.audit(joined)} == {"relative_peak_phase", "relative_peak_amplitude"}
    ds = static.copy(deep=True)
    ds["continuous_limit"][1] = -0.25
    p = only(audit.audit(ds), "continuous_limit")
    assert dict(p.where) == {"frequency_ratio": 1.0} and "[0, inf)" in str(p)


def test_many_bad_values_are_counted_once_per_fault(static):
    ds = static.copy(deep=True)
    ds["transmissibility"][:, 0] = -1.0
    ds["transmissibility"][2, 2] = math.inf
    problems = audit.audit(ds)
    assert [(p.variable, p.count, p.example) for p in problems] == [
        ("transmissibility", 1, math.inf), ("transmissibility", 3, -1.0)]


# --- coordinates and structure ----------------------------------------------------------------------------


@pytest.mark.parametrize("name, i, value, words", [
    ("frequency_ratio", 0, 0.0, "outside the valid range (0, inf)"),
    ("frequency_ratio", 0, -0.5, "outside the valid range (0, inf)"),
    ("frequency_ratio", 2, math.nan, "are NaN"),
    ("frequency_ratio", 2, math.inf, "are infinite"),
    ("force_ratio", 0, -0.1, "outside the valid range [0, inf)"),
    ("force_ratio", 1, 0.05, "are not strictly increasing"),
    ("force_ratio", 1, 0.1, "are not strictly increasing"),
])
def test_a_corrupted_coordinate_is_reported(static, name, i, value, words):
    values = static[name].values.copy()
    values[i] = value
    ds = static.assign_coords({name: values})
    p = only(audit.audit(ds), name)
    assert words in str(p)
    assert str(p).endswith(f"at {name}[{p.index[0]}])")


def test_structure_is_checked(static):
    ds = static.copy(deep=True)
    ds["foo"] = ds["transmissibility"] * 2
    ds["transmissibility"] = ds["transmissibility"].transpose()
    ds["regime"] = ds["regime"].astype(np.float64)
    ds = ds.drop_vars("force_ratio")
    got = [str(p) for p in audit.audit(ds)]
    assert got == [
        "force_ratio: is missing: every result cube has this coordinate",
        "transmissibility: has dims (frequency_ratio, force_ratio); the schema says (force_ratio, frequency_ratio)",
        "regime: is stored as float64; the schema says int8",
        "foo: is not a variable of the result cube schema",
    ]


def test_every_schema_variable_has_its_valid_values():
    for name, var in {**schema.COORDS, **schema.VARIABLES}.items():
        if np.issubdtype(var.dtype, np.integer) and name != "steady_states":
            assert var.flag_values is not None and var.valid_range is None, name
        else:
            assert var.valid_range is not None and var.flag_values is None, name
            lo, hi = var.valid_range
            assert lo < hi, name
    # metadata only: the attributes written to a cube are what they were
    assert "valid_min" not in schema.VARIABLES["transmissibility"].attrs("base")


# --- bytes flipped in the file ------------------------------------------------------------------------------


def flip(path, offset, n):
    with open(path, "r+b") as fh:
        fh.seek(offset)
        data = bytearray(fh.read(n))
        fh.seek(offset)
        fh.write(bytes(b ^ 0xFF for b in data))


def test_flipped_bytes_in_the_file_are_reported(tmp_path, static):
    path = tmp_path / "cube.h5"
    # stored uncompressed (a cube from before issue 33, or rewritten so by another tool): a flipped byte of a
    # compressed cube breaks its deflate stream, which the reader refuses as unreadable instead
    static.to_netcdf(path, engine="h5netcdf", encoding={name: {"zlib": False} for name in static.variables})
    with h5py.File(path, "r") as f:
        t, regime = f["transmissibility"], f["regime"]
        assert t.dtype == np.float64 and regime.dtype == np.int8
        t_offset, r_offset = t.id.get_offset(), regime.id.get_offset()
    assert t_offset is not None and r_offset is not None  # contiguous: the values lie there in C order
    # 8 bytes: the whole of transmissibility at (force_ratio 0.5, frequency_ratio 0.5), flat index 3
    flip(path, t_offset + 3 * 8, 8)
    # 1 byte: regime at (force_ratio 1.0, frequency_ratio 2.0), flat index 8 (stuck: 0 -> -1)
    flip(path, r_offset + 8, 1)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    before = static["transmissibility"].values[1, 0]
    after = ds["transmissibility"].values[1, 0]
    assert after != before and after < 0  # the sign bit went with the rest
    assert ds["regime"].values[2, 2] == -1
    problems = audit.audit(ds)
    assert [p.variable for p in problems] == ["transmissibility", "regime"]
    t, reg = problems
    assert (t.count, t.example, dict(t.where)) == (1, after, {"force_ratio": 0.5, "frequency_ratio": 0.5})
    assert (reg.count, reg.example, dict(reg.where)) == (1, -1, {"force_ratio": 1.0, "frequency_ratio": 2.0})
    # nothing else in the file changed
    for name in static.data_vars:
        if name not in ("transmissibility", "regime"):
            np.testing.assert_array_equal(ds[name].values, static[name].values)


def test_info_refuses_a_corrupted_cube(tmp_path, static):
    ds = static.copy(deep=True)
    ds.attrs["friction_sweep_version"] = "test"
    ds["regime"][0, 0] = 93
    path = tmp_path / "bad.h5"
    cube.write_atomic(ds, path, overwrite=False)
    res = CliRunner().invoke(main, ["info", str(path)])
    assert res.exit_code == 2
    assert "regime: 1 of 9 values are not valid regime codes (e.g. 93 at frequency_ratio=0.5" in res.output


# ---- issue 28, round 2: cube readers and check ------------------------------------------------------------

@pytest.mark.parametrize("method, excitation, effects", [
    ("theory", "force", None), ("theory", "base", None), ("theory", "joined", None),
    ("event", "base", None), ("event", "joined", {"static_friction_ratio": 1.5}),
    ("event", "force", {"viscous_damping": 0.05, "contact_stiffness": 100.0}),
    ("rk4", "base", {"static_friction_ratio": 1.5}), ("auto", "joined", None),
])
def test_pairs_of_values_every_method_writes_pass(method, excitation, effects):
    """The pair rules hold for every method's cube (a transmissibility reaches 1.07 x the peak: a first
    harmonic may exceed the peak, never 4/pi of it)."""
    r = np.round(np.linspace(0.3, 2.5, 12), 12)
    ds = make_cube(method, excitation, effects=effects, r=np.union1d(r, [1.0]), beta=np.array([0.0, 0.2, 0.7, 1.3]))
    ds.attrs["method"] = method
    assert audit.audit(ds) == [] and audit.together(ds) == []


@pytest.mark.parametrize("method, name, index, x, words", [
    ("event", "transmissibility", (1, 0), np.nan, "transmissibility: 1 of 9 values are NaN at a settled regime"),
    ("theory", "transmissibility", (0, 0), 50.0, "transmissibility: 1 of 9 values exceed 4/pi times "
                                                  "peak_transmissibility"),
    ("event", "peak_transmissibility", (1, 2), 0.01, "exceed 4/pi times peak_transmissibility"),
], ids=["settled NaN", "T above the peak", "peak below T"])
def test_impossible_pairs_are_reported(method, name, index, x, words):
    ds = make_cube(method)
    ds.attrs["method"] = method
    assert audit.together(ds) == []
    ds[name].values[index] = x
    assert audit.audit(ds) == []  # each value alone is in range
    problems = [str(p) for p in audit.together(ds)]
    assert len(problems) == 1 and words in problems[0], problems
