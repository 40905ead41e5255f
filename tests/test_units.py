"""A damper in physical units: `system:` and physical grid axes map onto (r, beta), and the cube carries
the physical coordinates and variables (spec/quantities.py, spec/system.py, storage/physical.py).

Expected values are worked out here by hand from unit definitions (2 pi rad per cycle, 60 s per minute,
standard gravity 9.80665 m/s^2), not read from pint or from the code under test.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import example, given, settings
from hypothesis import strategies as st

from friction_sweep.batch import pipeline
from friction_sweep.cli import main
from friction_sweep.spec import SpecError, parse_spec_text
from friction_sweep.spec.grid import round_significant
from friction_sweep.spec.quantities import (
    ACCELERATION,
    ANGLE,
    FORCE,
    FREQUENCY,
    LENGTH,
    MASS,
    RATIO,
    STIFFNESS,
    QuantityError,
    to_si,
)
from friction_sweep.storage import cube, schema

G0 = 9.80665
TWO_PI = 2.0 * math.pi


@pytest.mark.parametrize(("text", "kind", "si"), [
    ("50 Hz", FREQUENCY, 50.0),
    ("0.05 kHz", FREQUENCY, 50.0),
    ("314 rad/s", FREQUENCY, 314.0 / TWO_PI),  # the radian trap: not 314 Hz
    ("19.5721 rad/s", FREQUENCY, 19.5721 / TWO_PI),
    ("3000 rpm", FREQUENCY, 50.0),
    ("3000 revolution/minute", FREQUENCY, 50.0),
    ("3 cycle/s", FREQUENCY, 3.0),
    ("360 deg/s", FREQUENCY, 1.0),
    ("120 1/min", FREQUENCY, 2.0),  # no angle: cycles per minute
    ("40 kN/m", STIFFNESS, 40_000.0),
    ("40 N/mm", STIFFNESS, 40_000.0),
    ("2000 g", MASS, 2.0),
    ("2 kg", MASS, 2.0),
    ("1 mm", LENGTH, 1e-3),
    ("0.5 g", ACCELERATION, 0.5 * G0),  # g is gravity where an acceleration is asked for
    ("4.9 m/s^2", ACCELERATION, 4.9),
    ("12 N", FORCE, 12.0),
    ("1.2 kgf", FORCE, 1.2 * G0),
    ("0.3", RATIO, 0.3),
    (0.3, RATIO, 0.3),
    ("30 %", RATIO, 0.3),
])
def test_quantities_in_any_unit_of_their_dimension(text, kind, si):
    assert to_si(text, kind) == pytest.approx(si, rel=1e-14)


@pytest.mark.parametrize(("text", "kind", "reason"), [
    ("5 kg", FREQUENCY, "must be a frequency such as '50 Hz or 314 rad/s' (got '5 kg': a mass)"),
    ("3 Hz", LENGTH, "(got '3 Hz': a frequency)"),
    ("3 N m", FORCE, "of dimension"),
    (5, FORCE, "a number without a unit"),
    ("5", FREQUENCY, "a number without a unit"),
    ("5 blargs", FREQUENCY, "cannot read"),
    ("5 furlongs per fortnight", FREQUENCY, "(got '5 furlongs per fortnight': of dimension [length] / [time])"),
    ("", FORCE, "cannot read"),
    ("nan N", FORCE, "must be finite"),
    ("1e400 N", FORCE, "must be finite"),
    ("9**9**9 N", FORCE, "a unit's power is at most 4"),
    ("2 m/s", ACCELERATION, "an acceleration"),
    ("3 kg", RATIO, "a dimensionless number"),
    (True, FORCE, "must be a force"),
])
def test_quantities_refused_with_the_reason(text, kind, reason):
    with pytest.raises(QuantityError, match=None) as err:
        to_si(text, kind)
    assert reason in str(err.value)


# ---- the grammar of a quantity's text (spec/expression.py; issue 28) ---------------------------------

@pytest.mark.parametrize(("text", "kind", "si"), [
    ("kg m / s^2", FORCE, 1.0),  # side by side is a product
    ("kg*m/s**2", FORCE, 1.0),
    ("1e3N", FORCE, 1000.0),
    ("4.9 m/s\u00b2", ACCELERATION, 4.9),  # a superscript power
    ("2 m squared / m", LENGTH, 2.0),
    ("3 square m / mm", LENGTH, 3000.0),
    ("(2 m)**2 / m", LENGTH, 4.0),
    ("9**4 Hz", FREQUENCY, 6561.0),
    ("10 s^-1", FREQUENCY, 10.0),
    ("-2 N", FORCE, -2.0),  # the sign is the caller's to judge
    ("5 \u00b0", ANGLE, 5.0),
    ("1e-30 N", FORCE, 1e-30),  # the ends of the range of a physical value
    ("1e30 N", FORCE, 1e30),
    ("0 N", FORCE, 0.0),
])
def test_the_grammar_reads_products_powers_and_signs(text, kind, si):
    assert to_si(text, kind) == pytest.approx(si, rel=1e-14)


@pytest.mark.parametrize(("text", "kind", "reason"), [
    ("(((9**99)**99)**99)**99 Hz", FREQUENCY, "exponent 99 at character 7 is beyond 4: a unit's power is at most 4"),
    ("(9**99)**99 Hz", FREQUENCY, "a unit's power is at most 4"),
    ("m**-5 N", FORCE, "exponent -5 at character 5 is beyond 4"),
    ("m\u2075 N", FORCE, "is beyond 4"),
    ("2**2**2 N", FORCE, "a power applies to a number, a unit or a parenthesis, once"),
    ("m**(2) N", FORCE, "an exponent is a plain number of at most 4 (got '(' at character 4)"),
    ("((((10**4)**4)**4)**4)**4 Hz", FREQUENCY, "must be finite: it is beyond a double's range"),
    ("(((9**4)**4)**4)**3 * (((9**4)**4)**4)**3 Hz", FREQUENCY, "must be finite"),
    ("((9**4)**4)**4 Hz", FREQUENCY, "must be 0 or between 1e-30 and 1e+30 Hz (got '((9**4)**4)**4 Hz': 1.18e+61 Hz)"),
    ("1e200 Hz", FREQUENCY, "must be 0 or between 1e-30 and 1e+30 Hz"),
    ("1e-200 kg", MASS, "must be 0 or between 1e-30 and 1e+30 kg"),
    ("1e-320 N", FORCE, "must be 0 or between 1e-30 and 1e+30 N"),
    ("1e31", RATIO, "must be 0 or between 1e-30 and 1e+30 (got '1e31': 1e+31)"),
    (10**400, RATIO, "must be finite (got an integer of 401 digits)"),
    ("5 / 0 Hz", FREQUENCY, "divides by zero"),
    ("(-8)**0.5 N", FORCE, "a complex number"),
    ("1,5 N", FORCE, "a comma (write 1.5, not 1,5; 1000, not 1,000) at character 2"),
    ("\u0661\u0662 N", FORCE, "at character 1 is not part of a quantity"),  # Arabic-Indic digits
    ("__import__('os') N", FORCE, "is not part of a quantity"),
    ("inf N", FORCE, "must be finite (got 'inf')"),
    ("(5 N", FORCE, "the parenthesis at character 1 is not closed"),
    ("5 N)", FORCE, "unexpected ')' at character 4"),
    ("5 *", FORCE, "ends where a number or unit should follow"),
])
def test_the_grammar_refuses_with_the_reason(text, kind, reason):
    with pytest.raises(QuantityError) as err:
        to_si(text, kind)
    assert reason in str(err.value)


#: the characters a quantity's text is made of, and some it is not
EXPRESSION_TEXT = st.lists(st.sampled_from(list("0123456789.eE+-*/^() %,") + ["**", "Hz", "kg", "m", "N", "s", "rad",
                                                                                "\u00b2", "\u207b"]),
                           max_size=30).map("".join)


@settings(max_examples=400, deadline=None)
@given(text=EXPRESSION_TEXT, kind=st.sampled_from([FREQUENCY, FORCE, STIFFNESS, MASS, LENGTH, ACCELERATION, RATIO]))
@example(text="(((9**4)**4)**4)**3 * (((9**4)**4)**4)**3 Hz", kind=FREQUENCY)  # pint: OverflowError
@example(text="1e-200 Hz", kind=FREQUENCY)
def test_any_text_is_a_float_in_the_physical_range_or_a_quantity_error(text, kind):
    """Never an OverflowError, ZeroDivisionError or pint's own exceptions, and never a value outside the
    range every physical value keeps (0, or 1e-30 to 1e30 in SI)."""
    try:
        x = to_si(text, kind)
    except QuantityError:
        return
    assert math.isfinite(x) and (x == 0 or 1e-30 <= abs(x) <= 1e30), (text, x)


RIG = """\
scene: {excitation: base}
system:
  mass: 2 kg
  stiffness: 40 kN/m
  base_amplitude: 1 mm
