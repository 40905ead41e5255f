"""The command line, driven through click's CliRunner: run, validate, info, and bad input."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import ROOT, in_dir, small_spec, write_spec

from friction_sweep import codes
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.storage import cube, schema

CONFIGS = sorted((ROOT / "configs").glob("*.yaml"))

@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_run_writes_a_cube_that_keeps_the_contract(runner, tmp_path, excitation):
    spec = write_spec(tmp_path, excitation)
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec)])
    assert res.exit_code == 0, res.output
    out = tmp_path / "out.h5"
    assert f"wrote {Path('out.h5')}" in res.output
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert tuple(ds["transmissibility"].dims) == ("force_ratio", "frequency_ratio")
    assert ds.sizes == {"force_ratio": 3, "frequency_ratio": 15}
    for name in ("transmissibility", "peak_transmissibility", "phase", "peak_phase", "regime",
                 "stops_per_period", "continuous_limit"):
        assert name in ds, name
        assert ds[name].attrs["long_name"]
        assert ds[name].attrs["units"] in ("1", "degree")
    assert ds["phase"].attrs["units"] == "degree"
    assert ds["regime"].dtype == np.int8
    assert list(ds["regime"].attrs["flag_values"]) == [0, 1, 2, 3, 4]
    assert ds["regime"].attrs["flag_meanings"].split() == list(codes.meanings(Regime))
    assert ds.attrs["Conventions"].startswith("CF-")
    assert "fsweep run" in ds.attrs["history"]
    assert ds.attrs["spec"] == spec.read_text()
    for key in ("friction_sweep_version", "numpy_version", "numba_version", "xarray_version", "method_settings"):
        assert ds.attrs[key]
    assert ds.attrs["method"] == "theory" and ds.attrs["excitation"] == excitation
    # joined scenes also carry the relative motion of Sect. 4
    assert ("relative_peak_amplitude" in ds) == (excitation == "joined")
    # and the default engine opens it too
    xr.open_dataset(out).close()
    ds.close()


def test_cube_round_trips_unchanged(tmp_path):
    from friction_sweep.methods import theory
    from friction_sweep.storage import provenance

    r = np.linspace(0.2, 3.0, 12)
    beta = np.array([0.0, 0.4, 1.0])
    arrays = theory.compute_tile("joined", r, beta, ("transmissibility", "phase", "regime"))
    ds = cube.build_dataset(arrays, frequency_ratio=r, force_ratio=beta, excitation="joined", title="t",
                            history=provenance.history_line("test"),
                            attrs=provenance.attributes(spec_text="x: 1\n", spec_path="s.yaml",
                                                        excitation="joined", method="theory", settings={}))
    path = tmp_path / "c.h5"
    cube.write_atomic(ds, path, overwrite=False)
    back = cube.open_cube(path)
    xr.testing.assert_identical(back, ds)
    for name in arrays:
        np.testing.assert_array_equal(back[name].values, arrays[name])  # NaNs in the same places
        assert back[name].dtype == ds[name].dtype


def test_existing_output_is_never_replaced_without_overwrite(runner, tmp_path):
    spec = write_spec(tmp_path)
    out = tmp_path / "out.h5"
    out.write_bytes(b"precious")
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec)])
        assert res.exit_code == 2
        assert "exists" in res.output and "--overwrite" in res.output
        assert out.read_bytes() == b"precious"
        res = runner.invoke(main, ["run", str(spec), "--overwrite"])
    assert res.exit_code == 0, res.output
    assert xr.open_dataset(out, engine="h5netcdf").sizes["frequency_ratio"] == 15
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


def test_failed_write_leaves_target_and_no_temporary(tmp_path, monkeypatch):
    from friction_sweep.methods import theory

    r, beta = np.array([0.5, 2.0]), np.array([0.1])
    ds = cube.build_dataset(theory.compute_tile("base", r, beta, ("regime",)), frequency_ratio=r,
                            force_ratio=beta, excitation="base", title="t", history="h", attrs={})
    target = tmp_path / "c.h5"
    target.write_bytes(b"old result")

    def boom(self, *a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(cube, "netcdf_bytes", boom)
    with pytest.raises(OSError):
        cube.write_atomic(ds, target, overwrite=True)
    assert target.read_bytes() == b"old result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.h5"]


def test_output_option_overrides_spec(runner, tmp_path):
    spec = write_spec(tmp_path)
    other = tmp_path / "sub" / "x.h5"
    res = runner.invoke(main, ["run", str(spec), "-o", str(other), "--quiet"])
    assert res.exit_code == 0, res.output
    assert other.exists() and not (tmp_path / "out.h5").exists()


@pytest.mark.slow
def test_jobs_do_not_change_the_numbers(runner, tmp_path):
    text = small_spec("joined", "a.h5").replace("num: 15", "num: 70")
    spec = write_spec(tmp_path, text=text)
    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(a), "-j", "1"]).exit_code == 0
    res = runner.invoke(main, ["run", str(spec), "-o", str(b), "-j", "2"])
    assert res.exit_code == 0, res.output
    da, db = cube.open_cube(a), cube.open_cube(b)
    for name in da.data_vars:
        np.testing.assert_array_equal(da[name].values, db[name].values)


def test_validate_checks_only(runner, tmp_path):
    spec = write_spec(tmp_path)
    with in_dir(tmp_path):
        res = runner.invoke(main, ["validate", str(spec)])
    assert res.exit_code == 0
    assert "ok" in res.output and "45 points" in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]


BAD = {
    "negative force ratio": ("force_ratio: [0.0, 0.3, 0.9]", "force_ratio: [0.0, -0.3, 0.9]", "grid.force_ratio[1]"),
    "nan": ("force_ratio: [0.0, 0.3, 0.9]", "force_ratio: [0.0, .nan]", "grid.force_ratio[1]"),
    "zero frequency": ("{start: 0.2, stop: 3.0, num: 15}", "[0.0, 1.0]", "grid.frequency_ratio[0]"),
    "empty grid": ("force_ratio: [0.0, 0.3, 0.9]", "force_ratio: []", "grid.force_ratio"),
    "unknown key": ("method: theory", "method: theory\nsolver: fast", "solver"),
    "unknown excitation": ("excitation: base", "excitation: wall", "scene.excitation"),
    "duplicate key": ("method: theory", "method: theory\nmethod: theory", "method"),
    "string number": ("force_ratio: [0.0, 0.3, 0.9]", "force_ratio: ['0.3']", "grid.force_ratio[0]"),
    "unknown effect": ("effects: {}", "effects: {magnets: 1}", "scene.effects"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_specs_exit_2_name_the_key_and_write_nothing(runner, tmp_path, case):
    old, new, key = BAD[case]
    text = small_spec("base", "out.h5")
    assert old in text
    spec = write_spec(tmp_path, text=text.replace(old, new, 1))
    with in_dir(tmp_path):
        for command in ("run", "validate"):
            res = runner.invoke(main, [command, str(spec)])
            assert res.exit_code == 2, (command, res.output)
            assert str(spec) in res.output and key in res.output, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]


def test_malformed_yaml_reports_line_and_column(runner, tmp_path):
    spec = write_spec(tmp_path, text="scene:\n  excitation: base\ngrid: [unclosed\n")
    res = runner.invoke(main, ["run", str(spec)])
    assert res.exit_code == 2
    # the parser notices the unclosed flow sequence at the end of the stream, line 4
    assert f"{spec}:4:1: invalid YAML" in res.output
    assert "line 3, column 7" in res.output  # and says where the sequence started


def test_missing_spec_file_exits_2(runner, tmp_path):
    res = runner.invoke(main, ["run", str(tmp_path / "nope.yaml")])
    assert res.exit_code == 2
    assert "nope.yaml" in res.output


def test_info_describes_the_cube(runner, tmp_path):
    spec = write_spec(tmp_path, "joined")
    with in_dir(tmp_path):
        assert runner.invoke(main, ["run", str(spec)]).exit_code == 0
        res = runner.invoke(main, ["info", "out.h5"])
    assert res.exit_code == 0, res.output
    for text in ("force_ratio 3", "frequency_ratio 15", "excitation: joined", "method: theory",
                 "numpy", "numba", "xarray", "regimes:", "stuck", "continuous"):
        assert text in res.output
    ds = cube.open_cube(tmp_path / "out.h5")
    counts = codes.counts(ds["regime"].values)
    assert f"stuck {counts['stuck']}," in res.output


def test_info_methods_tabulates_what_each_method_can_do(runner):
    from friction_sweep.catalogue import METHODS

    res = runner.invoke(main, ["info", "--methods"])
    assert res.exit_code == 0, res.output
    rows = {line.split()[0]: line for line in res.output.splitlines()[1:len(METHODS) + 1]}
    assert list(rows) == list(METHODS)
    assert "static_friction_ratio" in rows["event"] and "static_friction_ratio" not in rows["theory"]
    assert "time_history" in rows["auto"] and "time_history" not in rows["paper"]
    for args in (["info"], ["info", "--methods", "x.h5"]):
        res = runner.invoke(main, args)
        assert res.exit_code == 2 and "--methods" in res.output


@pytest.mark.parametrize("text", [
    "scene: {excitation: base, effects: {static_friction_ratio: 1.5}}\n"
    "grid: {frequency_ratio: [0.5, 1.0, 2.0], force_ratio: [0.0, 0.3]}\nmethod: event\n"
    "outputs: [transmissibility, phase, regime, time_history]\n"
    "time_history: {points: [[0.95, 0.3]], samples_per_period: 8}\n",
    "scene: {excitation: joined}\ngrid: {frequency_ratio: [0.5, 2.0], force_ratio: [0.1]}\nmethod: theory\n",
])
def test_the_cube_file_reads_back_as_the_dataset(tmp_path, text):
    """`fsweep run` writes the cube's parts through h5netcdf, not through xarray (which would import
    dask): xarray reads the file back identical to the Dataset of the same parts, with the encodings
    xarray itself would have chosen (NaN fill for float variables, none for coordinates and flags)."""
    from friction_sweep.batch import pipeline
    from friction_sweep.spec import load_spec

    spec = tmp_path / "spec.yaml"
    spec.write_text(text)
    s = load_spec(spec)
    arrays = pipeline.compute(s, dict(s.settings))
    parts = pipeline.cube(s, arrays, dict(s.settings), "test")
    path = tmp_path / "c.h5"
    cube.write_atomic(parts, path, overwrite=False)
    with xr.open_dataset(path, engine="h5netcdf") as back:
        xr.testing.assert_identical(back.load(), cube.as_dataset(parts))
        for name, var in back.variables.items():
            fill = var.encoding.get("_FillValue")
            if np.issubdtype(var.dtype, np.floating) and name not in back.coords:
                assert fill is not None and np.isnan(fill), name
            else:
                assert fill is None, name


def test_a_dataset_with_string_coordinates_is_written_as_xarray_reads_it(tmp_path):
    """The benchmark's dataset (method, region names as coordinates) goes through the same writer."""
    ds = xr.Dataset({"error": (("method", "region"), np.array([[1e-9, np.nan]]), {"units": "1"})},
                    coords={"method": ["event"], "region": ["continuous", "two stops"]}, attrs={"title": "t"})
    cube.write_atomic(ds, tmp_path / "w.h5", overwrite=False)
    with xr.open_dataset(tmp_path / "w.h5", engine="h5netcdf") as back:
        xr.testing.assert_identical(back.load(), ds)


