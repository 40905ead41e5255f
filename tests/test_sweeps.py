"""Swept starts, as rigs are run (`sweep: {direction: up | down}`): each point starts from the orbit
its neighbour along frequency_ratio settled on (issue: two states)."""

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import OUTPUTS, STATIC
from independent_integrator import independent

from friction_sweep.batch.runner import run_grid
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.kernels import period_map, steady
from friction_sweep.methods import event

R = np.round(np.arange(1, 61) * 0.05, 12)  # 0.05 .. 3


def swept(excitation, r, beta, effects, direction):
    return event.compute_sweep_tile(excitation, r, np.asarray(beta, float), OUTPUTS, effects, None, direction)


@pytest.mark.parametrize("excitation", ["base", "joined"])
def test_with_plain_friction_both_sweeps_find_the_one_state(excitation):
    """Static = kinetic friction: the steady state is unique (README), so the sweeps reproduce the
    default cube everywhere, the r = 1/(2n) family included."""
    beta = np.array([0.1, 0.3, 0.5, 0.7])
    default = event.compute_tile(excitation, R, beta, OUTPUTS)
    for direction in ("up", "down"):
        out = swept(excitation, R, beta, None, direction)
        np.testing.assert_array_equal(out["regime"], default["regime"])
        np.testing.assert_allclose(out["transmissibility"], default["transmissibility"], rtol=1e-6)


def test_the_joined_hysteresis_band_is_the_two_answers_of_the_default_cube():
    """Joined, static ratio 1.5, beta = 0.5: from rest the mass rides with the wall until r^2 > 1.5
    beta; a down sweep comes in moving and keeps moving below that. In the band between, the up sweep
    is the default cube's state from rest and the down sweep its state from the moving start."""
    r = np.round(np.arange(60, 121) * 0.01, 12)
    beta = np.array([0.5])
    default = event.compute_tile("joined", r, beta, OUTPUTS, STATIC)
    up, down = (swept("joined", r, beta, STATIC, d) for d in ("up", "down"))
    band = ~np.isclose(up["transmissibility"][0], down["transmissibility"][0], rtol=1e-5, equal_nan=True)
    assert band.sum() >= 5
    assert np.all(r[band] < np.sqrt(1.5 * 0.5) + 0.01)  # below the break-away from rest
    assert np.all(up["regime"][0, band] == Regime.STUCK) and np.all(down["regime"][0, band] != Regime.STUCK)
    assert np.all(default["steady_states"][0, band] == 2)
    np.testing.assert_allclose(up["transmissibility"][0, band], default["transmissibility"][0, band], rtol=1e-5)
    np.testing.assert_allclose(down["transmissibility"][0, band], default["transmissibility_moving"][0, band],
                               rtol=1e-5)
    same = ~band
    np.testing.assert_allclose(up["transmissibility"][0, same], default["transmissibility"][0, same], rtol=1e-5)


def test_a_state_that_only_a_sweep_finds_is_a_real_orbit():
    """Base (0.56, 0.3), ratio 1.5: both default starts reach a continuous orbit (1.4912), the sweeps
    a one-stop orbit (1.5178): three starts, two states, so the default count is a lower bound. The
    independent integrator, started where the up sweep's orbit begins, stays on that orbit."""
    r = np.round(np.arange(1, 57) * 0.01, 12)  # up to 0.56
    A, c, bk, bs, zeta = event.point_parameters("base", r, np.full(r.shape, 0.3), STATIC)
    raw = np.empty((r.size, steady.OUT_SIZE))
    settings = event.kernel_settings()
    steady.solve_sweep(A, r, bk, bs, zeta, c, settings, *event.newton_guess(A, r, bk, bs, zeta, settings), raw,
                       period_map.integrator(settings))
    last = raw[-1]
    default = event.compute_tile("base", r[-1:], np.array([0.3]), OUTPUTS, STATIC)
    assert default["steady_states"][0, 0] == 1
    assert abs(last[steady.OUT_TRANSMISSIBILITY] / default["transmissibility"][0, 0] - 1) > 1e-3  # another state
    t, stops, _ = independent(1.0, 0.56, 0.3, 0.45, last[steady.OUT_END_Q], last[steady.OUT_END_V])
    assert t == pytest.approx(last[steady.OUT_TRANSMISSIBILITY], rel=1e-8) and stops == last[steady.OUT_STOPS_PER_PERIOD] == 1


SPEC = """\
scene: {{excitation: joined, effects: {{static_friction_ratio: 1.5}}}}
grid:
  frequency_ratio: {{start: 0.6, stop: 1.4, step: 0.02}}
  force_ratio: [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
method: event
sweep: {{direction: {direction}}}
"""


@pytest.mark.slow
def test_a_swept_run_is_the_same_whatever_the_workers_and_resumes(tmp_path):
    spec = tmp_path / "down.yaml"
    spec.write_text(SPEC.format(direction="down"))
    runner = CliRunner()
    cubes = []
    for jobs, executor in ((1, "serial"), (2, "threads"), (2, "processes")):
        out = tmp_path / f"down-{jobs}-{executor}.h5"
        res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--quiet", "-j", str(jobs),
                                   "--executor", executor])
        assert res.exit_code == 0, res.output
        cubes.append(xr.open_dataset(out, engine="h5netcdf"))
    for other in cubes[1:]:
        for name in cubes[0].data_vars:
            np.testing.assert_array_equal(other[name].values, cubes[0][name].values)
    assert "transmissibility_moving" not in cubes[0]  # the sweep is the start
    assert '"sweep": "down"' in cubes[0].attrs["method_settings"]
    # resuming from one finished tile (of two: force ratios in blocks of 4) gives the same numbers
    r = cubes[0]["frequency_ratio"].values
    beta = cubes[0]["force_ratio"].values
    first = run_grid("event", "joined", r, beta[:4], OUTPUTS, effects=STATIC, sweep="down")
    resumed = run_grid("event", "joined", r, beta, OUTPUTS, effects=STATIC, sweep="down", done={0: first})
    np.testing.assert_array_equal(resumed["transmissibility"], cubes[0]["transmissibility"].values)


def test_a_sweep_is_refused_where_it_cannot_run(tmp_path):
    runner = CliRunner()
    spec = tmp_path / "bad.yaml"
    spec.write_text(SPEC.format(direction="up").replace("method: event", "method: theory")
                    .replace(", effects: {static_friction_ratio: 1.5}", ""))
    res = runner.invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2 and "cannot run a swept sweep" in res.output
    spec.write_text(SPEC.format(direction="sideways"))
    res = runner.invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2 and "sweep.direction" in res.output
    spec.write_text(SPEC.format(direction="up") + "settings: {starts: 2}\n")
    res = runner.invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2 and "settings.starts" in res.output


def test_without_any_dissipation_a_sweep_reports_the_forced_orbit():
    """beta = 0, no damping: a start off the forced orbit would carry its free motion forever; the
    steady state meant is the forced one, |X| = 1/|1 - r^2|, whatever a point starts from."""
    r = np.round(np.arange(0.3, 3.0, 0.037), 6)
    out = swept("base", r, [0.0], None, "up")
    exact = 1 / np.abs(1 - r * r)
    np.testing.assert_allclose(out["transmissibility"][0], exact, rtol=1e-10)
    np.testing.assert_allclose(out["peak_transmissibility"][0], exact, rtol=1e-10)
