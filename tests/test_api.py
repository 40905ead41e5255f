"""The Python API (friction_sweep.api, re-exported at the package root): the cube `fsweep run` writes,
validated as the CLI validates, every refusal a FsweepError carrying the CLI's message."""

from __future__ import annotations

import datetime

import numpy as np
import pytest
import xarray as xr
from conftest import in_dir, write_spec

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.storage import cube


def _same_cube(a: xr.Dataset, b: xr.Dataset) -> None:
    """Identical numbers, variables and attributes, but for the history line (which names the command)."""
    xr.testing.assert_identical(a.drop_attrs(deep=False), b.drop_attrs(deep=False))
    assert set(a.attrs) == set(b.attrs)
    for key in set(a.attrs) - {"history", "spec_path"}:
        assert a.attrs[key] == b.attrs[key], key


def test_sweep_of_a_path_returns_the_cube_that_run_writes(runner, tmp_path):
    spec = write_spec(tmp_path, "joined")
    with in_dir(tmp_path):
        assert runner.invoke(main, ["run", str(spec), "-q"]).exit_code == 0
    written = fs.open_cube(tmp_path / "out.h5")
    _same_cube(written, fs.sweep(spec))
    _same_cube(written, fs.sweep_yaml(spec.read_text()))


def test_sweep_of_a_dict_takes_numpy_values_and_records_the_spec_as_yaml():
    spec = {"scene": {"excitation": "base"},
            "grid": {"frequency_ratio": np.linspace(0.5, 2.0, 4), "force_ratio": (np.float64(0.1), 0.3)},
            "method": "theory"}
    ds = fs.sweep(spec)
    np.testing.assert_array_equal(ds["frequency_ratio"].values, [0.5, 1.0, 1.5, 2.0])
    np.testing.assert_array_equal(ds["force_ratio"].values, [0.1, 0.3])
    again = fs.sweep_yaml(ds.attrs["spec"])  # the recorded text is the same spec
    xr.testing.assert_identical(again.drop_attrs(deep=False), ds.drop_attrs(deep=False))
    assert ds.attrs["spec_path"] == "<dict>"


def test_a_physical_dict_spec():
    ds = fs.sweep({"scene": {"excitation": "base"},
                   "system": {"mass": "2 kg", "stiffness": "40 kN/m", "base_amplitude": "1 mm"},
                   "grid": {"frequency": ["10 Hz", "40 Hz"], "friction_force": ["12 N"]}})
    assert ds["frequency"].attrs["units"] == "Hz"
    np.testing.assert_array_equal(ds["force_ratio"].values, [0.3])


def test_a_bad_spec_file_raises_the_message_the_cli_prints(runner, tmp_path):
    spec = write_spec(tmp_path, text="scene: {excitation: base}\ngrid: {frequency_ratio: [0.5, 0.4], "
                      "force_ratio: [-1]}\nmethod: nope\n")
    with pytest.raises(fs.FsweepError) as err:
        fs.sweep(spec)
    assert isinstance(err.value, fs.SpecError)
    res = runner.invoke(main, ["run", str(spec)])
    assert res.exit_code == 2
    lines = str(err.value).splitlines()
    assert len(lines) == 3 and all(f"{spec}:" in line for line in lines)
    for line in lines:
        assert line in res.output


def test_a_bad_dict_names_its_keys_without_lines():
    with pytest.raises(fs.SpecError) as err:
        fs.sweep({"scene": {"excitation": "base"}, "grid": {"frequency_ratio": [0.5], "force_ratio": [-0.3]}})
    assert str(err.value) == "<dict>: grid.force_ratio[0]: must be >= 0 (got -0.3)"
    with pytest.raises(fs.SpecError, match=r"^<dict>: scene\.excitation: cannot be written as YAML \(got a value of "
                                           r"type object\)$"):
        fs.sweep({"scene": {"excitation": object()}})


def test_open_cube_refuses_what_info_refuses(runner, tmp_path):
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5")
    with pytest.raises(fs.FsweepError, match="is not a readable result cube") as err:
        fs.open_cube(junk)
    res = runner.invoke(main, ["info", str(junk)])
    assert res.exit_code == 2 and str(err.value) in res.output
    with pytest.raises(fs.FsweepError, match="is not a regular file"):
        fs.open_cube(tmp_path)
    plain = tmp_path / "plain.h5"
    xr.Dataset({"a": ("x", [1.0])}).to_netcdf(plain, engine=cube.ENGINE)
    with pytest.raises(fs.FsweepError, match="no provenance attributes"):
        fs.open_cube(plain)


