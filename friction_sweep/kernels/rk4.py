"""Fixed-step classical Runge-Kutta over one forcing period, with a real stick mode.

A baseline integrator with the same contract as `event.advance_period` (state (q, v, mode) at a
period boundary, period-local time 0 <= t <= T = 2 pi / r, the same accumulator slots), but the slip
motion q'' + 2 zeta q' + q + sig bk = A cos(r t) is integrated with RK4 on a uniform grid of
`steps_per_period` steps instead of in closed form. It never chatters: friction is not a `sgn` in the
right-hand side but a mode, as in the event kernel.

- Slip: after each RK4 step the cubic Hermite interpolant of v (v and v' at both ends, error O(h^4))
  is searched for its first fall of sig v to zero inside the step. A positive Bernstein hull proves
  most steps free of stops at the cost of four comparisons; otherwise the cubic is split at its
  critical points and the first down-crossing is bisected. The step is then redone from its start
  with the shorter length, v is set to 0 at the stop, the next mode is decided there
  (`stick.decide`), and the rest of the original step follows, so the grid stays aligned with the
  period. A slip from rest (v = 0) searches w(s)/s instead of w(s), so the initial zero is never a
  stop, and a tie at the band edge (w'(0) = 0) only needs w to turn positive strictly after 0.
- Stick: q and v frozen; the exit from the static band is the closed form `stick.stick_exit`
  (exact); the slip starts there, inside its grid step.
- Measurement: the first-harmonic integrals are 3-point Gauss-Legendre on each step's cubic Hermite
  interpolant of q (q and v at both ends: O(h^4) globally), exact on sticks; the sliding distance is
  the sum of |q1 - q0| over slip steps (to the order of the steps' ends and stops, O(h^4)). Extremes of
  x = q + c cos(r t) come from step ends and stops (for c = 0 they are velocity zeros, i.e. stops) and,
  for c != 0, from the zero of x' inside a step (cubic Hermite v against the exact forcing phase),
  where q is the quintic Hermite interpolant (q, v, q'' at both ends), so that a short piece next to
  a stop does not leave an O(piece^4) error that no grid refinement removes.

work counts RK4 steps (redone ones included) plus events; status BUDGET when it passes the budget.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_SLIDE,
    ACC_STOPS,
    ACC_STUCK,
    BUDGET,
    OK,
    measure_stick,
    note_stop,
    offer_extreme,
)
from friction_sweep.kernels.segments import TWO_PI
from friction_sweep.kernels.stick import decide, slip_direction, stick_phase

_GL3_X, _GL3_W = np.polynomial.legendre.leggauss(3)
#: 3-point Gauss-Legendre on [0, 1]: nodes and weights
GL3_T = np.ascontiguousarray(0.5 * (_GL3_X + 1.0))
GL3_W = np.ascontiguousarray(0.5 * _GL3_W)


@jit
def _accel(t, q, v, sig, A, r, bk, zeta):
    """The equation's right-hand side (segments.acceleration) grouped as RK4 evaluates it: the forcing
    and friction first, then the state. The same sum rounds differently from segments.acceleration's
    order; regrouping the RK4 kernel through that one function changes its results by up to 1e-14 of the
    transmissibility (and flips peak phases near 0), so RK4 keeps its grouping."""
    # zeta == 0: 2 zeta v is +-0.0, and subtracting a zero is exact
    return (A * math.cos(r * t) - sig * bk) - q - 2.0 * zeta * v


@jit
def _rk4_step(t, q, v, H, sig, A, r, bk, zeta, a0):
    """One classical RK4 step of length H from (q, v) at t, with a0 = q''(t) given.

    Returns (q1, v1, a1) with a1 = q''(t + H) at the new state (the next step's a0).
    """
    hh = 0.5 * H
    t1 = t + H
    fm = A * math.cos(r * (t + hh)) - sig * bk  # forcing and friction at the midpoint, used twice
    f1 = A * math.cos(r * t1) - sig * bk
    k2q = v + hh * a0
    k2v = fm - (q + hh * v) - 2.0 * zeta * k2q
    k3q = v + hh * k2v
    k3v = fm - (q + hh * k2q) - 2.0 * zeta * k3q
    k4q = v + H * k3v
    k4v = f1 - (q + H * k3q) - 2.0 * zeta * k4q
    h6 = H / 6.0
    q1 = q + h6 * (v + 2.0 * (k2q + k3q) + k4q)
    v1 = v + h6 * (a0 + 2.0 * (k2v + k3v) + k4v)
    return q1, v1, f1 - q1 - 2.0 * zeta * v1


@jit
def _cubic(p0, p1, p2, p3, x):
    return p0 + x * (p1 + x * (p2 + x * p3))


@jit
def _quad_roots01(c0, c1, c2):
    """Real roots of c0 + c1 x + c2 x^2 strictly inside (0, 1), ascending; nan where absent."""
    ra = math.nan
    rb = math.nan
    if c2 == 0.0:
        if c1 != 0.0:
            ra = -c0 / c1
    else:
        disc = c1 * c1 - 4.0 * c2 * c0
        if disc >= 0.0:
            sq = math.sqrt(disc)
            qq = -0.5 * (c1 + sq) if c1 >= 0.0 else -0.5 * (c1 - sq)
            if qq != 0.0:
                ra = qq / c2
                rb = c0 / qq
            else:  # c0 = c1 = 0: double root at 0
                ra = 0.0
    if not (0.0 < ra < 1.0):
        ra = math.nan
    if not (0.0 < rb < 1.0):
        rb = math.nan
    if math.isnan(ra):
        ra, rb = rb, math.nan
    elif not math.isnan(rb) and rb < ra:
        ra, rb = rb, ra
    return ra, rb


@jit
def _bisect_down(p0, p1, p2, p3, lo, hi):
    """Smallest x in (lo, hi] with p(x) <= 0, where p(lo) > 0 >= p(hi) and p is monotone there."""
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _cubic(p0, p1, p2, p3, mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@jit
def _first_down(p0, p1, p2, p3):
    """First x in (0, 1] where the cubic p falls from > 0 to <= 0 (after being positive on (0, x)).

    Returns -1.0 if there is none. p is split at its critical points into monotone pieces; a piece
    that starts at p <= 0 (a tie at theta = 0, to rounding) is not a fall.
    """
    c1, c2 = _quad_roots01(p1, 2.0 * p2, 3.0 * p3)
    lo = 0.0
    plo = p0
    for j in range(3):
        if j == 0:
            hi = c1 if not math.isnan(c1) else 1.0
        elif j == 1:
            if math.isnan(c1):
                break
            hi = c2 if not math.isnan(c2) else 1.0
        else:
            if math.isnan(c2):
                break
            hi = 1.0
        phi = _cubic(p0, p1, p2, p3, hi)
        if plo > 0.0 and phi <= 0.0:
            return _bisect_down(p0, p1, p2, p3, lo, hi)
        lo = hi
        plo = phi
        if hi >= 1.0:
            break
    return -1.0


#: _stop_in_step's answers besides a fraction of the step: no stop in it, or a start from rest that
#: never gets moving
NO_STOP = -1.0
CANNOT_MOVE = -2.0


@jit
def _stop_in_step(sig, v0, a0, v1, a1, H):
    """Fraction of the step (0, 1] at which sig v first falls to 0, or NO_STOP if it does not.

    From the cubic Hermite interpolant of v on the step (theta = s / H):
        w(theta) = sig (v0 + H a0 theta + C2 theta^2 + C3 theta^3).
    Returns CANNOT_MOVE when the motion starts from rest but sig v never turns positive.
    """
    d0 = H * a0
    d1 = H * a1
    C2 = 3.0 * (v1 - v0) - 2.0 * d0 - d1
    C3 = 2.0 * (v0 - v1) + d0 + d1
    w0 = sig * v0
    w1 = sig * v1
    if v0 == 0.0:
        # from rest: w = theta g(theta), g quadratic; the zero at theta = 0 is not a stop
        g0 = sig * d0
        g1 = sig * C2
        g2 = sig * C3
        if g0 > 0.0 and g0 + g1 + g2 > 0.0 and g0 + 0.5 * g1 > 0.0:
            return NO_STOP  # Bernstein hull of g positive
        x = _first_down(g0, g1, g2, 0.0)
        if x < 0.0 and w1 <= 0.0:
            return CANNOT_MOVE
        return x
    # Bernstein control points of w: all positive proves no zero in the step
    if w0 > 0.0 and w1 > 0.0 and w0 + sig * d0 / 3.0 > 0.0 and w1 - sig * d1 / 3.0 > 0.0:
        return NO_STOP
    return _first_down(w0, sig * d0, sig * C2, sig * C3)


@jit
def _herm_q(q0, v0, q1, v1, H, x):
    """Cubic Hermite interpolant of q at fraction x of a step of length H."""
    x2 = x * x
    x3 = x2 * x
    return ((2.0 * x3 - 3.0 * x2 + 1.0) * q0 + (x3 - 2.0 * x2 + x) * H * v0
            + (3.0 * x2 - 2.0 * x3) * q1 + (x3 - x2) * H * v1)


@jit
def _herm5_q(q0, v0, a0, q1, v1, a1, H, x):
    """Quintic Hermite interpolant of q (q, v, a at both ends) at fraction x of a step of length H."""
    x2 = x * x
    x3 = x2 * x
    x4 = x3 * x
    x5 = x4 * x
    h2 = H * H
    return ((1.0 - 10.0 * x3 + 15.0 * x4 - 6.0 * x5) * q0 + (x - 6.0 * x3 + 8.0 * x4 - 3.0 * x5) * H * v0
            + 0.5 * (x2 - 3.0 * x3 + 3.0 * x4 - x5) * h2 * a0 + (10.0 * x3 - 15.0 * x4 + 6.0 * x5) * q1
            + (-4.0 * x3 + 7.0 * x4 - 3.0 * x5) * H * v1 + 0.5 * (x3 - 2.0 * x4 + x5) * h2 * a1)


@jit
def _measure_slip(acc, t0, q0, v0, a0, q1, v1, a1, H, r, c):
    """Harmonic integrals, sliding distance and extremes of x over one slip step [t0, t0 + H] (q is
    monotone on it: a step ends at the first stop)."""
    acc[ACC_SLIDE] += abs(q1 - q0)
    if H > 0.0:
        for i in range(3):
            x = GL3_T[i]
            q = _herm_q(q0, v0, q1, v1, H, x)
            ph = r * (t0 + x * H)
            wq = H * GL3_W[i] * q
            acc[ACC_IC] += wq * math.cos(ph)
            acc[ACC_IS] += wq * math.sin(ph)
    t1 = t0 + H
    offer_extreme(acc, q0 + c * math.cos(r * t0), t0)
    offer_extreme(acc, q1 + c * math.cos(r * t1), t1)
    if c != 0.0 and H > 0.0:
        x = turn_of_x(t0, v0, a0, v1, a1, H, r, c)
        if x >= 0.0:
            q = _herm5_q(q0, v0, a0, q1, v1, a1, H, x)  # O(H^6): the piece may be a short one
            tx = t0 + x * H
            offer_extreme(acc, q + c * math.cos(r * tx), tx)


@jit_inline
def turn_of_x(t0, v0, a0, v1, a1, H, r, c):
    """Where in a step of length H from t0 the response x = q + c cos(r t) turns: the fraction x in (0, 1) at
    which x' = v - c r sin(r t) changes sign, v on its cubic Hermite (v, a at both ends), bisected to
    rounding; -1 where x' has the same sign at both ends (an interior extreme of x is then not sought)."""
    e0 = v0 - c * r * math.sin(r * t0)
    e1 = v1 - c * r * math.sin(r * (t0 + H))
    if not ((e0 > 0.0 and e1 < 0.0) or (e0 < 0.0 and e1 > 0.0)):
        return -1.0
    d0 = H * a0
    d1 = H * a1
    C2 = 3.0 * (v1 - v0) - 2.0 * d0 - d1
    C3 = 2.0 * (v0 - v1) + d0 + d1
    lo = 0.0
    hi = 1.0
    sgn_lo = e0 > 0.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        e = _cubic(v0, d0, C2, C3, mid) - c * r * math.sin(r * (t0 + mid * H))
        if (e > 0.0) == sgn_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@jit_inline
def _grid_step_of(t, h, n):
    """The grid step k, [k h, (k + 1) h], that holds t (guarding int(t / h) against rounding)."""
    k = min(int(t / h), n - 1)
    while k + 1 < n and (k + 1) * h <= t:
        k += 1
    while k > 0 and k * h > t:
        k -= 1
    return k


@jit_inline
def _rest_to_step_end(acc, q, t, tk1, p, after_stop, measure):
    """A start from rest that never gets moving inside its step (CANNOT_MOVE): a tie at the band edge
    decided by rounding (a sliver of a step after a stick exit), or no way to move. The mass rests to
    the step's end and the mode is decided there, so that the march always moves on (deciding again at
    the same t could cycle stick -> exit -> stop for ever). Returns the mode at tk1."""
    acc[ACC_STUCK] += tk1 - t
    if after_stop:
        acc[ACC_STOPS] += 1.0  # the stop turned out to be a stick of positive duration
    if measure:
        measure_stick(acc, q, t, tk1, p.r, p.c)
    return decide(tk1, q, p.A, p.r, p.bs)


@jit
def advance_period_rk4(q, v, mode, p, steps_per_period, budget, measure, acc):
    """March one forcing period from t = 0 to T with fixed-step RK4. Returns (q, v, mode, status, work).

    Same contract and accumulator record as `event.advance_period`; `steps_per_period` RK4 steps of
    T / steps_per_period on a grid aligned with the period.
    """
    A, r, bk, bs, zeta, c = p
    T = TWO_PI / r
    n = steps_per_period
    h = T / n
    k = 0  # current grid step: [k h, (k + 1) h]
    t = 0.0
    work = 0
    new_stop = False  # the last stop decided stick: count the stick if it lasts
    after_stop = False  # the slip from rest starts at a stop (not at a stick exit)
    have_a = False  # a_next holds q'' at (t, q, v) in mode mode_a (carried from the last step)
    a_next = 0.0
    mode_a = 0
    while True:
        if mode == 0:
            have_a = False
            te = stick_phase(acc, q, t, T, p, new_stop, measure, False)
            new_stop = False
            after_stop = False
            if te >= T:
                return q, 0.0, 0, OK, work
            t = te
            v = 0.0
            mode = slip_direction(t, q, A, r)
            work += 1
            k = _grid_step_of(t, h, n)
            continue
        tk1 = T if k + 1 >= n else (k + 1) * h
        H = tk1 - t
        if H <= 0.0:
            k += 1
            if k >= n:
                return q, v, mode, OK, work
            continue
        sig = mode
        have_a = have_a and sig == mode_a
        mode_a = sig
        if sig * v < 0.0:
            theta = 0.0  # moving against the mode: a stop right here (as segments.find_stop)
            q1 = q
        else:
            if not have_a:
                a_next = _accel(t, q, v, sig, A, r, bk, zeta)
            # The slip step is written out here, not a helper (not even a jit_inline one returning
            # (q1, v1, a1, theta, status, work) with one shared _measure_slip call): with the helper,
            # LLVM no longer inlined _stop_in_step's no-stop test into this loop, and RK4 ran ~10% slower.
            a0 = a_next
            q1, v1, a1 = _rk4_step(t, q, v, H, sig, A, r, bk, zeta, a0)
            work += 1
            if work > budget:
                return q, v, mode, BUDGET, work
            theta = _stop_in_step(sig, v, a0, v1, a1, H)
            if theta == NO_STOP:
                if measure:
                    _measure_slip(acc, t, q, v, a0, q1, v1, a1, H, r, c)
                a_next = a1  # q'' at the start of the next step, same state and mode
                have_a = True
                t = tk1
                q = q1
                v = v1
                k += 1
                if k >= n:
                    return q, v, mode, OK, work
                continue
            if theta == CANNOT_MOVE:
                mode = _rest_to_step_end(acc, q, t, tk1, p, after_stop, measure)
                t = tk1
                v = 0.0
                have_a = False
                new_stop = False  # a stick from here on is the same one
                after_stop = False
                k += 1
                if k >= n:
                    return q, v, mode, OK, work
                continue
            if theta < 1.0:
                Hs = theta * H
                q1, v1, a1 = _rk4_step(t, q, v, Hs, sig, A, r, bk, zeta, a0)
                work += 1
                if work > budget:
                    return q, v, mode, BUDGET, work
                if measure:
                    _measure_slip(acc, t, q, v, a0, q1, v1, a1, Hs, r, c)
            elif measure:
                _measure_slip(acc, t, q, v, a0, q1, v1, a1, H, r, c)
        # a stop at fraction theta of the step
        have_a = False
        if theta >= 1.0:
            t = tk1
        else:
            t = min(t + theta * H, tk1)
        q = q1
        v = 0.0
        work += 1
        if work > budget:
            return q, v, mode, BUDGET, work
        note_stop(acc, q)
        mode = decide(t, q, A, r, bs)
        new_stop = mode == 0
        after_stop = mode != 0
        if t >= tk1:
            k += 1
            if k >= n:
                return q, v, mode, OK, work
