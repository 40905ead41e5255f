"""The fixed-step RK4 kernel with a real stick mode, against independent truths.

The truth is the exact event-driven kernel (closed-form segments, no step size) marched from the same
start state, the closed-form free decay (amplitude loss 4 bk per natural period) and the exact
no-motion limit. Every check is a number the RK4 method must reach, not a smoke test.
"""

import inspect
import math

import numpy as np
import pytest

from friction_sweep.kernels import event as ev
from friction_sweep.kernels import measure as rec
from friction_sweep.kernels import stick
from friction_sweep.kernels.point import Point
from friction_sweep.kernels.rk4 import advance_period_rk4

BUDGET = 10**7
STEPS = (32, 64, 128, 256, 512)

# the event kernel may carry extra trailing arguments (sample times and outputs); pass empty ones for those
# without a default (one with a default, such as harm=None, is a compile-time choice left out)
_EV_EXTRA = sum(p.default is inspect.Parameter.empty for p in inspect.signature(
    getattr(ev.advance_period, "py_func", ev.advance_period)).parameters.values()) - 8


def exact_period(state, A, r, bk, bs, zeta=0.0, c=0.0, measure=True):
    acc = rec.new_accumulator()
    q, v, mode, st, _ = ev.advance_period(*state, Point(A, r, bk, bs, zeta, c), 1e-12, BUDGET, measure, acc,
                                          *([np.empty(0)] * _EV_EXTRA))
    assert st == ev.OK
    return (q, v, mode), acc


def rk4_period(state, A, r, bk, bs, n, zeta=0.0, c=0.0, measure=True, budget=BUDGET):
    acc = rec.new_accumulator()
    q, v, mode, st, work = advance_period_rk4(*state, Point(A, r, bk, bs, zeta, c), n, budget, measure, acc)
    return (q, v, mode), acc, st, work


def on_orbit(A, r, bk, bs, zeta=0.0, c=0.0, periods=300):
    """The state at a period boundary on the steady orbit, from rest, by the exact kernel."""
    state = (0.0, 0.0, stick.decide(0.0, 0.0, A, r, bs))
    for _ in range(periods):
        state, _ = exact_period(state, A, r, bk, bs, zeta, c, measure=False)
    return state


def slope(errors, steps=STEPS):
    return -np.polyfit(np.log(steps), np.log(errors), 1)[0]


