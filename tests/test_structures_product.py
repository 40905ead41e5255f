"""Issue 30, the product around the multi-DoF engine: a `structure:` spec runs with `fsweep run` and
`fs.sweep` into a labelled cube (dims, names, CF attributes, flags, provenance, the structure it solved),
through the same tiles, executors, checkpoint and progress as a 1-DoF sweep, bit for bit the same whatever
the executor or the number of workers; `fsweep validate` and `info` show the structure; `check` and `plot`
read it (issue 31); the design commands (issue 32) take it.

What the numbers are (the engine against independent truths) is tested beside the engine; here a value is
compared only with another run of the same spec, or with what the spec says.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import ROOT, in_dir, one_error_line

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState, meanings


def _edit(text: str, *edits: tuple[str, str]) -> str:
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


#: the shipped example (configs/two_mass_damper.yaml: two masses, a rigid contact and a Jenkins one) on a
#: smaller plane, 40 frequencies (two tiles of 32) x 2 friction scales, with more outputs
SPEC = _edit((ROOT / "configs" / "two_mass_damper.yaml").read_text(),
             ("num: 541}", "num: 40}"), ("friction_scale: [0.25, 0.5, 1.0, 2.0]", "friction_scale: [0.5, 2.0]"),
             ("outputs: [amplitude, phase, regime]", "outputs: [amplitude, phase, regime, friction_energy, stability]"
              "\noutput: out.h5"))


@pytest.fixture(scope="module")
def spec_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("structure") / "spec.yaml"
    path.write_text(SPEC)
    return path


@pytest.fixture(scope="module")
def cube(spec_file) -> xr.Dataset:
    return fs.sweep(spec_file)


def test_the_cube_holds_every_mass_and_contact_on_its_dims(cube):
    assert dict(cube.sizes) == {"friction_scale": 2, "frequency": 40, "dof": 2, "contact": 2}
    assert cube["dof"].values.tolist() == ["blade", "damper"]
    assert cube["contact"].values.tolist() == ["platform", "root"]
    np.testing.assert_array_equal(cube["friction_scale"].values, [0.5, 2.0])
    assert cube["frequency"].values[0] == 0.3 and cube["frequency"].values[-1] == 3.0
    per_mass = ("amplitude", "peak_amplitude", "phase")
    per_contact = ("regime", "stops_per_period", "slips_per_period", "stuck_fraction", "friction_energy")
    per_point = ("steady_state", "orbit_period", "periods", "floquet_multiplier")
    # the root's static friction is above its kinetic: each variable again from the moving start (1-DoF's rule)
    own = {*per_mass, *per_contact, *per_point}
    assert set(cube.data_vars) == {*own, *(name + "_moving" for name in own), "steady_states"}
    for name in per_mass:
        assert cube[name].dims == ("friction_scale", "frequency", "dof") and cube[name].dtype == np.float64
    for name in per_contact:
        assert cube[name].dims == ("friction_scale", "frequency", "contact")
    for name in per_point:
        assert cube[name].dims == ("friction_scale", "frequency")
    assert cube["regime"].dtype == np.int8 and cube["steady_state"].dtype == np.int8


def test_the_cube_carries_cf_attributes_and_flags(cube):
    assert cube.attrs["Conventions"].startswith("CF-")
    for name in cube.data_vars:
        assert cube[name].attrs["long_name"] and "units" in cube[name].attrs, name
    assert cube["phase"].attrs["units"] == "degree"
    np.testing.assert_array_equal(cube["regime"].attrs["flag_values"], [int(m) for m in Regime])
    assert cube["regime"].attrs["flag_meanings"].split() == list(meanings(Regime))
    assert cube["steady_state"].attrs["flag_meanings"].split() == list(meanings(SteadyState))
    assert set(np.unique(cube["regime"].values)) <= {int(m) for m in Regime}


def test_a_rigid_contact_has_no_slips_of_a_slider(cube):
    """slips_per_period is the Jenkins slider's: NaN for the rigid contact wherever it is."""
    assert np.isnan(cube["slips_per_period"].sel(contact="platform").values).all()


