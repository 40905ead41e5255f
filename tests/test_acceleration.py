"""Constant-acceleration excitation (`system.base_acceleration`): what shaker controllers hold. Y = a/omega^2,
so beta = F_mu / (k Y) grows with f^2 along a sweep; the cube's dims are then the physical ones
(friction_force, frequency) with r and beta as coordinates (spec/system.py, batch/runner.py).

Expected values are worked out here from a, k and f (standard gravity 9.80665 m/s^2), and each column of
the cube is compared with the dimensionless run at that column's (r, beta), which shares only the kernels."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from friction_sweep import api
from friction_sweep.cli import main
from friction_sweep.spec import SpecError, parse_spec_text
from friction_sweep.spec.grid import round_significant

G0 = 9.80665
SPEC = """\
scene: {{excitation: {excitation}}}
system:
  mass: 2 kg
  stiffness: 40 kN/m
  base_acceleration: 0.5 g
grid:
  frequency: [5 Hz, 12 Hz, 22 Hz, 40 Hz, 60 Hz]
  friction_force: [0 N, 1 N, 2.5 N, 4 N]
method: {method}
"""
F = np.array([5.0, 12.0, 22.0, 40.0, 60.0])
FRICTION = np.array([0.0, 1.0, 2.5, 4.0])


def _expected(f=F, friction=FRICTION, k=40_000.0, a=0.5 * G0):
    f_n = math.sqrt(k / 2.0) / (2 * math.pi)
    r = round_significant(f / f_n)
    beta = round_significant((friction[:, None] * (2 * math.pi * f[None, :]) ** 2 / (k * a)).ravel()).reshape(
        friction.size, f.size)
    return r, beta


def test_beta_grows_with_the_square_of_the_frequency():
    spec = parse_spec_text(SPEC.format(excitation="base", method="theory"))
    r, beta = _expected()
    np.testing.assert_array_equal(spec.frequency_ratio, r)
    np.testing.assert_array_equal(spec.force_ratio, beta)
    assert spec.force_count == FRICTION.size


@pytest.mark.parametrize(("excitation", "method"), [("base", "theory"), ("joined", "theory"), ("base", "event"),
                                                    ("joined", "event")])
def test_each_column_is_the_dimensionless_run_at_its_own_ratios(excitation, method, compiled):
    ds = api.sweep_yaml(SPEC.format(excitation=excitation, method=method))
    assert dict(ds.sizes) == {"friction_force": FRICTION.size, "frequency": F.size}
    assert ds["frequency_ratio"].dims == ("frequency",) and ds["force_ratio"].dims == ("friction_force", "frequency")
    assert ds["transmissibility"].dims == ("friction_force", "frequency")
    r, beta = _expected()
    for i in range(F.size):
        column = api.sweep_yaml(f"scene: {{excitation: {excitation}}}\ngrid: {{frequency_ratio: [{float(r[i])!r}], "
                                f"force_ratio: {beta[:, i].tolist()!r}}}\nmethod: {method}\n")
        for name in ("transmissibility", "phase", "regime"):
            np.testing.assert_array_equal(ds[name].values[:, i], column[name].values[:, 0], err_msg=f"{name} at {i}")


def test_lengths_in_metres_follow_y_of_each_frequency():
    ds = api.sweep_yaml(SPEC.format(excitation="base", method="theory"))
    y = 0.5 * G0 / (2 * math.pi * F) ** 2
    np.testing.assert_allclose(ds["displacement_amplitude"].values, ds["transmissibility"].values * y[None, :],
                               rtol=1e-14)
    assert ds["displacement_amplitude"].attrs["units"] == "m"


def test_check_info_and_plot_understand_a_physical_grid(runner, tmp_path):
    spec = tmp_path / "shaker.yaml"
    spec.write_text(SPEC.format(excitation="base", method="event"))
    out = tmp_path / "shaker.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(out), "-q", "-j", "2"]).exit_code == 0
    one = api.open_cube(out)
    serial = tmp_path / "serial.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(serial), "-q", "--executor", "serial"]).exit_code == 0
    xr.testing.assert_identical(one.drop_attrs(deep=False), api.open_cube(serial).drop_attrs(deep=False))
    check = runner.invoke(main, ["check", str(out)])
    assert check.exit_code == 0 and "theory      ok" in check.output, check.output
    info = runner.invoke(main, ["info", str(out)])
    assert info.exit_code == 0, info.output
    assert "dims: friction_force 4, frequency 5" in info.output
    assert "base acceleration a = 4.90332 m/s^2 held" in info.output
    from friction_sweep import quicklook

    fig = quicklook.draw(one, "map")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "frequency $f$ [Hz]" and ax.get_ylabel().endswith("[N]")
    curves = quicklook.draw(one, "curves")
    assert curves.axes[0].get_legend() is not None and len(curves.axes[0].lines) == FRICTION.size


@pytest.mark.parametrize(("change", "expected"), [
    (("excitation: {excitation}", "excitation: force"),
     "system.base_acceleration: a force excitation's amplitude is a force"),
    (("friction_force: [0 N, 1 N, 2.5 N, 4 N]", "force_ratio: [0.1]"),
     "grid.force_ratio: with system.base_acceleration the force ratio grows with f^2"),
    (("  mass: 2 kg\n  stiffness: 40 kN/m\n", "  natural_frequency: 20 Hz\n"),
     "system.base_acceleration: a base acceleration drives the mass"),
    (("base_acceleration: 0.5 g", "base_acceleration: 0.5 m/s"), "must be an acceleration"),
    (("base_acceleration: 0.5 g", "base_acceleration: 0.5 g\n  base_amplitude: 1 mm"), "give the excitation one way"),
    (("method: {method}", "method: event\nsweep: {{direction: up}}"), "sweep: a stepped-sine sweep at constant"),
    (("[0 N, 1 N, 2.5 N, 4 N]", "[0 N, 1e-13 N]"), "grid.friction_force: 1e-13 N at 5 Hz is beta = "),
])
def test_constant_acceleration_mistakes(change, expected):
    old, new = change
    text = SPEC.replace(old, new).format(excitation="base", method="theory")
    with pytest.raises(SpecError) as err:
        parse_spec_text(text, "s.yaml")
    assert any(expected in str(p) for p in err.value.errors), str(err.value)