def test_info_refuses_a_foreign_file(runner, tmp_path):
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5")
    res = runner.invoke(main, ["info", str(junk)])
    assert res.exit_code == 2
    assert "not a readable result cube" in res.output


@pytest.mark.parametrize("config", CONFIGS, ids=[c.stem for c in CONFIGS])
@pytest.mark.slow
def test_every_shipped_config_runs_and_keeps_the_contract(runner, tmp_path, config):
    out = tmp_path / f"{config.stem}.h5"
    res = runner.invoke(main, ["run", str(config), "-o", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    ds = cube.open_cube(out)
    structure = schema.is_structure(ds.attrs)  # a structure's cube (issue 30) has its own dims and table
    dims = set(schema.DOF_DIMS) | {"contact"} if structure else {"force_ratio", "frequency_ratio"}
    assert set(ds.dims) == dims
    for name, var in ds.data_vars.items():
        spec = (schema.STRUCTURE_VARIABLES if structure else schema.VARIABLES)[name]
        assert var.dims == spec.dims
        assert var.attrs["units"] == spec.units
    # the theory writes numbers only where it can back them
    if ds.attrs["method"] == "theory" and "regime" in ds and "transmissibility" in ds:
        code = ds["regime"].values
        t = ds["transmissibility"].values
        assert np.all(np.isnan(t[code == Regime.STICK_SLIP]))
        assert np.all(np.isfinite(t[code == Regime.CONTINUOUS]))


def test_simulation_spec_with_time_history(runner, tmp_path):
    text = """\
scene: {excitation: joined}
grid: {frequency_ratio: [0.5, 0.95, 2.0], force_ratio: [0.3, 0.8]}
method: auto
outputs: [transmissibility, regime, time_history]
time_history: {points: [[0.95, 0.8]], samples_per_period: 32}
settings: {theory_margin: 0.05}
"""
    spec = write_spec(tmp_path, text=text)
    out = tmp_path / "h.h5"
    res = runner.invoke(main, ["run", str(spec), "-o", str(out)])
    assert res.exit_code == 0, res.output
    ds = cube.open_cube(out)
    assert ds["history_displacement"].dims == ("history_point", "sample")
    assert ds.sizes["sample"] == 32 * int(ds["history_orbit_period"].max())
    assert list(ds["method_used"].attrs["flag_meanings"].split()) == ["theory", "event"]
    assert ds["history_regime"].values[0] == Regime.STICK_SLIP  # the paper's Fig. 22 point
    assert "phase" not in ds  # not asked for, not written
    assert ds.attrs["method"] == "auto"
    # every stored code variable carries exactly the codes module's flags, and holds only those values
    enums = {"regime": codes.Regime, "history_regime": codes.Regime, "steady_state": codes.SteadyState,
             "method_used": codes.MethodUsed}
    for name, enum in enums.items():
        assert ds[name].attrs["flag_values"].tolist() == [m.value for m in enum]
        assert ds[name].attrs["flag_meanings"].split() == [m.name.lower() for m in enum]
        assert set(np.unique(ds[name].values)) <= {m.value for m in enum}
    assert {n for n in ds.data_vars if "flag_values" in ds[n].attrs} == set(enums)
    # the file format itself: codes written by earlier versions must keep their meaning
    assert ds["regime"].attrs["flag_meanings"] == "stuck stick_slip continuous unbounded unsettled"
    assert ds["steady_state"].attrs["flag_meanings"] == ("converged period_cap event_budget nonfinite growing "
                                                         "not_simulated family aperiodic unbalanced")
    assert ds["method_used"].attrs["flag_meanings"] == "theory event"


# --- faults: nothing is lost ------------------------------------------------------------------------------


def test_huge_grid_is_refused_with_an_estimate_unless_yes(runner, tmp_path, monkeypatch):
    import friction_sweep.batch.estimate as estimate

    text = small_spec("base", "out.h5").replace("method: theory", "method: event")
    spec = write_spec(tmp_path, text=text)
    monkeypatch.setattr(estimate, "HUGE_SECONDS", 1e-6)  # make this small grid count as huge
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec)])
        assert res.exit_code == 2
        assert "45 points with method event would take about" in res.output and "GiB" in res.output
        assert "--yes" in res.output
        assert not (tmp_path / "out.h5").exists()
        res = runner.invoke(main, ["run", str(spec), "--yes", "--quiet"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "out.h5").exists()


def test_unwritable_output_folder_fails_before_computing(runner, tmp_path, monkeypatch):
    import friction_sweep.batch.runner as runner_module

    spec = write_spec(tmp_path)
    blocker = tmp_path / "afile"
    blocker.write_text("not a folder")
    called = []
    monkeypatch.setattr(runner_module, "run_grid", lambda *a, **k: called.append(1))
    res = runner.invoke(main, ["run", str(spec), "-o", str(blocker / "out.h5")])
    assert res.exit_code == 2
    assert f"parent {blocker} is a file, not a folder" in res.output
    assert called == []  # nothing computed in vain
    assert blocker.read_text() == "not a folder"


def test_full_disk_at_the_end_keeps_the_old_result(runner, tmp_path, monkeypatch):
    spec = write_spec(tmp_path)
    out = tmp_path / "out.h5"
    with in_dir(tmp_path):
        assert runner.invoke(main, ["run", str(spec)]).exit_code == 0
    before = out.read_bytes()

    def no_space(self, *a, **k):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(cube, "netcdf_bytes", no_space)
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec), "--overwrite"])
    assert res.exit_code == 1
    assert "No space left on device" in res.output and "nothing was written" in res.output
    assert out.read_bytes() == before
    # no temporary file; the finished tiles wait in the checkpoint for --resume
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.h5.partial", "out.h5", "spec.yaml"]
    monkeypatch.undo()
    import friction_sweep.methods.theory as theory_module

    monkeypatch.setattr(theory_module, "compute_tile", lambda *a, **k: pytest.fail("recomputed a finished tile"))
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec), "--resume"])
    assert res.exit_code == 0, res.output
    assert not (tmp_path / ".out.h5.partial").exists()