def test_the_cube_records_what_was_solved(cube, spec_file):
    st = json.loads(cube.attrs["structure"])
    assert st["masses"] == {"blade": 1.0, "damper": 0.1}
    assert st["springs"] == [["ground", "blade", 1.0], ["blade", "damper", 2.0]]
    assert [c["name"] for c in st["contacts"]] == ["platform", "root"]
    assert st["contacts"][1]["stiffness"] == 20 and st["contacts"][0]["stiffness"] is None
    assert st["forcing"] == {"blade": 1.0}
    assert cube.attrs["spec"] == SPEC and cube.attrs["spec_path"] == str(spec_file)
    assert cube.attrs["excitation"] == "force" and cube.attrs["method"] == "event"
    assert json.loads(cube.attrs["method_settings"])["steady_tol"] == 1e-10
    assert "friction_sweep_version" in cube.attrs and "numba_version" in cube.attrs


def _same(a: xr.Dataset, b: xr.Dataset) -> None:
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.variables:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=str(name))


@pytest.mark.parametrize("jobs, executor", [(2, "threads"), (2, "processes")])
def test_the_cube_is_the_same_whatever_the_executor(cube, spec_file, jobs, executor):
    _same(fs.sweep(spec_file, jobs=jobs, executor=executor), cube)


@pytest.mark.slow
def test_the_cube_is_the_same_on_dask(cube, spec_file):
    pytest.importorskip("dask.distributed")
    _same(fs.sweep(spec_file, jobs=2, executor="dask"), cube)


def test_run_writes_the_cube_the_api_returns_and_info_shows_the_structure(cube, spec_file, tmp_path):
    runner = CliRunner()
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec_file), "-o", "out.h5", "-q", "-j", "2"])
        assert res.exit_code == 0, res.output
        assert "regimes at contact platform:" in res.output and "regimes at contact root:" in res.output
        written = fs.open_cube("out.h5")
        _same(written, cube)
        info = runner.invoke(main, ["info", "out.h5"])
    assert info.exit_code == 0, info.output
    for words in ("dims: friction_scale 2, frequency 40, dof 2, contact 2", "masses: blade 1.0, damper 0.1",
                  "contact platform: between damper and ground, friction 0.3, rigid",
                  "contact root: between blade and base, friction 0.2, Jenkins, stiffness 20",
                  "regimes at contact root:"):
        assert words in info.output, info.output


@pytest.mark.parametrize("command", ["check", "plot"])
def test_check_and_plot_read_a_structure_cube(spec_file, tmp_path, command):
    """They refused one (issue 30); issue 31 carries them over (tests/test_structure_commands.py)."""
    pytest.importorskip("matplotlib")
    runner = CliRunner()
    with in_dir(tmp_path):
        assert runner.invoke(main, ["run", str(spec_file), "-o", "s.h5", "-q"]).exit_code == 0
        res = runner.invoke(main, [command, "s.h5"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "s.png").exists() == (command == "plot")


def test_the_design_commands_take_a_structure_spec(spec_file, tmp_path):
    """fsweep peak (issue 32 for structures): one line per friction scale, the forced mass's peak and each
    contact's regime there; fsweep optimize refuses this spec's two friction scales in one line before
    anything is computed, writing nothing."""
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["peak", str(spec_file), "-o", "p.nc"])
        assert res.exit_code == 0, res.output
        lines = res.output.strip().splitlines()
        assert len(lines) == 2 and all(line.startswith("friction_scale ") for line in lines)
        assert all("root: " in line for line in lines)
        line = one_error_line(CliRunner().invoke(main, ["optimize", str(spec_file), "-o", "o.nc"]), 2)
    assert "grid.friction_scale: the optimum is searched from at least 3 friction scales (got 2)" in line
    assert (tmp_path / "p.nc").exists() and not (tmp_path / "o.nc").exists()


