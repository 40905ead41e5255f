"""Next to r = 1/(2n) (issue 28, class 2): the steady state is Den Hartog's stop-free orbit wherever it
exists, however close to the stick-free family r lies, and the tool says so in every scene.

At r = 1/(2n) + d the multiplier of Den Hartog's orbit is 1 - O(d^2 / beta) (1 to rounding at
|2nr - 1| = 2e-12, the 12-digit grid value 0.166666666667), so Newton cannot resolve the orbit, and a
march from rest creeps towards the family: one stop a period whose stuck time shrinks by a factor of 2
over some 2 x 10^5 periods. The march's per-period test took that creep for a stick-slip orbit (main: all
25 beta of the issue's grid `stick_slip`, stuck fraction 2e-4; joined at beta = 1e-12 `unsettled`). The
friction law is monotone, so the period map does not expand distances; a stick-free fixed point is then
the only one (kernels/shoot.py _neutral_closed_form), and the event kernel takes Den Hartog's closed
form, confirmed by one exact period, where the multiplier cannot be told from 1.
"""

from __future__ import annotations

import numpy as np
import pytest
from independent_integrator import one_period, steady_orbit

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import steady
from friction_sweep.methods import auto, event, theory
from friction_sweep.theory import den_hartog as dh

#: the issue's grid value: {start: 0.1, stop: 0.2, num: 31} written to 12 significant digits
ISSUE_R = 0.166666666667
#: where main's event kernel left the issue's point (base, beta = 0.001): at rest at the excitation's
#: maximum, one stop a period (its end_q)
MAIN_END_Q = 1.00099917077672


def test_the_issues_point_is_den_hartogs_orbit_by_an_independent_integrator(compiled):
    r, beta = ISSUE_R, 0.001
    T = 2 * np.pi / r
    qd, vd = (float(x[0]) for x in dh.section_state(np.array([r]), np.array([beta])))
    # DOP853 (no code shared with the kernels) from Den Hartog's closed-form state: back after one period,
    # never stopping: the stop-free orbit exists, so by monotonicity it is the only periodic one
    q1, v1, _, stops, stuck = one_period(1.0, r, beta, beta, 0.0, qd, vd)
    assert stops == 0 and stuck == 0.0
    assert abs(q1 - qd) + abs(v1 - vd) < 1e-10
    ref = steady_orbit(1.0, r, beta, beta, qd, vd)
    raw = event.solve_flat("base", np.array([r]), np.array([beta]))[0]
    assert raw[steady.OUT["regime"]] == Regime.CONTINUOUS
    assert raw[steady.OUT["stops_per_period"]] == 0.0 and raw[steady.OUT["stuck_fraction"]] == 0.0
    assert raw[steady.OUT["steady_state"]] == SteadyState.CONVERGED
    assert abs(raw[steady.OUT["transmissibility"]] / ref["amplitude"] - 1.0) < 1e-9
    assert abs(raw[steady.OUT["peak_transmissibility"]] / ref["peak"] - 1.0) < 1e-9
    # the tool's orbit is one for the independent integrator too: 5 periods repeat its state
    q, v = raw[steady.OUT["end_q"]], raw[steady.OUT["end_v"]]
    for k in range(5):
        q, v, _, stops, stuck = one_period(1.0, r, beta, beta, k * T, q, v)
        assert stops == 0 and stuck == 0.0
    assert abs(q - raw[steady.OUT["end_q"]]) + abs(v - raw[steady.OUT["end_v"]]) < 1e-9

    # main's stick-slip answer was a creep, not an orbit: from its state every DOP853 period sticks for
    # less time than the one before and ends nearer Den Hartog's orbit (the energy distance of the two
    # motions never grows, and shrinks while one of them sticks)
    q, v = MAIN_END_Q, 0.0
    last_stuck, last_distance = np.inf, np.hypot(q - qd, v - vd)
    for k in range(12):
        q, v, _, stops, stuck = one_period(1.0, r, beta, beta, k * T, q, v)
        distance = np.hypot(q - qd, v - vd)
        assert stops == 1 and 1e-4 < stuck / T < 3e-4
        assert stuck < last_stuck and distance < last_distance
        last_stuck, last_distance = stuck, distance


def _near_family_r(n: int) -> list[float]:
    """r = 1/(2n) in binary, its 12-digit grid value, and points from 2e-12 to 1e-6 (relative) either side."""
    r0 = 0.5 / n
    return [r0, float(f"{r0:.12g}"), *(r0 * (1.0 + s * d) for d in (2e-12, 1e-9, 1e-6) for s in (1.0, -1.0))]


