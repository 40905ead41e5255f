"""Steady state of the event-driven kernel: march the stroboscopic map, shoot, measure.

solve_point marches forcing periods from rest until the Poincare map repeats (period 1 or k),
tries a Newton shooting solve of P(x) = x from the first stop-free period (exact monodromy
Jacobian; one period per step), recognises steady linear growth (resonance below pi/4) and then
measures over the k periods of the orbit. Everything is recorded as numbers and codes.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.kernels.event import (
    ACC_IC, ACC_IS, ACC_JAC, ACC_JOK, ACC_QMAX, ACC_SIZE, ACC_STOPS, ACC_STUCK, ACC_TMAX, ACC_XMAX, ACC_XMIN, BUDGET,
    advance_period, decide, reset_accumulator,
)
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.rk4 import advance_period_rk4
from friction_sweep.kernels.segments import TWO_PI

# status codes: the values of friction_sweep.regimes (kept literal so kernels import no Python objects)
CONVERGED, PERIOD_CAP, EVENT_BUDGET, NONFINITE, GROWING = 0, 1, 2, 3, 4
STUCK, STICK_SLIP, CONTINUOUS, UNBOUNDED, UNSETTLED = 0, 1, 2, 3, 4

# output slots of solve_point
(OUT_TRANS, OUT_PEAK, OUT_PHASE, OUT_PEAK_PHASE, OUT_STOPS, OUT_STUCK, OUT_REGIME, OUT_PERIODS,
 OUT_STEADY, OUT_ORBIT, OUT_WORK, OUT_Q, OUT_V, OUT_MODE) = range(14)
OUT_SIZE = 14

# settings slots (one float array, so a new knob never changes a signature)
(SET_STEADY_TOL, SET_VTOL, SET_MAX_PERIODS, SET_KMAX, SET_BUDGET, SET_SHOOT_AFTER, SET_SHOOT_EVERY, SET_KERNEL,
 SET_STEPS, SET_Q0, SET_V0) = range(11)
SET_SIZE = 11
KERNEL_EVENT, KERNEL_RK4 = 0, 1
DEFAULT_SETTINGS = {
    "steady_tol": 1e-10,  # |P^k(x) - x| <= steady_tol * |x| on the stroboscopic map
    "stop_tol": 1e-12,  # a stop is declared when |v| <= stop_tol * max(A, |(q, v)|)
    "max_periods": 2000,
    "max_orbit_period": 8,  # period-k orbits detected up to this k
    "work_budget": 5_000_000,  # stop-search steps and events per point
    "shoot_after": 1,  # periods marched before the first shooting attempt (1: measured fastest, make bench)
    "shoot_every": 48,
    "kernel": KERNEL_EVENT,  # which period integrator the driver marches: event (exact) or rk4
    "steps_per_period": 256,  # rk4 only
    "initial_displacement": 0.0,  # the march starts here (in the equation's length unit) at forcing phase 0
    "initial_velocity": 0.0,
}
_ORDER = ("steady_tol", "stop_tol", "max_periods", "max_orbit_period", "work_budget", "shoot_after", "shoot_every",
          "kernel", "steps_per_period", "initial_displacement", "initial_velocity")


def settings_array(**overrides) -> np.ndarray:
    values = dict(DEFAULT_SETTINGS)
    unknown = set(overrides) - set(values)
    if unknown:
        raise KeyError(f"unknown event settings: {sorted(unknown)}")
    values.update(overrides)
    return np.array([float(values[k]) for k in _ORDER])


@jit
def wrap_lag_degrees(rad):
    """Lag in degrees wrapped into [-90, 270) (friction_sweep.theory.phase)."""
    deg = rad * 180.0 / math.pi
    return (deg + 90.0) % 360.0 - 90.0 - 0.0


@jit
def _advance(q, v, mode, A, r, bk, bs, zeta, c, settings, budget, measure, acc):
    """One period with the chosen integrator (a runtime switch: cached kernels cannot take functions)."""
    if settings[SET_KERNEL] == KERNEL_RK4:
        return advance_period_rk4(q, v, mode, A, r, bk, bs, zeta, c, int(settings[SET_STEPS]), budget, measure, acc)
    none = np.empty(0)  # no samples (a global array would be a read-only constant to numba)
    return advance_period(q, v, mode, A, r, bk, bs, zeta, c, settings[SET_VTOL], budget, measure, acc, none, none,
                          none)


@jit
def _period(q, v, mode, A, r, bk, bs, zeta, c, settings, budget, acc):
    reset_accumulator(acc)
    return _advance(q, v, mode, A, r, bk, bs, zeta, c, settings, budget, False, acc)


@jit
def _mode_of(q, v, A, r, bs):
    if v > 0.0:
        return 1
    if v < 0.0:
        return -1
    return decide(0.0, q, A, r, bs)


@jit
def _spectral_radius(m11, m12, m21, m22):
    """Largest |eigenvalue| of a 2 x 2 matrix."""
    half = 0.5 * (m11 + m22)
    disc = half * half - (m11 * m22 - m12 * m21)
    if disc >= 0.0:
        return abs(half) + math.sqrt(disc)
    return math.sqrt(m11 * m22 - m12 * m21)


@jit
def _shoot(q, v, A, r, bk, bs, zeta, c, settings, tol, budget, acc):
    """Newton on F(x) = P(x) - x for a period-1 orbit. Returns (q, v, ok, work).

    The Jacobian is the event kernel's monodromy matrix (exact, saltation at reversals) wherever it
    is valid, else forward differences (rk4 kernel, periods with a stick). The evaluation that can
    confirm convergence also measures: on success `acc` holds the measurement of the period from
    the returned state, exactly as a separate measured pass would. Newton finds unstable orbits as
    readily as stable ones; only an attracting one (monodromy spectral radius < 1) is a steady state.
    """
    work = 0
    # Accept only after a small Newton step: where the map has no fixed point (r = 1, friction
    # below pi/4) a near-singular Jacobian leaps to a huge state whose relative residual looks tiny.
    last_step = math.inf
    prev_step = math.inf
    radius = math.inf
    size = max(math.hypot(q, v), acc[ACC_QMAX], 1e-300)
    for _ in range(40):
        scale = max(math.hypot(q, v), size)
        # Confirm (and measure) once Newton has hit its floor: a step below 1e-9 of the state, or one
        # below 1e-6 that no longer shrinks quadratically (rounding next to resonance). Stopping at the
        # first step below 1e-6 would leave ~1e-12 of the state, all of it in x = z + cos(r t) when x
        # is tiny (joined scene at high r).
        measure = last_step <= 1e-9 * scale or (last_step <= 1e-6 * scale and last_step >= 1e-2 * prev_step)
        reset_accumulator(acc)
        q1, v1, m1, st, w = _advance(q, v, _mode_of(q, v, A, r, bs), A, r, bk, bs, zeta, c, settings, budget, measure,
                                     acc)
        work += w
        if st != 0 or not (math.isfinite(q1) and math.isfinite(v1)):
            return q, v, False, work
        fq = q1 - q
        fv = v1 - v
        if abs(fq) + abs(fv) <= tol * scale and measure:
            if acc[ACC_JOK] == 1.0:
                radius = _spectral_radius(acc[ACC_JAC], acc[ACC_JAC + 1], acc[ACC_JAC + 2], acc[ACC_JAC + 3])
            return q, v, radius < 1.0, work
        if acc[ACC_JOK] == 1.0:
            j11 = acc[ACC_JAC] - 1.0
            j12 = acc[ACC_JAC + 1]
            j21 = acc[ACC_JAC + 2]
            j22 = acc[ACC_JAC + 3] - 1.0
        else:
            h = 1e-6 * scale
            qa, va, _, st1, w1 = _period(q + h, v, _mode_of(q + h, v, A, r, bs), A, r, bk, bs, zeta, c, settings,
                                         budget, acc)
            qb, vb, _, st2, w2 = _period(q, v + h, _mode_of(q, v + h, A, r, bs), A, r, bk, bs, zeta, c, settings,
                                         budget, acc)
            work += w1 + w2
            if st1 != 0 or st2 != 0:
                return q, v, False, work
            j11 = (qa - q1) / h - 1.0
            j21 = (va - v1) / h
            j12 = (qb - q1) / h
            j22 = (vb - v1) / h - 1.0
        radius = _spectral_radius(j11 + 1.0, j12, j21, j22 + 1.0)
        det = j11 * j22 - j12 * j21
        if det == 0.0 or not math.isfinite(det):
            return q, v, False, work
        dq = (j22 * fq - j12 * fv) / det
        dv = (-j21 * fq + j11 * fv) / det
        q -= dq
        v -= dv
        prev_step = last_step
        last_step = abs(dq) + abs(dv)
        if not (math.isfinite(q) and math.isfinite(v)):
            return q, v, False, work
    return q, v, False, work


@jit
def solve_point(A, r, bk, bs, zeta, c, settings, out):
    """Steady state and measurements of one grid point; results in `out` (OUT_* slots)."""
    tol = settings[SET_STEADY_TOL]
    max_periods = int(settings[SET_MAX_PERIODS])
    kmax = int(settings[SET_KMAX])
    budget = int(settings[SET_BUDGET])
    shoot_after = int(settings[SET_SHOOT_AFTER])
    shoot_every = int(settings[SET_SHOOT_EVERY])
    out[:] = math.nan
    acc = np.empty(ACC_SIZE)
    hq = np.empty(kmax + 1)
    hv = np.empty(kmax + 1)
    hm = np.empty(kmax + 1, dtype=np.int64)
    rho_hist = np.empty(64)

    q = settings[SET_Q0]
    v = settings[SET_V0]
    if bk == 0.0 and bs == 0.0 and zeta == 0.0 and r != 1.0 and q == 0.0 and v == 0.0:
        # Nothing dissipates: a transient from rest would never decay, and the orbit would be forced plus
        # free motion forever. The steady state meant is the forced one (the limit of vanishing damping):
        # start on it, q = A/(1 - r^2) at the excitation's maximum.
        q = A / ((1.0 - r) * (1.0 + r))
    mode = _mode_of(q, v, A, r, bs)
    hq[0], hv[0], hm[0] = q, v, mode
    work = 0
    status = PERIOD_CAP
    orbit = 0
    shot = False
    # shoot at the first stop-free period from shoot_after on, and again shoot_every periods after a miss
    next_shot = shoot_after
    n = 0
    while n < max_periods:
        n += 1
        q, v, mode, st, w = _period(q, v, mode, A, r, bk, bs, zeta, c, settings, budget - work, acc)
        work += w
        if st == BUDGET or work > budget:
            status = EVENT_BUDGET
            break
        if not (math.isfinite(q) and math.isfinite(v)):
            status = NONFINITE
            break
        rho = math.hypot(q, v)
        rho_hist[n % 64] = rho
        # the orbit's size, not the state at the section, which may sit near (0, 0)
        size = max(rho, acc[ACC_QMAX])
        if rho > 1e12 * max(A, 1.0):
            status = GROWING
            break
        for k in range(1, min(kmax, n) + 1):
            j = (n - k) % (kmax + 1)
            scale = max(size, math.hypot(hq[j], hv[j]))
            near = abs(q - hq[j]) + abs(v - hv[j]) <= tol * scale
            # modes must agree, except at rest on both sides of a decision tie
            same = hm[j] == mode or (abs(v) <= tol * scale and abs(hv[j]) <= tol * scale)
            if near and same:
                orbit = k
                break
        if orbit > 0:
            status = CONVERGED
            break
        i = n % (kmax + 1)
        hq[i], hv[i], hm[i] = q, v, mode
        no_stops = acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0
        if no_stops and n >= next_shot:
            qs, vs, ok, w = _shoot(q, v, A, r, bk, bs, zeta, c, settings, tol, budget - work, acc)
            work += w
            next_shot = n + shoot_every
            if ok:
                q, v = qs, vs
                mode = _mode_of(q, v, A, r, bs)
                orbit = 1
                status = CONVERGED
                shot = True
                break
        # Steady linear growth (resonance with friction below pi/4): 48 rising periods at a rate that
        # does not decay, after shooting had its chances. Only next to r = 1: a pure sinusoid pumps
        # without bound only at resonance, while Coulomb transients elsewhere also approach their
        # (bounded) steady state at a constant rate, which must not be mistaken for growth.
        if n >= 128 and n % 16 == 0 and abs(1.0 - r) * (1.0 + r) < 1e-6:
            rising = True
            for m in range(n - 47, n + 1):
                if rho_hist[m % 64] <= rho_hist[(m - 1) % 64]:
                    rising = False
                    break
            if rising:
                d_old = rho_hist[(n - 32) % 64] - rho_hist[(n - 47) % 64]
                d_new = rho_hist[n % 64] - rho_hist[(n - 15) % 64]
                if d_new >= 0.9 * d_old:
                    status = GROWING
                    break
    out[OUT_PERIODS] = n
    out[OUT_STEADY] = status
    out[OUT_WORK] = work
    if status == GROWING:
        out[OUT_REGIME] = UNBOUNDED
        return
    if status != CONVERGED:
        out[OUT_REGIME] = UNSETTLED
        return
    # measure over the k periods of the orbit (the state on the orbit is kept for replays); a shooting
    # solve measured its confirming period already
    out[OUT_Q], out[OUT_V], out[OUT_MODE] = q, v, mode
    if not shot:
        reset_accumulator(acc)
        for _ in range(orbit):
            q, v, mode, st, w = _advance(q, v, mode, A, r, bk, bs, zeta, c, settings, budget, True, acc)
            work += w
    T = TWO_PI / r
    total = orbit * T
    stuck_fraction = acc[ACC_STUCK] / total
    all_stuck = acc[ACC_STUCK] >= total * (1.0 - 1e-15)
    ic = 0.0 if all_stuck else acc[ACC_IC]
    is_ = 0.0 if all_stuck else acc[ACC_IS]
    a1 = r / math.pi * ic / orbit + c  # the c cos(r t) part of x projects exactly onto (c, 0)
    b1 = r / math.pi * is_ / orbit
    amp = math.hypot(a1, b1)
    out[OUT_TRANS] = amp
    out[OUT_PEAK] = max(acc[ACC_XMAX], -acc[ACC_XMIN])
    if amp > 0.0:
        out[OUT_PHASE] = wrap_lag_degrees(math.atan2(b1, a1))
    if out[OUT_PEAK] > 0.0:
        out[OUT_PEAK_PHASE] = wrap_lag_degrees(r * acc[ACC_TMAX])
    out[OUT_STOPS] = acc[ACC_STOPS] / orbit
    out[OUT_STUCK] = stuck_fraction
    out[OUT_ORBIT] = orbit
    out[OUT_WORK] = work
    if all_stuck:
        out[OUT_REGIME] = STUCK
    elif acc[ACC_STOPS] > 0.0:
        out[OUT_REGIME] = STICK_SLIP
    else:
        out[OUT_REGIME] = CONTINUOUS


@jit
def sample_orbit(q, v, mode, A, r, bk, bs, zeta, c, vtol, budget, periods, ts, sq, sv):
    """Replay `periods` forcing periods from a state on the orbit, sampling q, v at the local
    times ts (sorted, in [0, T)) of every period; sq, sv have shape (periods, ts.size)."""
    acc = np.empty(ACC_SIZE)
    for k in range(periods):
        reset_accumulator(acc)
        q, v, mode, st, w = advance_period(q, v, mode, A, r, bk, bs, zeta, c, vtol, budget, False, acc,
                                           ts, sq[k], sv[k])


@jit
def solve_points(A, r, bk, bs, zeta, c, settings, out):
    """solve_point over 1-D arrays of points; out has shape (n, OUT_SIZE)."""
    for i in range(r.size):
        solve_point(A[i], r[i], bk[i], bs[i], zeta[i], c[i], settings, out[i])