def test_validate_accepts_the_spec_and_shows_the_structure(spec_file, tmp_path):
    res = CliRunner().invoke(main, ["validate", str(spec_file), "-o", str(tmp_path / "v.h5")])
    assert res.exit_code == 0, res.output
    assert "ok: structure of 2 masses and 2 contacts, excitation force, method event" in res.output
    assert "2 friction scales x 40 frequencies = 80 points" in res.output
    assert "contact root: blade-base, friction 0.2, Jenkins, stiffness 20, static ratio 1.2" in res.output
    assert "estimate: about" in res.output
    assert not (tmp_path / "v.h5").exists()


def test_resume_computes_only_the_missing_tile_and_gives_the_same_cube(cube, spec_file, tmp_path, caplog):
    """A checkpoint holding the first of two tiles: --resume computes the second only, and the cube is the
    uninterrupted run's, bit for bit."""
    from friction_sweep.batch import checkpoint, structure_sweep
    from friction_sweep.spec import load_spec

    spec = load_spec(spec_file)
    out = tmp_path / "out.h5"
    store = checkpoint.Checkpoint(out, structure_sweep.checkpoint_key(spec, {}, {}), structure_sweep.tile_grids(spec))
    store.start(False)
    store.save(0, {name: values[:, :32] for name, values in structure_sweep.compute(spec, {}).items()})
    caplog.set_level("INFO", logger="friction_sweep")
    res = CliRunner().invoke(main, ["run", str(spec_file), "-o", str(out), "--resume", "-q", "-v"])
    assert res.exit_code == 0, res.output
    assert "computing 1 tiles (16 points)" in caplog.text and "resuming: 1 of 2 tiles already done" in caplog.text
    assert not store.dir.exists()
    _same(fs.open_cube(out), cube)


def test_a_checkpoint_tile_of_another_shape_is_computed_again(spec_file):
    from friction_sweep.batch import structure_sweep
    from friction_sweep.spec import load_spec

    spec = load_spec(spec_file)
    full = structure_sweep.compute(spec, {})
    bad = {name: values[:, :32].astype(np.float32) if values.dtype == np.float64 else values[:, :32]
           for name, values in full.items()}
    again = structure_sweep.compute(spec, {}, done={0: bad})
    for name in full:
        np.testing.assert_array_equal(again[name], full[name])
        assert again[name].dtype == full[name].dtype


def test_the_progress_bar_counts_every_point(spec_file):
    from friction_sweep.batch import structure_sweep
    from friction_sweep.spec import load_spec

    counted: list[int] = []
    structure_sweep.compute(load_spec(spec_file), {}, on_tile=counted.append)
    assert sorted(counted) == [16, 64]  # 8 frequencies x 2 scales, 32 x 2


def test_a_dict_spec_with_numpy_axes_runs_as_its_file(cube):
    from friction_sweep.spec import parse_spec_text

    data = parse_spec_text(SPEC).model_dump(mode="json")
    data["grid"] = {"frequency": cube["frequency"].values, "friction_scale": np.array([0.5, 2.0])}
    _same(fs.sweep(data), cube)  # values only: the spec text it records differs


def test_a_1dof_spec_with_a_numpy_frequency_axis_is_read_as_before():
    """A structure's grid.frequency takes arrays whole; a 1-DoF spec's grid.frequency (physical, with units)
    reads an array as the list of its numbers, as it did: each a number without its unit."""
    from friction_sweep.api import spec_of_dict
    from friction_sweep.spec.errors import SpecError

    data = {"scene": {"excitation": "base"}, "grid": {"frequency": np.array([1.0, 2.0]), "force_ratio": 0.1},
            "system": {"natural_frequency": "2 Hz"}}
    with pytest.raises(SpecError) as err:
        spec_of_dict(data)
    assert [(p.key, "a number without a unit" in p.reason) for p in err.value.errors] == \
        [("grid.frequency[0]", True), ("grid.frequency[1]", True)]