@pytest.mark.slow
def test_a_killed_run_leaves_the_old_result_intact(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    spec = tmp_path / "spec.yaml"
    spec.write_text(small_spec("base", "out.h5"))
    out = tmp_path / "out.h5"
    fsweep = [sys.executable, "-m", "friction_sweep", "run", str(spec), "-o", str(out), "--quiet"]
    subprocess.run(fsweep, check=True, capture_output=True)
    before = out.read_bytes()
    # a long sweep over the same output, killed with SIGKILL while it computes
    spec.write_text(small_spec("base", "out.h5")
                    .replace("{start: 0.2, stop: 3.0, num: 15}", "{start: 0.2, stop: 3.0, num: 40000}")
                    .replace("method: theory", "method: event"))
    proc = subprocess.Popen(fsweep + ["--overwrite", "--yes"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(4)
    assert proc.poll() is None, "the sweep finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert out.read_bytes() == before


# --- scale: executors, determinism, resume, one run at a time ----------------------------------------

EVENT_SPEC = """\
scene: {excitation: joined}
grid: {frequency_ratio: {start: 0.1, stop: 3.0, num: 100}, force_ratio: [0.0, 0.3, 0.6, 1.2]}
method: event
"""


def _cube_arrays(path):
    ds = cube.open_cube(path)
    return {name: ds[name].values for name in ds.data_vars}


def _assert_same_bits(a, b):
    assert a.keys() == b.keys()
    for name in a:
        np.testing.assert_array_equal(a[name], b[name])


@pytest.mark.parametrize("args", [["-j", "2", "--executor", "threads"], ["-j", "2", "--executor", "processes"],
                                  ["--executor", "serial"]], ids=["threads", "processes", "serial"])
@pytest.mark.slow
def test_executors_and_worker_counts_give_the_same_bits(runner, tmp_path, args):
    spec = write_spec(tmp_path, text=EVENT_SPEC)
    ref, out = tmp_path / "ref.h5", tmp_path / "out.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(ref), "-j", "1"]).exit_code == 0
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), *args])
    assert res.exit_code == 0, res.output
    _assert_same_bits(_cube_arrays(ref), _cube_arrays(out))


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_bits(runner, tmp_path):
    spec = write_spec(tmp_path, text=EVENT_SPEC)
    ref, out = tmp_path / "ref.h5", tmp_path / "out.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(ref)]).exit_code == 0
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--executor", "dask", "-j", "2"])
    assert res.exit_code == 0, res.output
    _assert_same_bits(_cube_arrays(ref), _cube_arrays(out))