grid:
  frequency: {start: 5 Hz, stop: 60 Hz, num: 12}
  friction_force: [6 N, 12 N, 24 N]
method: theory
"""


def test_a_rig_in_physical_units_maps_onto_r_and_beta():
    spec = parse_spec_text(RIG)
    f_n = math.sqrt(40_000.0 / 2.0) / TWO_PI
    np.testing.assert_array_equal(spec.frequency_ratio, round_significant(np.linspace(5.0, 60.0, 12) / f_n))
    np.testing.assert_array_equal(spec.force_ratio, [6 / 40, 12 / 40, 24 / 40])  # k Y = 40 kN/m x 1 mm = 40 N
    assert spec.physical is not None
    assert spec.physical.natural_frequency == pytest.approx(f_n, rel=1e-15)
    assert spec.physical.length_scale == 1e-3 and spec.physical.reference_force == pytest.approx(40.0)


def _problems(text: str) -> list[str]:
    with pytest.raises(SpecError) as err:
        parse_spec_text(text, "rig.yaml")
    return [str(p) for p in err.value.errors]


@pytest.mark.parametrize(("change", "expected"), [
    (("mass: 2 kg", "mass: 2 m"), "rig.yaml:3:9: system.mass: must be a mass"),
    (("mass: 2 kg", "mass: -2 kg"), "rig.yaml:3:9: system.mass: must be positive"),
    (("mass: 2 kg", "mass: 2"), "rig.yaml:3:9: system.mass: must be a mass with its unit"),
    (("  mass: 2 kg\n", ""), "rig.yaml:3:14: system.stiffness: stiffness alone fixes no natural frequency"),
    (("  mass: 2 kg\n", "  natural_frequency: 20 Hz\n  mass: 2 kg\n"), "system.mass: give two of natural_frequency"),
    (("base_amplitude: 1 mm", "base_amplitude: 1 mm\n  excitation_force: 40 N"), "not both"),
    (("[6 N, 12 N, 24 N]", "[6 N, 12 Hz]"), "rig.yaml:8:25: grid.friction_force[1]: must be a force"),
    (("[6 N, 12 N, 24 N]", "[12 N, 6 N]"), "grid.friction_force[1]: values must be strictly increasing"),
    (("start: 5 Hz", "start: 0.001 Hz"), "rig.yaml:7:3: grid.frequency: 0.001 Hz is r = 4.44288e-05 (r = f / f_n at "
                                         "f_n = 22.5079 Hz); it must be between 0.01 and 100"),
    (("  friction_force: [6 N, 12 N, 24 N]\n", ""), "rig.yaml:6:1: grid: give a force axis"),
    (("  friction_force: [6 N, 12 N, 24 N]\n", "  force_ratio: 0.3\n  friction_force: 6 N\n"),
     "grid.friction_force: give one force axis"),
    (("  base_amplitude: 1 mm\n", "  base_amplitude: 1 mm\n  friction_force: 3 N\n"),
     "system.friction_force: grid.friction_force sweeps the friction: give it in one place"),
    (("  base_amplitude: 1 mm\n", "  base_amplitude: 1 mm\n  damping: 3 N\n"), "system.damping: unknown key"),
    (("excitation: base", "excitation: force"), "system.base_amplitude: a force excitation's amplitude is a force"),
])
def test_physical_mistakes_are_located_and_explained(change, expected):
    old, new = change
    assert old in RIG
    problems = _problems(RIG.replace(old, new))
    assert any(expected in p for p in problems), problems


def test_a_physical_axis_needs_its_system():
    text = "scene: {excitation: base}\ngrid: {frequency: [5 Hz], force_ratio: 0.1}\n"
    assert _problems(text) == ["rig.yaml:2:8: grid.frequency: a physical axis needs the system it is measured on: "
                               "give `system:` with the natural frequency and the excitation's force"]


def test_the_cli_refuses_a_bad_quantity_with_exit_2_and_writes_nothing(runner, tmp_path):
    spec = tmp_path / "rig.yaml"
    spec.write_text(RIG.replace("40 kN/m", "40 kN"))
    out = tmp_path / "out.h5"
    res = runner.invoke(main, ["run", str(spec), "-o", str(out)])
    assert res.exit_code == 2
    assert f"{spec}:4:14: system.stiffness: must be a stiffness such as '40 kN/m' (got '40 kN': a force)" in res.output
    assert list(tmp_path.iterdir()) == [spec]


# ---- a physical spec and the dimensionless spec it maps to give the same cube ----------------------

#: unit -> Hz per unit, from the definitions (not pint): angular units divide by 2 pi
FREQUENCY_UNITS = {"Hz": 1.0, "kHz": 1e3, "rad/s": 1 / TWO_PI, "rpm": 1 / 60, "1/min": 1 / 60, "deg/s": 1 / 360}
#: unit -> N per unit
FORCE_UNITS = {"N": 1.0, "kN": 1e3, "mN": 1e-3, "kgf": G0}


def _cube(text: str) -> xr.Dataset:
    spec = parse_spec_text(text)
    arrays = pipeline.compute(spec, dict(spec.settings))
    return cube.as_dataset(pipeline.cube(spec, arrays, dict(spec.settings), "test"))


@settings(max_examples=40, deadline=None)
@given(
    f_n=st.floats(0.5, 5e3), f_unit=st.sampled_from(sorted(FREQUENCY_UNITS)),
    axis_unit=st.sampled_from(sorted(FREQUENCY_UNITS)), ratios=st.lists(st.floats(0.02, 50), min_size=1, max_size=4,
                                                                      unique=True),
    force=st.floats(1e-3, 1e4), force_unit=st.sampled_from(sorted(FORCE_UNITS)),
    friction_unit=st.sampled_from(sorted(FORCE_UNITS)), betas=st.lists(st.floats(0.0, 3.0), min_size=1, max_size=3,
                                                                       unique=True),
    excitation=st.sampled_from(["force", "base", "joined"]),
)
def test_physical_and_dimensionless_specs_give_the_same_cube(f_n, f_unit, axis_unit, ratios, force, force_unit,
                                                             friction_unit, betas, excitation):
    """Frequencies and forces written in any unit (rad/s and rpm included) land on the dimensionless
    grid that the hand conversion gives, after the grid's 12-digit rounding; the numbers are those
    of the dimensionless spec (method theory: the mapping is what is under test)."""
    frequencies = sorted({float(f"{f_n * x / FREQUENCY_UNITS[axis_unit] * FREQUENCY_UNITS[f_unit]:.9g}")
                          for x in ratios})
    frictions = sorted({float(f"{force * b / FORCE_UNITS[friction_unit] * FORCE_UNITS[force_unit]:.9g}")
                        for b in betas})
    physical = (f"scene: {{excitation: {excitation}}}\n"
                f"system: {{natural_frequency: {f_n!r} {f_unit}, excitation_force: {force!r} {force_unit}}}\n"
                f"grid:\n  frequency: [{', '.join(f'{f!r} {axis_unit}' for f in frequencies)}]\n"
                f"  friction_force: [{', '.join(f'{x!r} {friction_unit}' for x in frictions)}]\n")
    hz = np.array(frequencies) * FREQUENCY_UNITS[axis_unit]
    newton = np.array(frictions) * FORCE_UNITS[friction_unit]
    r = round_significant(hz / (f_n * FREQUENCY_UNITS[f_unit]))
    beta = round_significant(newton / (force * FORCE_UNITS[force_unit]))
    if np.any(np.diff(r) <= 0) or np.any(np.diff(beta) <= 0) or r[0] < 0.01 or r[-1] > 100 or \
            np.any((beta > 0) & (beta < 1e-12)):
        with pytest.raises(SpecError):
            parse_spec_text(physical)
        return
    dimensionless = (f"scene: {{excitation: {excitation}}}\ngrid:\n  frequency_ratio: {r.tolist()!r}\n"
                     f"  force_ratio: {beta.tolist()!r}\n")
    a, b = _cube(physical), _cube(dimensionless)
    for name in b.data_vars:  # the physical cube's own coordinates aside (the system's constants scalar ones)
        physical_coords = ["frequency", "friction_force", *schema.SCALAR_COORDS]
        xr.testing.assert_identical(a[name].drop_vars(physical_coords, errors="ignore"), b[name])
    np.testing.assert_allclose(a["natural_frequency"].values, f_n * FREQUENCY_UNITS[f_unit], rtol=1e-14)
    np.testing.assert_allclose(a["frequency"].values, hz, rtol=1e-14)
    np.testing.assert_allclose(a["friction_force"].values, newton, rtol=1e-14)


# ---- the cube in physical units --------------------------------------------------------------------

def test_the_cube_carries_physical_coordinates_and_variables_with_cf_units(tmp_path, compiled):
    text = RIG.replace("method: theory", "method: event\noutputs: [transmissibility, phase, regime, time_history]\n"
                       "time_history: {points: [[0.5, 0.3]], samples_per_period: 16}")
    spec = tmp_path / "rig.yaml"
    spec.write_text(text)
    out = tmp_path / "rig.h5"
    from click.testing import CliRunner

    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    ds = cube.open_cube(out)
    assert ds["frequency"].dims == ("frequency_ratio",) and ds["frequency"].attrs["units"] == "Hz"
    assert ds["friction_force"].dims == ("force_ratio",) and ds["friction_force"].attrs["units"] == "N"
    np.testing.assert_allclose(ds["frequency"].values, np.linspace(5.0, 60.0, 12), rtol=1e-15)
    np.testing.assert_array_equal(ds["friction_force"].values, [6.0, 12.0, 24.0])
    assert ds["displacement_amplitude"].attrs["units"] == "m"
    np.testing.assert_array_equal(ds["displacement_amplitude"].values, ds["transmissibility"].values * 1e-3)
    np.testing.assert_array_equal(ds["peak_displacement"].values, ds["peak_transmissibility"].values * 1e-3)
    # time in seconds: one forcing period of the history point (r = 0.5) lasts 1 / (0.5 f_n)
    f_n = math.sqrt(40_000.0 / 2.0) / TWO_PI
    t = ds["history_physical_time"].isel(history_point=0).values
    np.testing.assert_allclose(t, ds["history_time"].isel(history_point=0).values / (0.5 * f_n), rtol=1e-14)
    assert ds["history_physical_time"].attrs["units"] == "s"
    # the file reads back as the Dataset the API builds from the same parts
    info = CliRunner().invoke(main, ["info", str(out)])
    assert info.exit_code == 0, info.output
    assert "frequency: 5 .. 60 Hz" in info.output and "friction_force: 6 .. 24 N" in info.output
    assert "natural frequency f_n = 22.5079 Hz (omega_n = 141.421 rad/s)" in info.output
    assert "length scale Y = 0.001 m" in info.output
    check = CliRunner().invoke(main, ["check", str(out)])
    assert check.exit_code == 0, check.output


def test_the_writer_names_physical_coordinates_as_xarray_does(tmp_path):
    spec = parse_spec_text(RIG)
    parts = pipeline.cube(spec, pipeline.compute(spec, {}), {}, "test")
    cube.write_atomic(parts, tmp_path / "c.h5", overwrite=False)
    with xr.open_dataset(tmp_path / "c.h5", engine="h5netcdf") as back:
        xr.testing.assert_identical(back.load(), cube.as_dataset(parts))
    theirs = tmp_path / "x.h5"
    cube.as_dataset(parts).to_netcdf(theirs, engine="h5netcdf")
    import h5py

    with h5py.File(tmp_path / "c.h5") as ours, h5py.File(theirs) as xarrays:
        for name in xarrays:
            assert ours[name].attrs.get("coordinates") == xarrays[name].attrs.get("coordinates"), name


# ---- the rig of shared/data, entered physically ----------------------------------------------------

#: rows of the data file whose drive frequency and frequency-ratio columns disagree (beta = 0.265 from
#: r = 1.25 nominal up: by 0.008-0.02 in r, 1.1 % at most); the validation table uses the ratio column
INCONSISTENT_ROWS = {(0.2650, 1.25), (0.2650, 1.40), (0.2650, 1.55), (0.2650, 1.70), (0.2650, 1.85)}


def test_the_measured_rig_entered_physically_reproduces_the_validation_table():
    """The rig's own values (omega_n = 19.5721 rad/s, k Y = 2.5 N, friction forces in N, drive
    frequencies in rad/s) give the (r, beta) of the data file's ratio columns to their 4 decimals and
    the theory's first-harmonic phases of today's validation table, except at five rows where the file's
    drive frequency and ratio columns disagree (named above)."""
    from friction_sweep import validation

    table = validation.read_measurements()
    ours, today, measured = [], [], []
    for friction, rows in table.groupby("friction_force_N", sort=False):
        rows = rows.sort_values("drive_omega_rad_s")
        text = ("scene: {excitation: base}\n"
                "system: {natural_frequency: 19.5721 rad/s, excitation_force: 2.5 N}\n"
                f"grid:\n  frequency: [{', '.join(f'{w} rad/s' for w in rows['drive_omega_rad_s'])}]\n"
                f"  friction_force: {friction} N\nmethod: theory\n")
        spec = parse_spec_text(text)
        np.testing.assert_allclose(spec.force_ratio, rows["force_ratio"].iloc[:1], atol=5.1e-5)
        off = {(b, n) for b, n, r, r_file in zip(rows["force_ratio"], rows["frequency_ratio_nominal"],
                                                 spec.frequency_ratio, rows["frequency_ratio"], strict=True)
               if abs(r - r_file) > 5.1e-5}
        assert off == {x for x in INCONSISTENT_ROWS if x[0] == rows["force_ratio"].iloc[0]}
        consistent = np.array([(b, n) not in off for b, n in zip(rows["force_ratio"], rows["frequency_ratio_nominal"],
                                                                 strict=True)])
        phase = pipeline.compute(spec, {})["phase"][0]
        # today's table: the theory at the file's ratio columns
        reference = np.array([validation.predict_point("theory", r, b)["phase"]
                              for r, b in zip(rows["frequency_ratio"], rows["force_ratio"], strict=True)])
        np.testing.assert_allclose(phase[consistent], reference[consistent], atol=0.01)
        ours.append(phase)
        today.append(reference)
        measured.append(rows["phase_deg"].to_numpy())
    rms = [float(np.sqrt(np.mean(validation._wrap_difference(np.concatenate(p), np.concatenate(measured)) ** 2)))
           for p in (ours, today)]
    assert np.isfinite(rms).all() and rms[0] == pytest.approx(rms[1], abs=0.05), rms


def test_validate_prints_the_mapping(runner, tmp_path):
    spec = tmp_path / "rig.yaml"
    spec.write_text(RIG)
    res = runner.invoke(main, ["validate", str(spec), "-o", str(tmp_path / "o.h5")])
    assert res.exit_code == 0, res.output
    assert "excitation force F_k = k Y = 40 N: beta = F_mu / F_k" in res.output
    assert not (tmp_path / "o.h5").exists()


def test_a_dimensionless_spec_gets_no_physical_side():
    ds = _cube("scene: {excitation: base}\ngrid: {frequency_ratio: [0.5, 2.0], force_ratio: [0.1]}\n")
    assert not {"frequency", "friction_force", "displacement_amplitude"} & set(ds.variables)
    assert "physical_system" not in ds.attrs


def test_a_system_without_a_length_scale_writes_no_metres():
    """Natural frequency and forces fix (r, beta) but not Y: coordinates yes, displacements in m no."""
    ds = _cube("scene: {excitation: base}\nsystem: {natural_frequency: 10 Hz, excitation_force: 2 N}\n"
               "grid: {frequency_ratio: [0.5, 2.0], force_ratio: [0.1]}\n")
    np.testing.assert_allclose(ds["frequency"].values, [5.0, 20.0], rtol=1e-15)
    np.testing.assert_allclose(ds["friction_force"].values, [0.2], rtol=1e-15)
    assert "displacement_amplitude" not in ds


def test_design_quantities_in_joules_and_newtons():
    """Where the motion is continuous, friction dissipates 4 F_mu X a cycle (X the peak displacement):
    in joules from the newtons and metres of the rig; the force amplitude is F_k times the ratio."""
    ds = _cube(RIG.replace("method: theory", "outputs: [transmissibility, phase, regime, friction_energy, "
                           "transmitted_force]"))
    assert ds["dissipated_energy"].attrs["units"] == "J" and ds["force_amplitude"].attrs["units"] == "N"
    continuous = (ds["regime"] == 2).values
    assert continuous.sum() > 10
    four_f_x = 4.0 * ds["friction_force"] * ds["peak_displacement"]
    np.testing.assert_allclose(ds["dissipated_energy"].values[continuous], four_f_x.values[continuous], rtol=1e-12)
    np.testing.assert_allclose(ds["force_amplitude"].values, ds["transmitted_force"].values * 40.0, rtol=1e-15)


def test_the_readme_opens_with_the_demo_spec_as_it_is():
    """The README shows configs/demo.yaml verbatim, under the demo's picture (one fact, checked in two places)."""
    root = Path(__file__).resolve().parents[1]
    readme = (root / "README.md").read_text()
    head = readme[: readme.index("## Two commands")]
    assert "](docs/demo.png)" in head and (root / "docs" / "demo.png").is_file()
    assert "```yaml\n" + (root / "configs" / "demo.yaml").read_text() + "```" in head
