"""Fixed-step classical RK4 over one forcing period of the Jenkins contact (docs/equations.md §7), with the
contract of `jenkins.advance_period_jenkins`: state (q, v, w, mode, anchor) at a period boundary, the same
accumulator slots (JACC_SLIPS, JACC_JUMP included), the same labels and modes (+-1 slipping, 0 stuck and not
yet a stop, STUCK_HELD stuck and a stop; a creep is a slip the load never drives, as there, judged by
sig q'' at the slip's grid points).

Both modes are integrated by RK4 instead of in closed form:

- slip in direction sig (|fc| = bk, the slider follows the mass, w = q - sig bk / kappa):

      q'' + 2 zeta q' + q + sig bk = A cos(r t)

  exactly kernels/rk4.py's slip step (its `_rk4_step`, `_stop_in_step`, `_measure_slip`): the slip ends at
  the first zero of v on the step's cubic Hermite interpolant, where the slider sticks;
- stick (w fixed), in the contact spring's stretch d = q - w (so that fc = kappa d keeps its relative
  precision however stiff the contact):

      d'' + 2 zeta d' + (1 + kappa) d = A cos(r t) - w

  It ends where |kappa d| reaches bs, the first outward crossing of the band |d| <= bs / kappa by the cubic
  Hermite interpolant of d on the step, from either edge (a stick begun on one edge may leave through the
  other, 2 bs / kappa away); there the slider slips towards that edge, w jumping by (bs - bk) / kappa. A
  stick not yet held becomes a stop at the first zero of v inside it (on the cubic Hermite of v, as a
  slip's stop).

Each event is located inside its step, the step redone from its start to the event, and the rest of the
step completed in the new mode, so the grid stays aligned with the period (as kernels/rk4.py).

The step. A slip oscillates at the natural frequency 1, a stick at Omega = sqrt(1 + kappa): on the grid of
`steps_per_period` steps h = T / steps_per_period that serves the slip, a stiff stick would be unresolved
(h Omega of order 1 or more: RK4 is unstable beyond h Omega = 2 sqrt(2), and far from accurate well
before). Sticks are therefore sub-stepped: each grid step is split into m = ceil(Omega) equal steps while
the slider is stuck, so that h Omega / m <= h: the stuck oscillator gets at least as many steps per its
own natural period as the slip gets per its, the same fourth-order accuracy in h, and stability wherever
the slip's grid is (h < 2 sqrt(2), i.e. every steps_per_period the catalogue allows at r >= 0.1). Refusing
instead (unsettled where h Omega is too large) would refuse most of a kappa = 100 plane at the catalogue's
steps; the price of sub-stepping is the event kernel's too: a stick costs sqrt(kappa) times a slip's steps
per unit time (a point's work budget then bounds it, with status BUDGET). The fine grid (steps_per_period
m per period) contains the coarse one, so a slip begun inside a fine step runs to the end of its coarse
step.

Measurement: the first-harmonic integrals by 3-point Gauss-Legendre on each step's cubic Hermite
interpolant of q (q = w + d while stuck), the sliding distance from the slip steps (the slider's travel
while it slips; its jumps are JACC_JUMP's), extremes of x = q + c cos(r t) at step ends and events and,
where x' = v - c r sin(r t) changes sign inside a step, at its zero (v on its cubic Hermite, q on the
quintic one): in a stick the mass swings, so this holds for c = 0 too. No monodromy matrix (jac_ok = 0).

work counts RK4 steps (redone ones included) plus events; status BUDGET when it passes the budget.
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jenkins import JACC_JUMP, JACC_SLIPS, STUCK_HELD
from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_JAC_OK,
    ACC_STOPS,
    ACC_STUCK,
    BUDGET,
    OK,
    note_stop,
    offer_extreme,
)
from friction_sweep.kernels.rk4 import (
    CANNOT_MOVE,
    GL3_T,
    GL3_W,
    NO_STOP,
    _accel,
    _first_down,
    _herm5_q,
    _herm_q,
    _measure_slip,
    _rk4_step,
    _stop_in_step,
    turn_of_x,
)
from friction_sweep.kernels.segments import TWO_PI


@jit
def stick_substeps(kappa):
    """RK4 steps per grid step while the slider is stuck: m = ceil(Omega), Omega = sqrt(1 + kappa), so that
    the stick's step h/m times its frequency Omega is at most the slip's h times its frequency 1."""
    return int(math.ceil(math.sqrt(1.0 + kappa)))


@jit
def _rk4_stick(t, d, v, H, A, r, w, K, zeta, a0):
    """One classical RK4 step of the stick, d'' = A cos(r t) - w - K d - 2 zeta d' (K = 1 + kappa), of length
    H from (d, v) at t with a0 = d''(t) given. Returns (d1, v1, a1), a1 = d''(t + H) at the new state."""
    hh = 0.5 * H
    fm = A * math.cos(r * (t + hh)) - w  # forcing less the spring's pull to the slider, at the midpoint
    f1 = A * math.cos(r * (t + H)) - w
    k2d = v + hh * a0
    k2v = fm - K * (d + hh * v) - 2.0 * zeta * k2d
    k3d = v + hh * k2v
    k3v = fm - K * (d + hh * k2d) - 2.0 * zeta * k3d
    k4d = v + H * k3v
    k4v = f1 - K * (d + H * k3d) - 2.0 * zeta * k4d
    h6 = H / 6.0
    d1 = d + h6 * (v + 2.0 * (k2d + k3d) + k4d)
    v1 = v + h6 * (a0 + 2.0 * (k2v + k3v) + k4v)
    return d1, v1, f1 - K * d1 - 2.0 * zeta * v1


@jit
def _band_exit_in_step(d0, v0, d1, v1, H, hb):
    """First fraction x in (0, 1] of the step at which the cubic Hermite interpolant of d (d and d' = v at
    both ends) leaves the band |d| <= hb outwards, and the edge (+1: fc = +bs) it leaves by; (-1.0, 0) if it
    stays inside. For edge e the distance to the edge, hb - e d(x), must fall from > 0 to <= 0: a start on
    the edge (a stick begun where a slip stopped, with bs = bk) is not an exit (rk4._first_down), and a step
    whose Bernstein control points of that distance are all positive is proved free of it."""
    hv0 = H * v0
    hv1 = H * v1
    C2 = 3.0 * (d1 - d0) - 2.0 * hv0 - hv1
    C3 = 2.0 * (d0 - d1) + hv0 + hv1
    best = -1.0
    edge = 0
    for e in (1.0, -1.0):
        p0 = hb - e * d0
        p3 = hb - e * d1
        if p0 > 0.0 and p3 > 0.0 and p0 - e * hv0 / 3.0 > 0.0 and p3 + e * hv1 / 3.0 > 0.0:
            continue
        x = _first_down(p0, -e * hv0, -e * C2, -e * C3)
        if x >= 0.0 and (best < 0.0 or x < best):
            best = x
            edge = int(e)
    return best, edge


@jit
def _measure_stick_step(acc, t0, w, d0, v0, a0, d1, v1, a1, H, r, c):
    """Harmonic integrals and extremes of x over one stick step [t0, t0 + H] (q = w + d; no sliding). The
    mass swings on the contact spring, so x can peak inside the step for c = 0 too: at a sign change of
    x' = v - c r sin(r t), v on its cubic Hermite, q there on the quintic Hermite (O(H^6))."""
    if H > 0.0:
        for i in range(3):
            x = GL3_T[i]
            q = w + _herm_q(d0, v0, d1, v1, H, x)
            ph = r * (t0 + x * H)
            wq = H * GL3_W[i] * q
            acc[ACC_IC] += wq * math.cos(ph)
            acc[ACC_IS] += wq * math.sin(ph)
    t1 = t0 + H
    offer_extreme(acc, w + d0 + c * math.cos(r * t0), t0)
    offer_extreme(acc, w + d1 + c * math.cos(r * t1), t1)
    if H > 0.0:
        x = turn_of_x(t0, v0, a0, v1, a1, H, r, c)
        if x >= 0.0:
            tx = t0 + x * H
            offer_extreme(acc, w + _herm5_q(d0, v0, a0, d1, v1, a1, H, x) + c * math.cos(r * tx), tx)


