"""The Jenkins contact from other starts than rest: stepped-sine sweeps, the second (moving) start with static
friction, and time histories of the steady orbit. Truths: where static equals kinetic friction the steady
state does not depend on the start (a sweep in either direction lands where the grid from rest does); a
second state is a genuine orbit (the tests' independent DOP853 integrator, started on it, stays on it with the
same labels); the sampled orbit's first harmonic is the measured transmissibility."""

import numpy as np
import pytest
from independent_jenkins import jenkins_orbit

from friction_sweep.codes import Regime
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady
from friction_sweep.methods import event
from friction_sweep.spec.parse import load_spec

OUTPUTS = ("transmissibility", "phase", "regime")
R = np.arange(0.2, 3.0, 0.05)
BETA = np.array([0.2, 0.5, 0.9])


@pytest.mark.parametrize("direction", ["up", "down"])
def test_sweep_lands_where_rest_does_with_one_friction(direction):
    effects = {"contact_stiffness": 100.0}
    grid = event.compute_tile("base", R, BETA, OUTPUTS, effects)
    sweep = event.compute_sweep_tile("base", R, BETA, OUTPUTS, effects, direction=direction)
    np.testing.assert_array_equal(sweep["regime"], grid["regime"])
    np.testing.assert_array_equal(sweep["slips_per_period"], grid["slips_per_period"])
    np.testing.assert_allclose(sweep["transmissibility"], grid["transmissibility"], rtol=1e-9)


def test_second_start_with_static_friction_finds_genuine_orbits():
    effects = {"contact_stiffness": 100.0, "static_friction_ratio": 1.5}
    tile = event.compute_tile("base", R, BETA, OUTPUTS, effects)
    assert {"regime_moving", "slips_per_period_moving", "steady_states"} <= set(tile)
    two = np.argwhere(tile["steady_states"] == 2)
    assert len(two) >= 2  # the grid crosses points with a stuck or slower state from rest and a moving one
    for j, i in two:
        r, beta = R[i], BETA[j]
        row = event.solve_moving("base", np.array([r]), np.array([beta]), effects)[0]
        assert row[steady.OUT_REGIME] in (Regime.STICK_SLIP, Regime.CONTINUOUS)
        A, c, bk, bs, zeta = (float(x[0]) for x in event.point_parameters("base", [r], [beta], effects))
        ind = jenkins_orbit(A, r, bk, bs, 100.0, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W],
                            int(row[steady.OUT_END_MODE]), c=c, zeta=zeta, kmax=16)
        assert ind["orbit_period"] == row[steady.OUT_ORBIT_PERIOD]
        assert (ind["slips"], ind["stops"]) == (row[js.JOUT_SLIPS], row[steady.OUT_STOPS_PER_PERIOD])
        assert ind["amplitude"] == pytest.approx(row[steady.OUT_TRANSMISSIBILITY], rel=1e-8)


@pytest.mark.parametrize(("excitation", "r", "beta"), [("base", [0.3, 0.6, 0.9, 1.1], 0.7),
                                                      ("joined", [0.7], 0.4), ("joined", [0.9], 0.6)])
def test_undamped_stiff_contact_keeps_the_rigid_models_two_states(excitation, r, beta):
    """Static friction, no damping, kappa = 1e4: where the rigid mass stays stuck from rest but keeps moving
    from the moving start, so does the contact's (the stuck oscillator's free motion decides whether a start
    settles without slipping, not a shortcut to the stuck orbit), and a sweep down keeps it moving."""
    r = np.array(r)
    effects = {"static_friction_ratio": 1.5}
    rigid = event.compute_tile(excitation, r, np.array([beta]), OUTPUTS, effects)
    contact = event.compute_tile(excitation, r, np.array([beta]), OUTPUTS, {**effects, "contact_stiffness": 1e4})
    assert (rigid["steady_states"] == 2).all() and (rigid["regime"] == Regime.STUCK).all()
    assert (contact["steady_states"] == 2).all() and (contact["regime"] == Regime.STUCK).all()
    assert np.isin(contact["regime_moving"], [Regime.STICK_SLIP, Regime.CONTINUOUS]).all()
    down = event.compute_sweep_tile(excitation, r, np.array([beta]), OUTPUTS, {**effects, "contact_stiffness": 1e4},
                                    direction="down")
    rigid_down = event.compute_sweep_tile(excitation, r, np.array([beta]), OUTPUTS, effects, direction="down")
    np.testing.assert_array_equal(down["regime"] != Regime.STUCK, rigid_down["regime"] != Regime.STUCK)


@pytest.mark.parametrize("excitation", ["base", "joined"])
def test_time_history_is_the_measured_orbit(excitation):
    points = [(0.5, 0.5), (1.5, 0.3), (2.0, 1.2)]  # stick-slip, continuous, a slider that never slips
    effects = {"contact_stiffness": 100.0}
    n = 2048
    hist = event.time_histories(excitation, points, n, effects)
    r, beta = np.array(points).T
    raw = event.solve_flat(excitation, r, beta, effects)
    for i in range(len(points)):
        k = int(hist["history_orbit_period"][i])
        assert k >= 1
        x = hist["history_displacement"][i, : k * n]
        angle = 2 * np.pi * np.arange(k * n) / n
        # the trapezoid rule on a periodic orbit whose acceleration jumps: error ~ 1/n^2
        first = np.hypot(2 * np.mean(x * np.cos(angle)), 2 * np.mean(x * np.sin(angle)))
        assert first == pytest.approx(raw[i, steady.OUT_TRANSMISSIBILITY], rel=1e-6, abs=1e-9)
        assert hist["history_relative_displacement"][i, 0] == pytest.approx(raw[i, steady.OUT_END_Q], abs=1e-12)


def test_spec_takes_sweeps_and_histories_with_the_effect(tmp_path):
    head = ("scene: {excitation: base, effects: {contact_stiffness: 100}}\n"
            "grid: {frequency_ratio: [0.5, 1.5], force_ratio: [0.3]}\nmethod: event\n")
    swept = tmp_path / "swept.yaml"
    swept.write_text(head + "sweep: {direction: down}\n")
    assert load_spec(swept).sweep is not None
    sampled = tmp_path / "sampled.yaml"
    sampled.write_text(head + "outputs: [transmissibility, regime, time_history]\n"
                       "time_history: {points: [[0.5, 0.3]], samples_per_period: 64}\n")
    assert load_spec(sampled).time_history is not None