def test_an_accuracy_no_setting_meets_is_a_fsweep_error(tmp_path):
    spec = write_spec(tmp_path, text="scene: {excitation: base}\ngrid: {frequency_ratio: [0.5], force_ratio: [0.1]}\n"
                      "method: event\naccuracy: 1.0e-15\n")
    with pytest.raises(fs.FsweepError, match=f"^{spec}: accuracy: "):
        fs.sweep(spec)


def test_importing_the_package_loads_no_api():
    import subprocess
    import sys

    code = "import sys, friction_sweep; print('friction_sweep.api' in sys.modules, 'xarray' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


# ---- hostile arguments (issue 28): every refusal is a FsweepError saying what was wrong ----------------

SMALL = {"scene": {"excitation": "base"}, "grid": {"frequency_ratio": [1.0], "force_ratio": [0.1]}, "method": "theory"}


@pytest.mark.parametrize(("call", "words"), [
    (lambda: fs.sweep(12), "spec must be a spec file's path (str, bytes or os.PathLike) or a dict (got int 12)"),
    (lambda: fs.sweep([SMALL]), "or a dict (got list"),
    (lambda: fs.sweep(""), "spec: the path is empty"),
    (lambda: fs.sweep("spec\0.yaml"), "holds a NUL character"),
    (lambda: fs.sweep(b"spec\0.yaml"), "holds a NUL character"),
    (lambda: fs.sweep_yaml(123), "sweep_yaml: text must be the spec's YAML as a str (got int 123)"),
    (lambda: fs.sweep_yaml(b"scene: {excitation: base}"), "as a str (got bytes"),
    (lambda: fs.open_cube(3), "path must be a cube's path (str, bytes or os.PathLike) (got int 3)"),
    (lambda: fs.open_cube("cube\0.h5"), "holds a NUL character"),
    (lambda: fs.open_cube(""), "path: the path is empty"),
    (lambda: fs.sweep(SMALL, jobs="2"), "jobs must be a whole number from 1 to 1024 (got '2')"),
    (lambda: fs.sweep(SMALL, jobs=0), "(got 0)"),
    (lambda: fs.sweep(SMALL, jobs=-3), "(got -3)"),
    (lambda: fs.sweep(SMALL, jobs=2.5), "(got 2.5)"),
    (lambda: fs.sweep(SMALL, jobs=True), "(got true)"),
    (lambda: fs.sweep(SMALL, jobs=np.float64(2.0)), "jobs must be a whole number"),
    (lambda: fs.sweep(SMALL, jobs=10**100), "jobs must be a whole number"),
    (lambda: fs.sweep(SMALL, executor="bogus"), "executor must be one of: threads, processes, dask, serial "
                                                "(got 'bogus')"),
    (lambda: fs.sweep_yaml("x: 1", executor=None), "executor must be one of"),
])
def test_a_hostile_argument_is_refused_with_a_fsweep_error(call, words):
    with pytest.raises(fs.FsweepError) as err:
        call()
    assert words in str(err.value)


@pytest.mark.parametrize(("axis", "words"), [
    (np.array([[0.5, 1.0]]), "grid.frequency_ratio: must be a 1-D array of numbers (got shape (1, 2))"),
    (np.array(0.5), "must be a 1-D array of numbers (got shape ())"),
    (np.array([True, False]), "must be an array of numbers (got an array of dtype bool)"),
    (np.array([1 + 1j]), "must be an array of numbers (got an array of dtype complex128)"),
    (np.array([0.5, 1e4000], dtype=np.longdouble), "grid.frequency_ratio[1]: must be a finite number (got .inf)"),
    (np.array([0.001] * 5 + [1.0]), "grid.frequency_ratio[0]: must be between 0.01 and 100 (got 0.001) (4 more): "
                                    "frequency ratios are computed from 0.01 to 100"),
])
def test_an_array_axis_is_checked_as_a_whole(axis, words):
    with pytest.raises(fs.SpecError) as err:
        fs.sweep({**SMALL, "grid": {"frequency_ratio": axis, "force_ratio": [0.1]}})
    assert len(err.value.errors) == 1 and words in str(err.value), str(err.value)


def test_a_force_array_beyond_its_range_names_the_force_axis():
    with pytest.raises(fs.SpecError, match=r"grid\.force_ratio\[1\]: must be 0 or between 1e-12 and 1e\+06 "
                                           r"\(got 10000000\.0\): force ratios above 1e6"):
        fs.sweep({**SMALL, "grid": {"frequency_ratio": 1.0, "force_ratio": np.array([0.1, 1e7], dtype=np.longdouble)}})


