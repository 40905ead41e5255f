"""Tests of the sweep-spec layer: YAML reading, validation, grid values, error reports."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from friction_sweep.catalogue import EXCITATIONS, METHODS, OUTPUTS
from friction_sweep.spec import Spec, SpecError, load_spec, parse_spec_text

DEMO = """\
scene:
  excitation: base            # force | base | joined
  effects: {}                 # physical effects beyond the plain model
grid:
  frequency_ratio: {start: 0.05, stop: 5.0, num: 496}
  force_ratio: [0.1, 0.3, 0.5]
method: theory
outputs: [transmissibility, phase, regime]
output: results/demo.h5
"""


def spec_text(
    excitation: str = "base",
    effects: str = "{}",
    fr: str = "[0.5, 1.0]",
    fo: str = "[0.1, 0.3]",
    tail: str = "",
) -> str:
    """A valid spec. Lines: 1 scene, 2 excitation, 3 effects, 4 grid, 5 frequency_ratio,
    6 force_ratio, then `tail` from line 7."""
    return (
        "scene:\n"
        f"  excitation: {excitation}\n"
        f"  effects: {effects}\n"
        "grid:\n"
        f"  frequency_ratio: {fr}\n"
        f"  force_ratio: {fo}\n" + tail
    )


def spec_error(text: str, source: str = "t.yaml") -> SpecError:
    with pytest.raises(SpecError) as info:
        parse_spec_text(text, source)
    return info.value


def only(err: SpecError):
    assert len(err.errors) == 1, str(err)
    return err.errors[0]


# --- valid specs ---------------------------------------------------------------------------


def test_demo_spec_from_file(tmp_path: Path):
    path = tmp_path / "demo.yaml"
    path.write_text(DEMO, encoding="utf-8")
    spec = load_spec(path)
    r = spec.frequency_ratio
    assert r.dtype == np.float64 and r.shape == (496,)
    assert r[0] == 0.05 and r[-1] == 5.0
    assert 1.0 in r  # resonance hit exactly, not 0.9999999999999999
    assert np.all(np.diff(r) > 0)
    assert spec.force_ratio.tolist() == [0.1, 0.3, 0.5]
    assert spec.scene.excitation == "base"
    assert spec.scene.effects == {}
    assert spec.method == "theory"
    assert spec.outputs == ("transmissibility", "phase", "regime")
    assert spec.output == "results/demo.h5"  # as written: a Path would drop a trailing slash
    assert spec.source_path == str(path)
    assert spec.text == DEMO


def test_linspace_values_are_decimal():
    spec = parse_spec_text(DEMO)
    expected = [round(0.05 + 0.01 * i, 2) for i in range(496)]
    assert spec.frequency_ratio.tolist() == expected


def test_step_form_is_inclusive_of_stop_on_lattice():
    spec = parse_spec_text(spec_text(fr="{start: 0.05, stop: 5.0, step: 0.01}"))
    r = spec.frequency_ratio
    assert len(r) == 496
    assert r[0] == 0.05 and r[-1] == 5.0
    assert 1.0 in r
    assert r.tolist() == parse_spec_text(DEMO).frequency_ratio.tolist()


def test_step_form_stops_below_stop_off_lattice():
    spec = parse_spec_text(spec_text(fo="{start: 0, stop: 1, step: 0.3}"))
    assert spec.force_ratio.tolist() == [0.0, 0.3, 0.6, 0.9]


def test_single_number_axis():
    spec = parse_spec_text(spec_text(fr="0.7", fo="0"))
    assert spec.frequency_ratio.tolist() == [0.7]
    assert spec.frequency_ratio.ndim == 1 and spec.frequency_ratio.dtype == np.float64
    assert spec.force_ratio.tolist() == [0.0]


def test_list_axis_kept_as_given_and_ints_accepted():
    spec = parse_spec_text(spec_text(fr="[0.5, 1, 2.25, 1e1]", fo="[0, 0.123456789012345]"))
    assert spec.frequency_ratio.tolist() == [0.5, 1.0, 2.25, 10.0]
    assert spec.force_ratio.tolist() == [0.0, 0.123456789012345]  # lists are not rounded


def test_num_one_with_equal_ends():
    spec = parse_spec_text(spec_text(fr="{start: 1.5, stop: 1.5, num: 1}"))
    assert spec.frequency_ratio.tolist() == [1.5]


def test_defaults():
    spec = parse_spec_text("scene: {excitation: force}\ngrid: {frequency_ratio: 1, force_ratio: 0.5}\n")
    assert spec.method == "theory"
    assert spec.outputs == ("transmissibility", "phase", "regime")  # the default
    assert spec.output is None
    assert spec.scene.effects == {}
    assert spec.source_path == "<string>"


def test_outputs_subset_in_canonical_order():
    spec = parse_spec_text(spec_text(tail="outputs: [regime, transmissibility]\n"))
    assert spec.outputs == ("transmissibility", "regime")


def test_empty_effects_value_means_none():
    spec = parse_spec_text(spec_text(effects=""))
    assert spec.scene.effects == {}


def test_constants():
    assert EXCITATIONS == ("force", "base", "joined")
    assert list(METHODS)[0] == "theory" and "event" in METHODS
    assert OUTPUTS == ("transmissibility", "phase", "regime", "friction_energy", "transmitted_force", "stability",
                       "harmonics", "time_history")


def test_model_dump_round_trips():
    spec = parse_spec_text(DEMO)
    data = spec.model_dump(mode="json")
    assert data["output"] == "results/demo.h5"
    assert data["outputs"] == ["transmissibility", "phase", "regime"]
    again = Spec.model_validate(data)
    assert np.array_equal(again.frequency_ratio, spec.frequency_ratio)
    assert np.array_equal(again.force_ratio, spec.force_ratio)


def test_grid_arrays_are_read_only():
    spec = parse_spec_text(DEMO)
    with pytest.raises(ValueError):
        spec.frequency_ratio[0] = 2.0
    assert not pickle.loads(pickle.dumps(spec)).force_ratio.flags.writeable


# --- YAML-level errors ---------------------------------------------------------------------


def test_duplicate_key_names_key_and_line():
    # force_ratio on lines 6 and 7, both inside grid
    err = spec_error(spec_text(fo="[0.1]\n  force_ratio: [0.2]"))
    p = only(err)
    assert p.key == "grid.force_ratio"
    assert p.line == 7 and p.column == 3
    assert "duplicate key 'force_ratio'" in p.reason and "line 6" in p.reason


def test_malformed_yaml_has_line_and_column():
    err = spec_error("grid:\n  force_ratio: [0.1, 0.3]]\n")
    p = only(err)
    assert (p.line, p.column) == (2, 26)
    assert p.key == ""
    assert p.reason.startswith("invalid YAML")
    assert str(err).startswith("t.yaml:2:26: invalid YAML")


@pytest.mark.parametrize(
    "text, got",
    [("- 1\n- 2\n", "a list"), ("", "an empty document"), ("just text\n", "a str")],
)
def test_top_level_must_be_mapping(text, got):
    p = only(spec_error(text))
    assert "must be a mapping" in p.reason and got in p.reason


def test_missing_file(tmp_path: Path):
    path = tmp_path / "absent.yaml"
    with pytest.raises(SpecError) as info:
        load_spec(path)
    err = info.value
    assert err.path == str(path) and err.line is None and err.key == ""
    assert "not found" in err.reason
    assert str(err) == f"{path}: file not found"


def test_directory_is_not_a_spec(tmp_path: Path):
    with pytest.raises(SpecError, match="directory"):
        load_spec(tmp_path)


# --- unknown and missing keys --------------------------------------------------------------


def test_unknown_top_level_key():
    p = only(spec_error(spec_text(tail="colour: red\n")))
    assert p.key == "colour" and (p.line, p.column) == (7, 1)
    assert "unknown key 'colour'" in p.reason and "scene" in p.reason


def test_unknown_key_inside_grid():
    p = only(spec_error(spec_text(tail="  damping: 0.1\n")))
    assert p.key == "grid.damping" and p.line == 7
    assert "unknown key 'damping'" in p.reason


def test_unknown_key_inside_range():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, num: 3, count: 4}")))
    assert p.key == "grid.frequency_ratio.count" and p.line == 5
    assert "unknown key 'count'" in p.reason and "num" in p.reason


def test_missing_grid():
    p = only(spec_error("scene:\n  excitation: force\n"))
    assert p.key == "grid" and p.line is None
    assert "required key 'grid' is missing" in p.reason


def test_missing_excitation_points_at_scene():
    text = "method: theory\nscene:\n  effects: {}\ngrid: {frequency_ratio: 1, force_ratio: 1}\n"
    p = only(spec_error(text))
    assert p.key == "scene.excitation" and p.line == 2
    assert "'excitation' is missing" in p.reason


# --- numbers -------------------------------------------------------------------------------


def test_negative_force_ratio_message_format():
    err = spec_error(spec_text(fo="[0.1, -0.3, 0.5]"), source="configs/x.yaml")
    p = only(err)
    assert p.key == "grid.force_ratio[1]" and (p.line, p.column) == (6, 22)
    assert str(err) == "configs/x.yaml:6:22: grid.force_ratio[1]: must be >= 0 (got -0.3)"


@pytest.mark.parametrize(
    "fr, key, got",
    [
        ("[0, 1]", "grid.frequency_ratio[0]", "got 0"),
        ("[-1, 1]", "grid.frequency_ratio[0]", "got -1"),
        ("0", "grid.frequency_ratio", "got 0"),
        ("-0.5", "grid.frequency_ratio", "got -0.5"),
        ("{start: 0, stop: 2, num: 3}", "grid.frequency_ratio.start", "got 0"),
        ("[1.0e-10]", "grid.frequency_ratio[0]", "got 1e-10"),
    ],
)
def test_frequency_ratio_must_be_in_its_meaningful_range(fr, key, got):
    p = only(spec_error(spec_text(fr=fr)))
    assert p.key == key and p.line == 5
    assert "must be >= 0.01" in p.reason and got in p.reason and "cost" in p.reason


def test_frequency_ratio_above_its_range_is_refused_with_the_reason():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 1.0e20, num: 3}")))
    assert p.key == "grid.frequency_ratio.stop" and "must be <= 100" in p.reason and "1e-4" in p.reason


def test_negative_force_range_start():
    p = only(spec_error(spec_text(fo="{start: -0.1, stop: 1, num: 3}")))
    assert p.key == "grid.force_ratio.start" and p.line == 6
    assert "must be >= 0 (got -0.1)" in p.reason


@pytest.mark.parametrize(
    "value, shown", [(".nan", ".nan"), (".NaN", ".nan"), (".inf", ".inf"), ("-.inf", "-.inf")]
)
def test_non_finite_rejected(value, shown):
    p = only(spec_error(spec_text(fo=f"[0.1, {value}]")))
    assert p.key == "grid.force_ratio[1]" and p.line == 6
    assert "finite" in p.reason and shown in p.reason


def test_nan_in_range_start():
    p = only(spec_error(spec_text(fr="{start: .nan, stop: 2, num: 3}")))
    assert p.key == "grid.frequency_ratio.start" and "finite" in p.reason


def test_string_number_rejected():
    p = only(spec_error(spec_text(fo='[0.1, "0.3"]')))
    assert p.key == "grid.force_ratio[1]" and p.line == 6
    assert "not a string" in p.reason and "'0.3'" in p.reason


def test_string_single_value_rejected():
    p = only(spec_error(spec_text(fr='"0.1"')))
    assert p.key == "grid.frequency_ratio" and "not a string" in p.reason


def test_boolean_rejected():
    p = only(spec_error(spec_text(fr="{start: true, stop: 2, num: 3}")))
    assert p.key == "grid.frequency_ratio.start" and p.line == 5
    assert "boolean" in p.reason and "true" in p.reason


def test_yaml11_yes_is_a_string_not_a_boolean():
    p = only(spec_error(spec_text(fo="[yes]")))
    assert "not a string" in p.reason and "'yes'" in p.reason


def test_null_axis_rejected():
    p = only(spec_error(spec_text(fr="")))
    assert p.key == "grid.frequency_ratio" and p.line == 5
    assert "list of numbers" in p.reason and "null" in p.reason


# --- lists ---------------------------------------------------------------------------------


def test_empty_list_rejected():
    p = only(spec_error(spec_text(fr="[]")))
    assert p.key == "grid.frequency_ratio" and p.line == 5
    assert "empty" in p.reason


def test_unsorted_list_rejected():
    p = only(spec_error(spec_text(fo="[0.1, 0.5, 0.3]")))
    assert p.key == "grid.force_ratio[2]" and p.line == 6
    assert "strictly increasing" in p.reason and "0.3 after 0.5" in p.reason


def test_duplicate_list_value_rejected():
    p = only(spec_error(spec_text(fr="[0.5, 1.0, 1]")))
    assert p.key == "grid.frequency_ratio[2]"
    assert "duplicate value" in p.reason


# --- ranges --------------------------------------------------------------------------------


def test_num_zero():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, num: 0}")))
    assert p.key == "grid.frequency_ratio.num" and p.line == 5
    assert "must be >= 1 (got 0)" in p.reason


def test_num_not_integer():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, num: 2.5}")))
    assert p.key == "grid.frequency_ratio.num" and "integer" in p.reason


def test_num_one_needs_equal_ends():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, num: 1}")))
    assert p.key == "grid.frequency_ratio.num" and "start == stop" in p.reason


@pytest.mark.parametrize("step", ["0", "-0.1"])
def test_step_must_be_positive(step):
    p = only(spec_error(spec_text(fr=f"{{start: 1, stop: 2, step: {step}}}")))
    assert p.key == "grid.frequency_ratio.step" and p.line == 5
    assert f"must be > 0 (got {step})" in p.reason


def test_stop_below_start():
    p = only(spec_error(spec_text(fo="{start: 0.5, stop: 0.2, num: 3}")))
    assert p.key == "grid.force_ratio.stop" and p.line == 6
    assert "must be >= start (0.5)" in p.reason and "0.2" in p.reason


def test_both_num_and_step():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, num: 3, step: 0.5}")))
    assert p.key == "grid.frequency_ratio" and p.line == 5
    assert "exactly one of 'num' or 'step'" in p.reason and "both" in p.reason


def test_neither_num_nor_step():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2}")))
    assert p.key == "grid.frequency_ratio" and "neither" in p.reason


def test_block_mapping_error_points_at_its_key():
    text = spec_text(fr="\n    start: 1\n    stop: 2")  # frequency_ratio on line 5, its keys on 6-7
    p = only(spec_error(text))
    assert p.key == "grid.frequency_ratio" and p.line == 5


def test_too_many_points():
    text = spec_text(fr="{start: 1, stop: 2, num: 100000}", fo="{start: 0, stop: 1, num: 101}")
    p = only(spec_error(text))
    assert p.key == "grid" and p.line == 4
    assert "10100000 points" in p.reason


def test_too_many_points_from_step():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 2, step: 1e-9}")))
    assert p.key == "grid.frequency_ratio.step" and "10000000" in p.reason


def test_spacing_below_rounding_is_rejected():
    p = only(spec_error(spec_text(fr="{start: 1, stop: 1.000000000001, num: 10}")))
    assert p.key == "grid.frequency_ratio" and "significant digits" in p.reason


# --- scene, method, outputs ----------------------------------------------------------------


def test_unknown_excitation():
    p = only(spec_error(spec_text(excitation="shaker")))
    assert p.key == "scene.excitation" and (p.line, p.column) == (2, 15)
    assert "unknown excitation 'shaker'" in p.reason and "joined" in p.reason


def test_unknown_effect():
    p = only(spec_error(spec_text(effects="{stribeck: true}")))
    assert p.key == "scene.effects.stribeck" and p.line == 3
    assert p.reason == "unknown effect 'stribeck' (known: viscous_damping, static_friction_ratio, contact_stiffness)"


def test_unknown_method():
    p = only(spec_error(spec_text(tail="method: magic\n")))
    assert p.key == "method" and (p.line, p.column) == (7, 9)
    assert p.reason.startswith("unknown method 'magic'")


def test_every_method_is_available():
    for name in ("theory", "event", "rk4", "paper", "auto"):
        assert parse_spec_text(spec_text(tail=f"method: {name}\n")).method == name


def test_the_catalogue_matches_the_implementations():
    """Every catalogued method is implemented, and every capability it claims is there to call."""
    from friction_sweep import methods
    from friction_sweep.bench import workprecision
    from friction_sweep.catalogue import METHODS

    for name, record in METHODS.items():
        module = methods.get(name)
        assert module.CATALOGUE is record
        assert record.sweep == hasattr(module, "compute_sweep_tile")
        assert record.time_history == hasattr(module, "time_histories")
        assert set(record.excitations) <= {"force", "base", "joined"}
        for setting in record.settings.values():
            assert setting.contains(setting.default)
        # `accuracy:` owns every knob that the benchmark calibrates, and every row lies in the ranges
        if record.accuracy_knobs:
            bench = workprecision.SETTINGS[record.calibrated_as]
            assert {k for row in bench for k in row} - {"max_evaluations"} <= set(record.accuracy_knobs)
            assert set(record.accuracy_knobs) <= set(record.settings)


def test_effects_are_validated_and_declared():
    spec = parse_spec_text(spec_text(effects="{viscous_damping: 0.05, static_friction_ratio: 1.2}",
                                     tail="method: event\n"))
    assert spec.scene.effects == {"viscous_damping": 0.05, "static_friction_ratio": 1.2}
    p = only(spec_error(spec_text(effects="{viscous_damping: 1.0}", tail="method: event\n")))
    assert p.key == "scene.effects.viscous_damping" and p.line == 3 and "between 0 and 1 (1 excluded)" in p.reason
    p = only(spec_error(spec_text(effects="{static_friction_ratio: 0.9}", tail="method: event\n")))
    assert p.key == "scene.effects.static_friction_ratio" and "between 1 and 100" in p.reason
    # an effect named without a value is off, as before effects were catalogued
    spec = parse_spec_text(spec_text(effects="{viscous_damping: null, static_friction_ratio: 1.2}",
                                     tail="method: event\n"))
    assert spec.scene.effects == {"static_friction_ratio": 1.2}


def test_accuracy_owns_the_knobs_its_calibration_varies_or_holds():
    for method, knob, value in (("event", "stop_tol", 1e-12), ("auto", "steady_tol", 1e-9),
                                ("rk4", "steps_per_period", 512), ("rk4", "steady_tol", 1e-9)):
        p = only(spec_error(spec_text(tail=f"method: {method}\naccuracy: 1e-3\nsettings: {{{knob}: {value}}}\n")))
        assert p.key == "accuracy" and knob in p.reason, (method, knob, p.reason)
    assert parse_spec_text(spec_text(tail="method: rk4\naccuracy: 1e-3\nsettings: {max_periods: 500}\n"))


def test_theory_refuses_effects_it_does_not_model():
    p = only(spec_error(spec_text(effects="{viscous_damping: 0.05}", tail="method: theory\n")))
    assert p.key == "scene.effects.viscous_damping" and p.line == 3
    assert "method 'theory' does not model viscous_damping (methods that do: event, rk4)" == p.reason


def test_method_settings_are_validated():
    spec = parse_spec_text(spec_text(tail="method: event\nsettings: {steady_tol: 1.0e-9, max_periods: 500}\n"))
    assert spec.settings == {"steady_tol": 1e-9, "max_periods": 500}
    p = only(spec_error(spec_text(tail="method: event\nsettings: {speed: 11}\n")))
    assert p.key == "settings.speed" and p.line == 8 and "unknown setting 'speed'" in p.reason
    p = only(spec_error(spec_text(tail="method: event\nsettings: {max_periods: 2.5}\n")))
    assert p.key == "settings.max_periods" and "integer" in p.reason
    p = only(spec_error(spec_text(tail="method: event\nsettings: {steady_tol: 0}\n")))
    assert p.key == "settings.steady_tol" and "between 1e-13 and 1e-06 (got 0)" in p.reason
    p = only(spec_error(spec_text(tail="method: theory\nsettings: {steady_tol: 1.0e-9}\n")))
    assert "allowed: none" in p.reason


def test_unknown_output():
    p = only(spec_error(spec_text(tail="outputs: [phase, energy]\n")))
    assert p.key == "outputs[1]" and (p.line, p.column) == (7, 18)
    assert "unknown output 'energy'" in p.reason


def test_duplicate_output():
    p = only(spec_error(spec_text(tail="outputs: [phase, phase]\n")))
    assert p.key == "outputs[1]" and "twice" in p.reason


def test_empty_outputs():
    p = only(spec_error(spec_text(tail="outputs: []\n")))
    assert p.key == "outputs" and p.line == 7 and "empty" in p.reason


@pytest.mark.parametrize("value", ['""', "3", "[a.h5]"])
def test_bad_output_path(value):
    p = only(spec_error(spec_text(tail=f"output: {value}\n")))
    assert p.key == "output" and p.line == 7 and "file path" in p.reason


# --- several problems at once --------------------------------------------------------------


def test_all_problems_are_collected_in_file_order():
    text = spec_text(excitation="shaker", fo="[0.1, -0.3]", tail="method: magic\nbogus: 1\n")
    err = spec_error(text)
    assert [p.key for p in err.errors] == ["scene.excitation", "grid.force_ratio[1]", "method", "bogus"]
    assert [p.line for p in err.errors] == [2, 6, 7, 8]
    assert (err.key, err.line, err.reason) == ("scene.excitation", 2, err.errors[0].reason)
    assert str(err).splitlines() == [str(p) for p in err.errors]


def test_spec_error_pickles():
    err = spec_error(spec_text(fo="[-1]"))
    again = pickle.loads(pickle.dumps(err))
    assert again.errors == err.errors and str(again) == str(err)


# --- property ------------------------------------------------------------------------------


@settings(max_examples=200, deadline=None)
@given(
    start=st.floats(min_value=1e-2, max_value=50.0),
    width=st.floats(min_value=1e-3, max_value=50.0),
    num=st.integers(min_value=1, max_value=2000),
)
def test_num_grid_property(start, width, num):
    stop = start if num == 1 else start + width
    spec = parse_spec_text(spec_text(fr=f"{{start: {start!r}, stop: {stop!r}, num: {num}}}"))
    r = spec.frequency_ratio
    assert len(r) == num
    assert r[0] == start and r[-1] == stop
    assert np.all(np.diff(r) > 0)


def test_time_history_needs_points_and_a_simulation_method():
    spec = parse_spec_text(spec_text(tail="method: event\noutputs: [regime, time_history]\n"
                                          "time_history: {points: [[0.95, 0.8], [0.3, 0.5]], samples_per_period: 64}\n"))
    assert spec.outputs == ("regime", "time_history")
    assert spec.time_history.points == [[0.95, 0.8], [0.3, 0.5]]
    p = only(spec_error(spec_text(tail="method: event\noutputs: [time_history]\n")))
    assert p.key == "outputs" and "time_history: {points" in p.reason
    p = only(spec_error(spec_text(tail="method: theory\noutputs: [time_history]\ntime_history: {points: [[1.5, 0.2]]}\n")))
    assert "cannot write output 'time_history'" in p.reason
    p = only(spec_error(spec_text(tail="method: event\ntime_history: {points: [[1.5, 0.2]]}\n")))
    assert p.key == "time_history" and "not listed in outputs" in p.reason
    p = only(spec_error(spec_text(tail="method: event\noutputs: [time_history]\ntime_history: {points: [[0, 0.2]]}\n")))
    assert p.key == "time_history.points[0][0]"
