"""The Python API (friction_sweep.api, re-exported at the package root): the cube `fsweep run` writes,
validated as the CLI validates, every refusal a FsweepError carrying the CLI's message."""

from __future__ import annotations

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
    with pytest.raises(fs.SpecError, match="<dict>: cannot be written as YAML"):
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