def test_numpy_scalars_of_every_type_are_plain_numbers():
    """longdouble (which numpy's tolist leaves a longdouble: `maximum recursion depth` before), float32,
    0-d arrays, numpy ints and strings, inside the dict and as its axes."""
    spec = {"scene": {"excitation": np.str_("base")},
            "grid": {"frequency_ratio": np.array([0.5, 1.0], dtype=np.longdouble), "force_ratio": np.float32(0.25)},
            "method": "event", "settings": {"steady_tol": np.longdouble(1e-8), "max_periods": np.int32(500)}}
    ds = fs.sweep(spec, jobs=np.int64(2))  # any integer type for jobs, numpy's too
    np.testing.assert_array_equal(ds["frequency_ratio"].values, [0.5, 1.0])
    np.testing.assert_array_equal(ds["force_ratio"].values, [0.25])
    with pytest.raises(fs.SpecError, match=r"grid\.force_ratio: must be a finite number \(got \.inf\)"):
        fs.sweep({**SMALL, "grid": {"frequency_ratio": 1.0, "force_ratio": np.longdouble("1e4000")}})


def test_a_dict_that_holds_itself_or_too_much_is_refused():
    looped: dict = {}
    looped["x"] = looped
    with pytest.raises(fs.SpecError, match="nested deeper than 32 levels"):
        fs.sweep({**SMALL, "x": looped})
    with pytest.raises(fs.SpecError, match="a spec is at most 262144"):
        fs.sweep({**SMALL, "x": list(range(10**6))})
    with pytest.raises(fs.SpecError, match="a spec is at most 262144"):
        fs.sweep({**SMALL, "method": "m" * 10**6})
    with pytest.raises(fs.SpecError, match="a spec is at most 262144"):  # refused before it is listed
        fs.sweep({**SMALL, "method": "event", "outputs": ["regime", "time_history"],
                  "time_history": {"points": np.zeros((10**7, 2))}})


def test_sweep_yaml_is_capped_as_a_spec_file_is():
    text = "scene: {excitation: base}\ngrid: {frequency_ratio: 1.0, force_ratio: 0.1}\nx: [" + \
        ", ".join(["1.0"] * 250_000) + "]\n"
    with pytest.raises(fs.SpecError, match=r"^<string>: is 1250\d\d\d bytes; a spec is at most 262144"):
        fs.sweep_yaml(text)


def test_a_long_array_axis_never_goes_through_the_yaml_parser(monkeypatch):
    """3e5 values (44 s and 517 MB through YAML before): the parser sees only the rest of the spec, and the
    cube records the values as a flow list that reads back to the same numbers."""
    from friction_sweep import api

    seen: list[int] = []
    real = api.parse_yaml
    monkeypatch.setattr(api, "parse_yaml", lambda text, source: seen.append(len(text)) or real(text, source))
    r = np.linspace(0.5, 2.0, 300_000)
    betas = [i / 10 for i in range(1, 21)]
    spec = api.spec_of_dict({**SMALL, "grid": {"frequency_ratio": r, "force_ratio": betas}})
    assert seen and max(seen) < 1000
    np.testing.assert_array_equal(spec.frequency_ratio, r)
    np.testing.assert_array_equal(spec.force_ratio, betas)  # a long list of numbers: an array too
    from ruamel.yaml import YAML

    small = api.spec_of_dict({**SMALL, "grid": {"frequency_ratio": r[::3000], "force_ratio": np.arange(1, 4)}})
    recorded = YAML(typ="safe").load(small.text)["grid"]
    assert recorded["frequency_ratio"] == r[::3000].tolist() and recorded["force_ratio"] == [1, 2, 3]


def test_an_array_on_the_range_lattice_is_recorded_as_the_range():
    """np.linspace rounded to the grid's digits (the axis of a cube read back) is written {start, stop, num},
    which the recorded text reads back to, value for value; a dict's text stays small."""
    from friction_sweep import api
    from friction_sweep.spec import grid, parse_spec_text

    r = grid.linspace_values(0.5, 2.0, 300_000)
    spec = api.spec_of_dict({**SMALL, "grid": {"frequency_ratio": r, "force_ratio": np.array([0.1, 0.2])}})
    assert "{start: 0.5, stop: 2.0, num: 300000}" in spec.text and len(spec.text) < 1000
    again = parse_spec_text(spec.text)
    np.testing.assert_array_equal(again.frequency_ratio, r)
    np.testing.assert_array_equal(again.force_ratio, [0.1, 0.2])


def test_an_axis_numpy_reads_as_an_array_is_one():
    """An xarray coordinate (a cube's own axis) or a pandas Series, as an axis: not "cannot be written as YAML"."""
    first = fs.sweep({**SMALL, "grid": {"frequency_ratio": np.linspace(0.5, 2.0, 30), "force_ratio": [0.1]}})
    again = fs.sweep({**SMALL, "grid": {"frequency_ratio": first["frequency_ratio"], "force_ratio": [0.1]}})
    np.testing.assert_array_equal(again["frequency_ratio"].values, first["frequency_ratio"].values)