def _interrupted_after(n: int, real):
    """compute_tile that computes n tiles, then raises KeyboardInterrupt as Ctrl-C would."""
    calls = []

    def compute(*a, **k):
        calls.append(1)
        if len(calls) > n:
            raise KeyboardInterrupt
        return real(*a, **k)

    return compute


@pytest.mark.slow
def test_interrupted_run_resumes_to_the_same_bits(runner, tmp_path, monkeypatch):
    import friction_sweep.methods.event as event_module

    spec = write_spec(tmp_path, text=EVENT_SPEC)
    ref, out = tmp_path / "ref.h5", tmp_path / "out.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(ref)]).exit_code == 0
    real = event_module.compute_tile
    monkeypatch.setattr(event_module, "compute_tile", _interrupted_after(2, real))
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--executor", "serial"])
    assert res.exit_code == 130 and "interrupted" in res.output
    assert not out.exists()
    partial = tmp_path / ".out.h5.partial"
    assert sorted(p.name for p in partial.glob("tile-*.npz")) == ["tile-00000.npz", "tile-00001.npz"]
    # without --resume the leftover is not silently thrown away
    monkeypatch.setattr(event_module, "compute_tile", real)
    res = runner.invoke(main, ["run", str(spec), "-o", str(out)])
    assert res.exit_code == 2 and "--resume" in res.output and "2 finished tiles" in res.output
    computed = []

    def counting(*a, **k):
        computed.append(1)
        return real(*a, **k)

    monkeypatch.setattr(event_module, "compute_tile", counting)
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--resume", "--executor", "serial"])
    assert res.exit_code == 0, res.output
    assert len(computed) == 2  # 4 tiles of 32 frequency ratios: only the 2 missing ones
    _assert_same_bits(_cube_arrays(ref), _cube_arrays(out))
    assert not partial.exists()


