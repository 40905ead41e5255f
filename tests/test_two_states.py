"""Two steady states where static friction allows them (issue: two states).

The answers are held against an integrator written here, sharing no code with the kernels: SciPy's
DOP853 on the slip equation with the stops and the stick exits as events, static friction deciding
at every stop, marched from rest and from a moving start until the stroboscopic map repeats.
"""

import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad, solve_ivp

from friction_sweep import regimes
from friction_sweep.methods import event
from friction_sweep.storage import schema

OUTPUTS = ("transmissibility", "phase", "regime")
STATIC = {"static_friction_ratio": 1.5}


def independent(A, r, bk, bs, q, v, c=0.0, max_periods=400, tol=1e-11):
    """March q'' + q + f = A cos(r t) from (q, v) at t = 0 until (q, v) repeats from one period to the
    next; returns (first-harmonic amplitude of x = q + c cos(r t), stops per period, stuck at the end)."""
    T = 2 * np.pi / r

    def decide(t, q):
        d = A * np.cos(r * t) - q
        return 0 if abs(d) <= bs else int(np.sign(d))

    def period(t0, q, v):
        mode = int(np.sign(v)) if v != 0 else decide(t0, q)
        t, t_end, pieces, stops = t0, t0 + T, [], 0
        while t < t_end - 1e-13:
            if mode == 0:
                def band(tt, y, qs=q):
                    return (A * np.cos(r * tt) - qs) ** 2 - bs ** 2
                band.terminal, band.direction = True, 1
                sol = solve_ivp(lambda tt, y: [0.0], (t, t_end), [q], events=band, rtol=1e-12, atol=1e-13,
                                max_step=T / 512)
                t_new = sol.t_events[0][0] if sol.t_events[0].size else t_end
                pieces.append((t, t_new, lambda tt, qs=q: qs))
                t = t_new
                if t < t_end:
                    mode = 1 if A * np.cos(r * t) - q > 0 else -1
            else:
                sig = mode

                def rhs(tt, y):
                    return [y[1], A * np.cos(r * tt) - y[0] - sig * bk]

                def stop(tt, y):
                    return y[1]
                stop.terminal, stop.direction = True, -sig
                sol = solve_ivp(rhs, (t, t_end), [q, v], method="DOP853", events=stop, rtol=1e-12, atol=1e-13,
                                dense_output=True, first_step=1e-9)
                pieces.append((t, sol.t[-1], lambda tt, s=sol.sol: s(tt)[0]))
                q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
                if sol.status == 1:
                    v = 0.0
                    mode = decide(t, q)
                    stops += mode == 0
        return q, v, pieces, stops

    t = 0.0
    for _ in range(max_periods):
        q1, v1, pieces, stops = period(t, q, v)
        done = abs(q1 - q) + abs(v1 - v) <= tol * max(1.0, abs(q))
        q, v, t = q1, v1, t + T
        if done:
            break
    else:
        raise AssertionError("no steady state")
    a = b = 0.0
    with warnings.catch_warnings():  # quad's roundoff notice where a piece's integral is ~0
        warnings.simplefilter("ignore", IntegrationWarning)
        for lo, hi, f in pieces:
            if hi > lo:
                a += quad(lambda s: (f(s) + c * np.cos(r * s)) * np.cos(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
                b += quad(lambda s: (f(s) + c * np.cos(r * s)) * np.sin(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
    stuck_now = v == 0.0 and abs(A * np.cos(r * t) - q) <= bs
    return 2 / T * np.hypot(a, b), stops, stuck_now


def both(excitation, r, beta):
    out = event.compute_tile(excitation, np.array([r]), np.array([beta]), OUTPUTS, STATIC)
    return {k: v.ravel()[0] for k, v in out.items()}


@pytest.mark.parametrize("excitation,r,beta,moving_regime", [
    ("base", 0.8, 0.7, regimes.CONTINUOUS),  # stuck from rest, continuous once moving (issue)
    ("base", 0.5, 0.7, regimes.STICK_SLIP),  # stuck from rest, two stops per period once moving
    ("joined", 0.89, 0.55, regimes.CONTINUOUS),  # rides with the wall from rest, moves relative once moving
])
def test_two_states_both_confirmed_by_an_independent_integrator(excitation, r, beta, moving_regime):
    p = both(excitation, r, beta)
    assert p["steady_states"] == 2
    assert p["regime"] == regimes.STUCK and p["regime_moving"] == moving_regime
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
    assert p["steady_states"] == 1 and p["regime"] == p["regime_moving"] == regimes.CONTINUOUS
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
    assert out["regime_moving"][0, 0] == regimes.CONTINUOUS
    assert out["regime_moving"][1, 0] != regimes.CONTINUOUS


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