@pytest.mark.parametrize("where, value, key", [
    ("frequency_ratio", np.ma.masked_array([0.5, 1.5], [0, 1]), "grid.frequency_ratio"),
    ("frequency_ratio", np.ma.masked_array(np.linspace(0.5, 2, 40), [0] * 39 + [1]), "grid.frequency_ratio"),
    ("force_ratio", np.ma.masked_array([0.1, 0.2, 0.3], [1, 0, 0]), "grid.force_ratio"),
    ("force_ratio", [0.1, np.ma.masked], "grid.force_ratio[1]"),
    ("force_ratio", np.ma.masked_array(0.1, mask=True), "grid.force_ratio"),
])
def test_a_masked_value_is_refused_not_computed(where, value, key):
    """Issue 28 round 2: np.asarray drops a masked array's mask, so the masked point was computed."""
    grid = {"frequency_ratio": [0.5, 1.5], "force_ratio": [0.1], where: value}
    with pytest.raises(fs.SpecError) as err:
        fs.sweep({**SMALL, "grid": grid})
    assert f"{key}: a numpy masked array with 1 masked value(s)" in str(err.value), str(err.value)


def test_a_masked_array_without_a_masked_value_is_its_values():
    cube = fs.sweep({**SMALL, "grid": {"frequency_ratio": np.ma.masked_array([0.5, 1.5], [0, 0]),
                                       "force_ratio": [0.1]}})
    np.testing.assert_array_equal(cube.frequency_ratio.values, [0.5, 1.5])


@pytest.mark.parametrize("axis", [
    lambda pd, xr: pd.Series([0.5, np.nan]), lambda pd, xr: pd.Series([0.5, None], dtype="Float64"),
    lambda pd, xr: pd.array([1, None], dtype="Int64"), lambda pd, xr: xr.DataArray([0.5, np.nan]),
    lambda pd, xr: pd.Index([0.5, np.nan]), lambda pd, xr: xr.DataArray(np.ma.masked_array([0.5, 1.5], [0, 1])),
])
def test_pandas_and_xarray_axes_holding_a_missing_value_are_refused(axis):
    import pandas as pd
    import xarray as xr

    with pytest.raises(fs.SpecError, match=r"grid\.frequency_ratio\[1\]: must be a finite number"):
        fs.sweep({**SMALL, "grid": {"frequency_ratio": axis(pd, xr), "force_ratio": [0.1]}})


@pytest.mark.parametrize("where, value, words", [
    (("grid", "frequency_ratio"), [10**5000, 1.0], "grid.frequency_ratio[0]: an integer of 5001 digits is beyond"),
    (("grid", "frequency_ratio"), 10**5000, "grid.frequency_ratio: an integer of 5001 digits is beyond"),
    (("grid", "frequency_ratio"), {"start": 0.5, "stop": 2, "num": -10**400},
     "grid.frequency_ratio.num: a negative integer of 401 digits is beyond"),
    (("grid", "force_ratio"), [10**300], "grid.force_ratio[0]: must be <= 1000000 (got an integer of 301 digits)"),
    (("method",), {"a"}, "method: must be a method name (got a set (!!set) {'a'})"),
    (("method",), b"event", "method: must be a method name (got binary data of 5 bytes (!!binary))"),
    (("method",), 1 + 2j, "method: cannot be written as YAML (got a complex number (1.0, 2.0))"),
    (("settings",), {"steady_tol": datetime.date(2001, 12, 14)},
     "settings.steady_tol: must be a number (got a timestamp (2001-12-14))"),
], ids=["huge-int-in-list", "huge-int", "huge-num", "300-digit-int", "set", "bytes", "complex", "date"])
def test_a_refusal_shows_values_as_yaml_never_as_python(where, value, words):
    """Issue 28 round 2: a huge integer gave Python's "Exceeds the limit (4300 digits) for integer string
    conversion", a set "set(odict_keys(['a']))": a value is shown by spec.base.show only."""
    spec = {**SMALL, "method": "event", "grid": {"frequency_ratio": [0.5, 1.5], "force_ratio": [0.1]}}
    if len(where) == 2:
        spec[where[0]] = {**spec[where[0]], where[1]: value}
    else:
        spec[where[0]] = value
    with pytest.raises(fs.SpecError) as err:
        fs.sweep(spec)
    text = str(err.value)
    assert words in text and "Exceeds" not in text and "odict" not in text and "datetime" not in text, text