def test_resume_refuses_a_checkpoint_of_another_sweep(runner, tmp_path, monkeypatch):
    import friction_sweep.methods.event as event_module

    spec = write_spec(tmp_path, text=EVENT_SPEC)
    out = tmp_path / "out.h5"
    monkeypatch.setattr(event_module, "compute_tile", _interrupted_after(1, event_module.compute_tile))
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--executor", "serial"])
    assert res.exit_code == 130 and "1 finished tiles are kept" in res.output and "--resume" in res.output
    spec.write_text(EVENT_SPEC.replace("1.2]", "1.3]"))
    for args in (["--resume"], []):  # both name the command that clears the other sweep's tiles
        res = runner.invoke(main, ["run", str(spec), "-o", str(out), *args])
        assert res.exit_code == 2 and "different sweep" in res.output
        assert f"rm -r {tmp_path / '.out.h5.partial'}" in res.output


def test_a_run_that_failed_before_any_tile_does_not_block_the_next(runner, tmp_path, monkeypatch):
    import friction_sweep.methods.event as event_module

    spec = write_spec(tmp_path, text=EVENT_SPEC)
    out = tmp_path / "out.h5"
    monkeypatch.setattr(event_module, "compute_tile", lambda *a, **k: 1 / 0)
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "-q"])
    assert res.exit_code == 1 and "ZeroDivisionError" in res.output and len(res.output.splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]
    monkeypatch.undo()
    assert runner.invoke(main, ["run", str(spec), "-o", str(out)]).exit_code == 0