@jit_inline
def _time_at(j, T, nf):
    """Time of fine grid point j (of nf per period; the period's end exactly T)."""
    return T if j >= nf else T * j / nf


@jit_inline
def _fine_step_of(t, T, nf):
    """The fine grid step j, [time j, time j + 1), that holds t (guarding int(t / T nf) against rounding)."""
    j = min(int(t / T * nf), nf - 1)
    while j + 1 < nf and _time_at(j + 1, T, nf) <= t:
        j += 1
    while j > 0 and _time_at(j, T, nf) > t:
        j -= 1
    return j


@jit
def advance_period_jenkins_rk4(q, v, w, mode, anchor, p, steps_per_period, budget, measure, acc):
    """March one forcing period of the Jenkins contact from t = 0 to T with fixed-step RK4 (steps_per_period
    steps while slipping, stick_substeps(kappa) times as many while stuck). Returns (q, v, w, mode, anchor,
    status, work), as jenkins.advance_period_jenkins."""
    A, r, bk, bs, zeta, c, kappa = p
    T = TWO_PI / r
    m = stick_substeps(kappa)
    nf = steps_per_period * m
    K = 1.0 + kappa
    hb = bs / kappa
    acc[ACC_JAC_OK] = 0.0
    t = 0.0
    j = 0  # the fine grid step holding t
    work = 0
    d = q - w  # while stuck the state is (d, v) and q = w + d
    have_a = False  # a_next holds the acceleration at (t, state) in the current mode
    a_next = 0.0
    stalled = False  # a slip could not start from the last stick exit: no exit until this fine step ends
    pending = False  # a slip begun at a stick exit, not counted until it moves
    stuck_before = 0  # the stuck mode that slip left
    while True:
        if mode == 0 or mode == STUCK_HELD:
            je = j + 1
            tk1 = _time_at(je, T, nf)
            H = tk1 - t
            if H <= 0.0:
                j = je
                if j >= nf:
                    return w + d, v, w, mode, anchor, OK, work
                continue
            if not have_a:
                a_next = A * math.cos(r * t) - w - K * d - 2.0 * zeta * v
            a0 = a_next
            d1, v1, a1 = _rk4_stick(t, d, v, H, A, r, w, K, zeta, a0)
            work += 1
            if work > budget:
                return w + d, v, w, mode, anchor, BUDGET, work
            xe = -1.0
            edge = 0
            if not stalled:
                # a start on or beyond an edge moving out of the band (or tied, not turning in) leaves at once
                for e in (1, -1):
                    if hb - e * d <= 0.0 and (e * v > 0.0 or (v == 0.0 and e * a0 >= 0.0)):
                        xe = 0.0
                        edge = e
                if xe < 0.0:
                    xe, edge = _band_exit_in_step(d, v, d1, v1, H, hb)
            stalled = False
            held_from = t
            if mode == 0 and xe != 0.0:
                # a stop once the mass's velocity returns to zero within the stick (before it ends)
                sv = 0
                if v != 0.0:
                    sv = 1 if v > 0.0 else -1
                elif a0 != 0.0:
                    sv = 1 if a0 > 0.0 else -1
                if sv != 0:
                    xs = _stop_in_step(sv, v, a0, v1, a1, H)
                    if xs > 0.0 and (xs < xe or (xe < 0.0 and xs <= 1.0)):
                        mode = STUCK_HELD
                        held_from = t + xs * H
                        acc[ACC_STOPS] += 1.0
            if xe < 0.0 or xe >= 1.0:
                t_end = tk1
                Hs = H
            else:
                Hs = xe * H
                t_end = min(t + Hs, tk1)
                if Hs > 0.0:
                    d1, v1, a1 = _rk4_stick(t, d, v, Hs, A, r, w, K, zeta, a0)
                    work += 1
                    if work > budget:
                        return w + d, v, w, mode, anchor, BUDGET, work
                else:
                    d1, v1, a1 = d, v, a0
            if mode == STUCK_HELD:
                acc[ACC_STUCK] += max(t_end - held_from, 0.0)
            if measure:
                _measure_stick_step(acc, t, w, d, v, a0, d1, v1, a1, Hs, r, c)
            t = t_end
            d = d1
            v = v1
            if xe < 0.0:
                a_next = a1
                have_a = True
                j = je
                if j >= nf:
                    return w + d, v, w, mode, anchor, OK, work
                continue
            have_a = False
            work += 1
            if work > budget:
                return w + d, v, w, mode, anchor, BUDGET, work
            if t >= T:
                # an exit at the period's end: the next period's start leaves at once from the edge
                return w + d, v, w, mode, anchor, OK, work
            # the slider slips towards the edge reached; the slip is counted once it moves (below)
            q = w + d
            stuck_before = mode
            mode = edge
            pending = True
            j = je if t >= tk1 else _fine_step_of(t, T, nf)
            continue
        sig = mode
        jc = (j // m + 1) * m  # a slip steps on the coarse grid: to the end of the coarse step holding t
        tk1 = _time_at(jc, T, nf)
        H = tk1 - t
        if H <= 0.0:
            j = jc
            if j >= nf:
                return q, v, q - sig * bk / kappa, mode, anchor, OK, work
            continue
        a0 = 0.0
        q1 = q
        v1 = 0.0
        a1 = 0.0
        if sig * v < 0.0:
            x = 0.0  # moving against the slip: a stop right here
        else:
            if not have_a:
                a_next = _accel(t, q, v, sig, A, r, bk, zeta)
            a0 = a_next
            q1, v1, a1 = _rk4_step(t, q, v, H, sig, A, r, bk, zeta, a0)
            work += 1
            if work > budget:
                return q, v, q - sig * bk / kappa, mode, anchor, BUDGET, work
            x = _stop_in_step(sig, v, a0, v1, a1, H)
            if x == CANNOT_MOVE:
                x = 0.0  # from rest, and never gets moving: a stop right here
                q1 = q
            Hs = H if x == NO_STOP or x >= 1.0 else x * H
            if 0.0 < x < 1.0:
                q1, v1, a1 = _rk4_step(t, q, v, Hs, sig, A, r, bk, zeta, a0)
                work += 1
                if work > budget:
                    return q, v, q - sig * bk / kappa, mode, anchor, BUDGET, work
        if pending:
            pending = False
            if x == 0.0 or q1 == q:
                # the force on the slider left the band tangentially and turned back: it stays stuck
                mode = stuck_before
                stalled = True
                have_a = False
                j = _fine_step_of(t, T, nf)
                continue
            anchor = w if stuck_before == STUCK_HELD else math.nan
            acc[JACC_SLIPS] += 1.0
            acc[JACC_JUMP] += 0.5 * (bs - bk) * (bs + bk) / kappa
        # a slip the load drives somewhere (sig q'' > 0 at a grid point of it) is no creep (jenkins.py)
        if not math.isnan(anchor) and x != 0.0 and (sig * a0 > 0.0 or sig * a1 > 0.0):
            anchor = math.nan
        if x == NO_STOP:
            if measure:
                _measure_slip(acc, t, q, v, a0, q1, v1, a1, H, r, c)
            a_next = a1
            have_a = True
            t = tk1
            q = q1
            v = v1
            j = jc
            if j >= nf:
                return q, v, q - sig * bk / kappa, mode, anchor, OK, work
            continue
        # a stop at fraction x of the step: the slider sticks there
        if measure and x > 0.0:
            _measure_slip(acc, t, q, v, a0, q1, v1, a1, Hs, r, c)
        have_a = False
        t = tk1 if x >= 1.0 else min(t + x * H, tk1)
        q = q1
        v = 0.0
        w = q - sig * bk / kappa
        d = sig * bk / kappa
        work += 1
        if work > budget:
            return q, v, w, mode, anchor, BUDGET, work
        note_stop(acc, q)
        # a creep within a stop leaves the mass held
        mode = 0 if math.isnan(anchor) else STUCK_HELD
        anchor = math.nan
        if t >= T:
            return q, v, w, mode, anchor, OK, work
        j = jc if t >= tk1 else _fine_step_of(t, T, nf)