def test_the_estimate_counts_the_engine_compile_only_where_numba_has_not_cached_it(cube, spec_file, monkeypatch,
                                                                                    tmp_path):
    """One compilation serves every structure: after a run (the `cube` fixture) the estimate adds none; with
    an empty numba cache it adds the engine's measured compile."""
    from friction_sweep.batch.estimate import COMPILE_SECONDS, STRUCTURE_KERNEL, estimate
    from friction_sweep.spec import load_spec

    spec = load_spec(spec_file)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    assert estimate(spec, jobs=1, executor="threads").compile == 0.0
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    cold = estimate(spec, jobs=1, executor="threads")
    assert cold.compile == COMPILE_SECONDS[STRUCTURE_KERNEL[0]] and cold.seconds > cold.compile


def test_a_base_excited_structure_records_the_base_amplitude():
    text = _edit(SPEC, ("{excitation: force}", "{excitation: base}"), ("forcing: {blade: 1.0}", "base_amplitude: 0.5"),
                 ("num: 40", "num: 3"))
    ds = fs.sweep_yaml(text)
    assert ds.attrs["excitation"] == "base" and json.loads(ds.attrs["structure"])["base_amplitude"] == 0.5
    assert "forcing" not in text and dict(ds.sizes) == {"friction_scale": 2, "frequency": 3, "dof": 2, "contact": 2}


def test_the_estimate_counts_the_harmonics_replay_and_its_compile(spec_file, monkeypatch, tmp_path):
    """outputs: harmonics adds its replay (HARMONICS_COST a point), its values' memory and, with an empty numba
    cache, the replay's own compile beside the engine's."""
    from friction_sweep.batch.estimate import (
        COMPILE_SECONDS,
        HARMONICS_COST,
        STRUCTURE_HARMONICS_KERNEL,
        STRUCTURE_KERNEL,
        estimate,
    )
    from friction_sweep.spec import load_spec

    plain = load_spec(spec_file)
    path = tmp_path / "h.yaml"
    path.write_text(re.sub(r"outputs: \[(.*)\]", r"outputs: [\1, harmonics]", SPEC))
    harmonic = load_spec(path)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    cold, cold_h = (estimate(s, jobs=1, executor="threads") for s in (plain, harmonic))
    assert cold_h.compile == COMPILE_SECONDS[STRUCTURE_KERNEL[0]] + COMPILE_SECONDS[STRUCTURE_HARMONICS_KERNEL[0]]
    assert cold_h.seconds - cold_h.compile > (HARMONICS_COST - 0.01) * (cold.seconds - cold.compile - 0.4)
    assert cold_h.bytes > cold.bytes


def test_the_estimate_counts_the_time_histories_and_their_sampler(spec_file, monkeypatch, tmp_path):
    """A time_history: section adds its points' solves, their samples' memory and, with an empty numba cache,
    the sampler's compile."""
    from friction_sweep.batch.estimate import COMPILE_SECONDS, STRUCTURE_HISTORY_KERNEL, STRUCTURE_KERNEL, estimate
    from friction_sweep.spec import load_spec

    plain = load_spec(spec_file)
    path = tmp_path / "t.yaml"
    path.write_text(re.sub(r"outputs: \[(.*)\]", r"outputs: [\1, time_history]", SPEC)
                    + "time_history: {points: [[1.0, 1.0], [1.2, 2.0]], samples_per_period: 100000}\n")
    history = load_spec(path)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    cold, cold_t = (estimate(s, jobs=1, executor="threads") for s in (plain, history))
    assert cold_t.compile == COMPILE_SECONDS[STRUCTURE_KERNEL[0]] + COMPILE_SECONDS[STRUCTURE_HISTORY_KERNEL[0]]
    assert cold_t.seconds - cold_t.compile > cold.seconds - cold.compile
    assert cold_t.bytes - cold.bytes >= 2 * 100_000 * 8  # at least the samples of time at each point