def test_a_second_run_on_the_same_output_is_refused(runner, tmp_path):
    from friction_sweep.batch import checkpoint

    spec = write_spec(tmp_path)
    out = tmp_path / "out.h5"
    with checkpoint.Lock(out):  # as a running fsweep holds it
        res = runner.invoke(main, ["run", str(spec), "-o", str(out)])
    assert res.exit_code == 2
    assert "another fsweep run is writing" in res.output and "out.h5" in res.output
    assert not out.exists()
    assert runner.invoke(main, ["run", str(spec), "-o", str(out)]).exit_code == 0  # released


@pytest.mark.slow
def test_kill_9_then_resume_gives_the_same_bits(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    spec = tmp_path / "spec.yaml"
    spec.write_text(EVENT_SPEC.replace("num: 100", "num: 1500").replace("method: event", "method: event\n"
                    "settings: {max_periods: 3000}"))
    ref, out = tmp_path / "ref.h5", tmp_path / "out.h5"
    fsweep = [sys.executable, "-m", "friction_sweep", "run", str(spec), "--quiet", "--executor", "serial"]
    proc = subprocess.Popen(fsweep + ["-o", str(out)], stderr=subprocess.PIPE)
    partial = tmp_path / ".out.h5.partial"
    deadline = time.time() + 60
    while time.time() < deadline and len(list(partial.glob("tile-*.npz"))) < 3:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    finished = len(list(partial.glob("tile-*.npz")))
    assert 3 <= finished < 47 and not out.exists()
    subprocess.run(fsweep + ["-o", str(out), "--resume"], check=True, capture_output=True)
    subprocess.run(fsweep + ["-o", str(ref)], check=True, capture_output=True)
    _assert_same_bits(_cube_arrays(ref), _cube_arrays(out))


# ---- issue 33 item 6: command-line conventions


def test_fsweep_alone_prints_the_help():
    """It squashed the whole help into one error line."""
    res = CliRunner().invoke(main, [], prog_name="fsweep")
    assert res.exit_code == 2  # as click's own no_args_is_help
    lines = res.stderr.splitlines()
    assert lines[0] == "Usage: fsweep [OPTIONS] COMMAND [ARGS]..." and "fsweep: error" not in res.stderr
    commands = lines[lines.index("Commands:") + 1:]
    assert {line.split()[0] for line in commands} == set(main.list_commands(None))


def test_a_spec_without_output_writes_a_nc_cube(tmp_path):
    """CF 2.1: netCDF files end in .nc (the default was results/<spec>.h5)."""
    spec = write_spec(tmp_path, text=small_spec().replace("output: out.h5\n", ""))
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["run", str(spec), "-q"])
    assert res.exit_code == 0, res.output
    assert sorted(p.relative_to(tmp_path).as_posix() for p in (tmp_path / "results").iterdir()) == ["results/spec.nc"]
    with xr.open_dataset(tmp_path / "results/spec.nc", engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"].startswith("CF-")


def test_the_readme_documents_shell_completion_that_works(tmp_path):
    """click's completion, under the variable click derives from the program's name."""
    readme = (ROOT / "README.md").read_text()
    for shell in ("bash", "zsh", "fish"):
        assert f"_FSWEEP_COMPLETE={shell}_source fsweep" in readme
    fsweep = Path(sys.executable).with_name("fsweep")
    res = subprocess.run([fsweep], env={**os.environ, "_FSWEEP_COMPLETE": "bash_source"}, capture_output=True,
                         text=True, check=False, cwd=tmp_path)
    assert res.returncode == 0 and "_fsweep_completion" in res.stdout, res.stdout + res.stderr
    words = subprocess.run([fsweep], env={**os.environ, "_FSWEEP_COMPLETE": "bash_complete", "COMP_WORDS": "fsweep ca",
                                          "COMP_CWORD": "1"}, capture_output=True, text=True, check=False, cwd=tmp_path)
    assert words.stdout.split() == ["plain,calibrate"], words.stdout