def state_error(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


# --- order 4 in the continuous region --------------------------------------------------------


@pytest.mark.parametrize("r, beta", [(2.0, 0.3), (0.8, 0.2)])
def test_fourth_order_in_the_continuous_region(r, beta):
    start = on_orbit(1.0, r, beta, beta)
    end, acc = exact_period(start, 1.0, r, beta, beta)
    assert acc[rec.ACC_STOPS] == 0 and acc[rec.ACC_EVENTS] == 2  # continuous: two reversals, no stick
    err_state, err_ic, err_harm = [], [], []
    for n in STEPS:
        got, a, st, work = rk4_period(start, 1.0, r, beta, beta, n)
        assert st == ev.OK and work >= n
        assert got[2] == end[2] and a[rec.ACC_EVENTS] == 2 and a[rec.ACC_STOPS] == 0
        err_state.append(state_error(got, end))
        err_ic.append(abs(a[rec.ACC_IC] - acc[rec.ACC_IC]))
        err_harm.append(math.hypot(a[rec.ACC_IC] - acc[rec.ACC_IC], a[rec.ACC_IS] - acc[rec.ACC_IS]))
    assert 3.6 <= slope(err_state) <= 4.4, err_state
    assert 3.6 <= slope(err_harm) <= 4.4, err_harm  # the first harmonic (cos and sin parts)
    assert slope(err_ic) >= 3.6, err_ic  # at r = 0.8 its leading h^4 term nearly cancels: slope ~5
    assert err_state[-1] < 1e-8 and err_harm[-1] < 1e-7


# --- stick-slip: converges to the exact orbit, same stops --------------------------------------


def test_stick_slip_converges_with_the_same_stops():
    A, r, beta = 1.0, 0.5, 0.5
    start = on_orbit(A, r, beta, beta)
    end, acc = exact_period(start, A, r, beta, beta)
    assert acc[rec.ACC_STOPS] == 2 and acc[rec.ACC_STUCK] > 0.1 * 2 * math.pi / r
    errors, stuck = [], []
    for n in STEPS:
        got, a, st, _ = rk4_period(start, A, r, beta, beta, n)
        assert st == ev.OK and got[2] == end[2]
        assert a[rec.ACC_STOPS] == acc[rec.ACC_STOPS] and a[rec.ACC_EVENTS] == acc[rec.ACC_EVENTS]
        errors.append(state_error(got, end))
        stuck.append(abs(a[rec.ACC_STUCK] - acc[rec.ACC_STUCK]))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(ratios >= 8.0), ratios  # ~16 per halving of h
    assert errors[-1] < 1e-7
    assert stuck[-1] < 1e-6 and np.all(np.diff(stuck) < 0)


# --- a real stick: no chattering ---------------------------------------------------------------


def _naive_sgn_rk4_sign_changes(q, v, A, r, beta, n):
    """The paper's approach (fixed-step RK4 on x'' + x + beta sgn(x') = cos): velocity sign flips."""
    def f(t, q, v):
        return v, A * math.cos(r * t) - q - beta * float(np.sign(v))

    h = 2 * math.pi / r / n
    flips = 0
    for k in range(n):
        t = k * h
        k1 = f(t, q, v)
        k2 = f(t + h / 2, q + h / 2 * k1[0], v + h / 2 * k1[1])
        k3 = f(t + h / 2, q + h / 2 * k2[0], v + h / 2 * k2[1])
        k4 = f(t + h, q + h * k3[0], v + h * k3[1])
        v_new = v + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        q += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        flips += v_new * v < 0
        v = v_new
    return flips


def test_long_stick_has_no_chattering():
    A, r, beta = 1.0, 0.3, 0.3
    start = on_orbit(A, r, beta, beta)
    _, acc = exact_period(start, A, r, beta, beta)
    T = 2 * math.pi / r
    assert acc[rec.ACC_STUCK] > 0.4 * T  # a long stick inside the period
    for n in (64, 256, 1024):
        _, a, st, work = rk4_period(start, A, r, beta, beta, n)
        assert st == ev.OK
        assert a[rec.ACC_EVENTS] == acc[rec.ACC_EVENTS] == 2
        assert a[rec.ACC_STOPS] == acc[rec.ACC_STOPS]
        assert work <= n + 2 * a[rec.ACC_EVENTS] + 2  # the stick costs no steps
    # the same grid with sgn friction chatters through the stick (6, 10, 48, 170 velocity sign
    # flips at 64, 256, 1024, 4096 steps: more with every refinement)
    assert _naive_sgn_rk4_sign_changes(start[0], 1e-12, A, r, beta, 1024) > 20


# --- no motion, free decay ---------------------------------------------------------------------


@pytest.mark.parametrize("bs", [1.0, 1.5])
def test_nothing_moves_when_static_friction_exceeds_the_force(bs):
    A, r = 1.0, 0.7
    state = (0.0, 0.0, stick.decide(0.0, 0.0, A, r, bs))
    for _ in range(3):
        state, a, st, work = rk4_period(state, A, r, bs, bs, 64)
        assert state == (0.0, 0.0, 0) and st == ev.OK and work == 0
        assert a[rec.ACC_STUCK] == 2 * math.pi / r
        assert a[rec.ACC_STOPS] == 0 and a[rec.ACC_EVENTS] == 0
        assert a[rec.ACC_IC] == 0.0 and a[rec.ACC_IS] == 0.0


def test_free_decay_loses_four_bk_per_period():
    bk = 0.5
    state = (10.0, 0.0, stick.decide(0.0, 10.0, 0.0, 1.0, bk))
    events = 0
    for n in range(1, 5):
        state, a, st, _ = rk4_period(state, 0.0, 1.0, bk, bk, 512)
        events += a[rec.ACC_EVENTS]
        assert st == ev.OK
        assert abs(state[0] - (10.0 - 4 * bk * n)) < 1e-9, (n, state)
        assert abs(state[1]) < 1e-7  # the period ends at a velocity zero
    # q = 2 -> -1 -> 0: inside the static band, it sticks for good. That last stop falls on the
    # period boundary, to within the method's error: it may be found at the start of period 6
    stops = 0
    for _ in range(2):
        state, a, st, _ = rk4_period(state, 0.0, 1.0, bk, bk, 512)
        events += a[rec.ACC_EVENTS]
        stops += a[rec.ACC_STOPS]
    assert state[2] == 0 and state[1] == 0.0 and abs(state[0]) < 1e-9 and stops == 1
    assert events == 10  # one velocity zero per half cycle, nothing more


# --- effects, measurement, budget -------------------------------------------------------------


def test_viscous_damping_converges_to_the_damped_closed_form():
    A, r, bk, bs, zeta = 1.0, 0.8, 0.2, 0.3, 0.05
    start = on_orbit(A, r, bk, bs, zeta)
    end, _ = exact_period(start, A, r, bk, bs, zeta)
    e1 = state_error(rk4_period(start, A, r, bk, bs, 128, zeta)[0], end)
    e2 = state_error(rk4_period(start, A, r, bk, bs, 256, zeta)[0], end)
    assert e2 < 1e-7 and 12.0 <= e1 / e2 <= 20.0


def test_joined_extremes_converge_to_the_exact_ones():
    # joined scene at r = 0.5, beta = 0.1: A = r^2, x = z + cos(r t); stick-slip
    A, r, beta, c = 0.25, 0.5, 0.1, 1.0
    start = on_orbit(A, r, beta, beta, c=c)
    _, acc = exact_period(start, A, r, beta, beta, c=c)
    _, a, _, _ = rk4_period(start, A, r, beta, beta, 256, c=c)
    assert abs(a[rec.ACC_XMAX] - acc[rec.ACC_XMAX]) < 1e-8 and abs(a[rec.ACC_XMIN] - acc[rec.ACC_XMIN]) < 1e-7
    assert abs(a[rec.ACC_TMAX] - acc[rec.ACC_TMAX]) < 1e-6


def test_budget_is_reported_not_raised():
    start = (0.0, 0.0, 1)
    _, _, st, work = rk4_period(start, 1.0, 2.0, 0.3, 0.3, 512, budget=100)
    assert st == ev.BUDGET and work > 100
