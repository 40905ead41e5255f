"""Two steady states where static friction allows them (issue: two states).

The answers are held against an integrator written for the tests (independent_integrator.py), sharing no
code with the kernels: SciPy's DOP853 on the slip equation with the stops and the stick exits as
events, static friction deciding at every stop, marched until the stroboscopic map repeats.
"""

import numpy as np
import pytest
from independent_integrator import independent

from friction_sweep.codes import Regime
from friction_sweep.methods import event
from friction_sweep.storage import schema

OUTPUTS = ("transmissibility", "phase", "regime")
STATIC = {"static_friction_ratio": 1.5}


def both(excitation, r, beta):
    out = event.compute_tile(excitation, np.array([r]), np.array([beta]), OUTPUTS, STATIC)
    return {k: v.ravel()[0] for k, v in out.items()}


@pytest.mark.parametrize("excitation,r,beta,moving_regime", [
    ("base", 0.8, 0.7, Regime.CONTINUOUS),  # stuck from rest, continuous once moving (issue)
    ("base", 0.5, 0.7, Regime.STICK_SLIP),  # stuck from rest, two stops per period once moving
    ("joined", 0.89, 0.55, Regime.CONTINUOUS),  # rides with the wall from rest, moves relative once moving
])
def test_two_states_both_confirmed_by_an_independent_integrator(excitation, r, beta, moving_regime):
    p = both(excitation, r, beta)
    assert p["steady_states"] == 2
    assert p["regime"] == Regime.STUCK and p["regime_moving"] == moving_regime
    A = r * r if excitation == "joined" else 1.0
    c = 1.0 if excitation == "joined" else 0.0
    t_rest, stops_rest, stuck = independent(A, r, beta, 1.5 * beta, 0.0, 0.0, c)
    assert stuck and stops_rest == 0 and p["transmissibility"] == pytest.approx(t_rest, abs=1e-12)
    # a moving start of its own: the mass at the excitation's maximum, moving fast (not the tool's seed)
    t_moving, stops_moving, _ = independent(A, r, beta, 1.5 * beta, 0.0, 3.0 * A, c)
    assert p["transmissibility_moving"] == pytest.approx(t_moving, rel=1e-8)
    assert p["stops_per_period_moving"] == stops_moving


def test_where_the_starts_agree_there_is_one_state():
    p = both("base", 2.0, 0.3)
    assert p["steady_states"] == 1 and p["regime"] == p["regime_moving"] == Regime.CONTINUOUS
    t_rest, stops, _ = independent(1.0, 2.0, 0.3, 0.45, 0.0, 0.0)
    t_moving, _, _ = independent(1.0, 2.0, 0.3, 0.45, 0.0, 3.0)
    assert p["transmissibility"] == pytest.approx(t_rest, rel=1e-8)
    assert p["transmissibility_moving"] == pytest.approx(t_moving, rel=1e-8)
    assert stops == 0


def test_band_edge_at_fixed_r_is_where_the_reversal_force_meets_static_friction():
    """The continuous moving orbit exists while, at each velocity reversal, the force on the mass
    exceeds the static friction. At a reversal (a maximum q0 of Den Hartog's orbit, phase phi) that
    force is |cos(phi) - q0|; so at r = 0.8 the edge in beta solves |cos(phi) - x0| = 1.5 beta, with
    x0, phi the closed form (the moving orbit is Den Hartog's while it does not stop)."""
    from scipy.optimize import brentq

    from friction_sweep.theory import den_hartog as dh

    r = 0.8

    def margin(beta):
        x0 = float(dh.amplitude(r, beta))
        phi = float(dh.phase(r, beta))
        return abs(np.cos(phi) - x0) - 1.5 * beta

    edge = brentq(margin, 0.05, 0.8, xtol=1e-14)
    below, above = edge * (1 - 1e-3), edge * (1 + 1e-3)
    out = event.compute_tile("base", np.array([r]), np.array([below, above]), OUTPUTS, STATIC)
    assert out["regime_moving"][0, 0] == Regime.CONTINUOUS
    assert out["regime_moving"][1, 0] != Regime.CONTINUOUS


def test_one_start_costs_what_it_cost_and_plain_friction_adds_nothing():
    r, beta = np.array([0.5, 0.8, 2.0]), np.array([0.3, 0.7])
    one = event.compute_tile("base", r, beta, OUTPUTS, STATIC, {"starts": 1})
    two = event.compute_tile("base", r, beta, OUTPUTS, STATIC)
    assert set(two) - set(one) == {n + schema.MOVING_SUFFIX for n in event.variables_for("base", OUTPUTS)} | {
        "steady_states"}
    for name in one:
        np.testing.assert_array_equal(one[name], two[name])  # the state from rest is untouched
    plain = event.compute_tile("base", r, beta, OUTPUTS)
    assert not any(n.endswith(schema.MOVING_SUFFIX) for n in plain) and "steady_states" not in plain