def _agree_with_theory(method, excitation: str, r: float, settings=None) -> None:
    """Below 0.98 beta*(r), from 1e-12 up: the method's regime is the theory's (continuous) and its first
    harmonic the closed form's to 1e-8 (the rule `theory` of fsweep check). Above beta* the orbit sticks,
    next to the family as anywhere: there the closed form is not taken (it has no stop-free solution, or
    one that the exact period finds stopping)."""
    bstar = float(theory.continuous_limit(excitation, np.array([r]))[0])
    beta = np.array([1e-12, 1e-6, 1e-3 * bstar, 0.5 * bstar, 0.97 * bstar])
    out = method.compute_tile(excitation, np.array([r]), beta, ("transmissibility", "regime"), settings=settings)
    ref = theory.compute_tile(excitation, np.array([r]), beta, ("transmissibility", "regime"))
    assert (ref["regime"] == Regime.CONTINUOUS).all()
    np.testing.assert_array_equal(out["regime"], ref["regime"], err_msg=f"{excitation} r={r!r} beta={beta}")
    np.testing.assert_allclose(out["transmissibility"], ref["transmissibility"], rtol=1e-8, atol=0)
    above = np.array([1.05, 1.5]) * bstar
    out = method.compute_tile(excitation, np.array([r]), above, ("regime",), settings=settings)
    assert (out["regime"] == Regime.STICK_SLIP).all() and (out["stops_per_period"] >= 1).all(), (r, out["regime"])


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
@pytest.mark.parametrize("n", [1, 3])
def test_event_is_continuous_next_to_the_family(excitation, n, compiled):
    for r in _near_family_r(n):
        _agree_with_theory(event, excitation, r)


@pytest.mark.slow
@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
@pytest.mark.parametrize("n", [2, 4, 5, 8, 10])
def test_event_is_continuous_next_to_the_family_wide(excitation, n, compiled):
    for r in _near_family_r(n):
        _agree_with_theory(event, excitation, r)


@pytest.mark.parametrize("excitation", ["base", "joined"])
def test_auto_agrees_next_to_the_family(excitation, compiled):
    """auto simulates what lies near beta* (here all but b < 0.01 beta*): with event's answers."""
    for r in _near_family_r(3):
        _agree_with_theory(auto, excitation, r, {"theory_margin": 0.99})


def test_joined_issue_point_with_the_least_friction(compiled):
    """The issue's joined example: (0.166666666667, 1e-12) was `unsettled` (a march with almost nothing to
    dissipate); Den Hartog's orbit, confirmed, is its steady state."""
    out = event.compute_tile("joined", np.array([ISSUE_R]), np.array([1e-12]), ("transmissibility", "regime"))
    ref = theory.compute_tile("joined", np.array([ISSUE_R]), np.array([1e-12]), ("transmissibility", "regime"))
    assert out["regime"][0, 0] == Regime.CONTINUOUS and out["steady_state"][0, 0] == SteadyState.CONVERGED
    assert abs(out["transmissibility"][0, 0] / ref["transmissibility"][0, 0] - 1.0) < 1e-8



def test_beta_star_through_the_family_and_the_simulation_brackets_it(compiled):
    """beta*(1/(2n)) = r^2 V = 1/(4n^2 - 1) (U = 0 and S = 1 there), continuous through r = 1/(2n), and the
    exact simulation, at the binary and the 12-digit r, is stop-free just below it and stops just above
    (main: 0.166666666667 crept with a stop at 0.995 beta*)."""
    for n in (1, 2, 3, 5, 8):
        r0 = 0.5 / n
        rs = np.array([r0 * (1 - 1e-6), r0, float(f"{r0:.12g}"), r0 * (1 + 1e-6)])
        bstar = dh.continuous_limit(rs)
        assert abs(bstar[1] * (4 * n * n - 1) - 1.0) < 1e-12
        assert np.all(np.abs(bstar / bstar[1] - 1.0) < 1e-5)
        below = event.compute_tile("base", rs[1:3], 0.995 * bstar[1:2], ("regime",))
        above = event.compute_tile("base", rs[1:3], 1.005 * bstar[1:2], ("regime",))
        assert (below["regime"] == Regime.CONTINUOUS).all() and (below["stops_per_period"] == 0).all(), n
        assert (above["regime"] == Regime.STICK_SLIP).all() and (above["stops_per_period"] == 2).all(), n
