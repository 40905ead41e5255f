"""Steady state of the event-driven kernel: march the stroboscopic map, shoot, measure.

solve_point marches forcing periods from rest until the Poincare map repeats (period 1 or k),
tries a Newton shooting solve of P(x) = x from the first stop-free period (exact monodromy
Jacobian; one period per step), recognises steady linear growth (resonance below pi/4) and then
measures over the k periods of the orbit. Everything is recorded as numbers and codes.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels.event import (
    ACC_IC, ACC_IS, ACC_JAC, ACC_JOK, ACC_QHI, ACC_QLO, ACC_QMAX, ACC_SIZE, ACC_STOPS, ACC_STUCK, ACC_TMAX, ACC_XMAX,
    ACC_XMIN, BUDGET,
    advance_period, decide, reset_accumulator,
)
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.rk4 import advance_period_rk4
from friction_sweep.kernels.segments import TWO_PI, stuck_for_good
from friction_sweep.ties import RESONANCE_FRICTION_LIMIT, TIE_RTOL


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
    "max_orbit_period": 256,  # period-k orbits detected up to this k (static friction locks onto k up to ~250)
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


#: rounding of one period of the event map, relative to the orbit's size (measured: 5.5e-15 at
#: r = 1 +- 1e-10)
MAP_ROUNDING = 32.0 * 2.220446049250313e-16
#: a solution of P(x) = x is accepted only if the error that the map's own error (rounding, or RK4's
#: truncation: _map_error) can cause, |(J - I)^-1| times it, is below this relative: near r = 1,
#: |(J - I)^-1| ~ 0.23/|1 - r|, so
#: orbits are resolved down to |1 - r| ~ 2e-11; a "solution" of size 1e15 or more at r = 1, where the
#: map's O(1) drift per period is lost in rounding, has |(J - I)^-1| ~ its size and is refused
RESOLVABLE = 1e-4


@jit
def _inverse_norm(b11, b12, b21, b22):
    """|B^-1| (Frobenius: |B| / |det B| for 2 x 2); inf where B is singular."""
    det = b11 * b22 - b12 * b21
    if det == 0.0 or not math.isfinite(det):
        return math.inf
    return math.sqrt(b11 * b11 + b12 * b12 + b21 * b21 + b22 * b22) / abs(det)


@jit
def _map_error(r, settings):
    """Relative error of one period of the map: rounding for the event kernel; for RK4 also its
    truncation over the period, (2 pi / r) h^4 / 120 with h = 2 pi / (r steps_per_period) in natural
    time (the RK4 map of the oscillator has its resonance detuned by about that much, so at r = 1
    it has a bounded orbit of size ~1e8 that the true system lacks)."""
    if settings[SET_KERNEL] != KERNEL_RK4:
        return MAP_ROUNDING
    h = TWO_PI / (r * settings[SET_STEPS])
    return max(MAP_ROUNDING, TWO_PI / r * h ** 4 / 120.0)


@jit
def _resolvable(b11, b12, b21, b22, map_error):
    """Whether a fixed point of P with Jacobian J = I + B is pinned down by the map despite its own
    error: |B^-1| times that error (relative to the larger of the orbit and the forcing) is below
    RESOLVABLE."""
    return _inverse_norm(b11, b12, b21, b22) * map_error <= RESOLVABLE


@jit
def _within_forced_bound(acc, k, A, r, bk, bs, zeta):
    """The orbit's first harmonic Q1 (of q over its k measured periods, from ACC_IC/IS) obeys the bound
    that the equation itself proves: projecting q'' + 2 zeta q' + q + f = A cos(r t) onto the forcing
    frequency gives (1 - r^2 + 2i zeta r) Q1 = A - F1, and a friction force |f| <= max(bk, bs) has
    |F1| <= 4 max(bk, bs)/pi. Only a spurious orbit breaks it (always true at r = 1 without damping)."""
    q1 = r / math.pi * math.hypot(acc[ACC_IC], acc[ACC_IS]) / k
    gain = math.hypot((1.0 - r) * (1.0 + r), 2.0 * zeta * r)
    return q1 * gain <= (A + 4.0 / math.pi * max(bk, bs)) * (1.0 + 1e-9)


@jit
def _map(q, v, k, A, r, bk, bs, zeta, c, settings, budget, measure, acc):
    """P^k(q, v): k periods from (q, v), measured together in `acc` if asked. Returns (q, v, status,
    work); acc[ACC_JOK] vouches for the monodromy matrix only for k = 1."""
    reset_accumulator(acc)
    mode = _mode_of(q, v, A, r, bs)
    work = 0
    for _ in range(k):
        q, v, mode, st, w = _advance(q, v, mode, A, r, bk, bs, zeta, c, settings, budget - work, measure, acc)
        work += w
        if st != 0:
            return q, v, st, work
    if k > 1:
        acc[ACC_JOK] = 0.0
    return q, v, 0, work


@jit
def _shoot(q, v, k, A, r, bk, bs, zeta, c, settings, tol, budget, acc):
    """Newton on F(x) = P^k(x) - x for a period-k orbit. Returns (q, v, ok, work).

    The Jacobian is the event kernel's monodromy matrix (exact, saltation at reversals) wherever it
    is valid (k = 1), else forward differences (rk4 kernel, periods with a stick). The evaluation that can
    confirm convergence also measures: on success `acc` holds the measurement of the period from
    the returned state, exactly as a separate measured pass would. Newton finds unstable orbits as
    readily as stable ones; only an attracting one (monodromy spectral radius < 1) is a steady state,
    and only one that rounding cannot move far (_resolvable) and that obeys the forced bound.
    """
    work = 0
    map_error = _map_error(r, settings)
    # Accept only after a small Newton step: where the map has no fixed point (r = 1, friction
    # below pi/4) a near-singular Jacobian leaps to a huge state whose relative residual looks tiny.
    last_step = math.inf
    prev_step = math.inf
    radius = math.inf
    b11 = b12 = b21 = b22 = 0.0  # J - I of the latest Jacobian (exact, or forward differences)
    size = max(math.hypot(q, v), acc[ACC_QMAX], 1e-300)
    for _ in range(40):
        scale = max(math.hypot(q, v), size)
        # What the map's own error leaves: it is computed to ~map_error of the larger of the orbit and
        # the forcing (an orbit far smaller than A, next to the no-motion threshold, is pinned only
        # absolutely), and Newton's step inherits that times |(J - I)^-1|.
        noise = map_error * max(scale, A)
        step_noise = noise * min(_inverse_norm(b11, b12, b21, b22), 1e300) if last_step < math.inf else 0.0
        # Confirm (and measure) once Newton has hit its floor: a step below 1e-9 of the state, or one
        # below 1e-6 that no longer shrinks quadratically (rounding next to resonance). Stopping at the
        # first step below 1e-6 would leave ~1e-12 of the state, all of it in x = z + cos(r t) when x
        # is tiny (joined scene at high r).
        measure = (last_step <= 1e-9 * scale + step_noise
                   or (last_step <= 1e-6 * scale + step_noise and last_step >= 1e-2 * prev_step))
        q1, v1, st, w = _map(q, v, k, A, r, bk, bs, zeta, c, settings, budget - work, measure, acc)
        work += w
        if st != 0 or not (math.isfinite(q1) and math.isfinite(v1)):
            return q, v, False, work
        fq = q1 - q
        fv = v1 - v
        if abs(fq) + abs(fv) <= tol * scale + noise and measure:
            if acc[ACC_JOK] == 1.0:
                radius = _spectral_radius(acc[ACC_JAC], acc[ACC_JAC + 1], acc[ACC_JAC + 2], acc[ACC_JAC + 3])
                b11, b12 = acc[ACC_JAC] - 1.0, acc[ACC_JAC + 1]
                b21, b22 = acc[ACC_JAC + 2], acc[ACC_JAC + 3] - 1.0
            ok = (radius < 1.0 and _resolvable(b11, b12, b21, b22, map_error)
                  and _within_forced_bound(acc, k, A, r, bk, bs, zeta))
            return q, v, ok, work
        if acc[ACC_JOK] == 1.0:
            j11 = acc[ACC_JAC] - 1.0
            j12 = acc[ACC_JAC + 1]
            j21 = acc[ACC_JAC + 2]
            j22 = acc[ACC_JAC + 3] - 1.0
        else:
            # a step of 1e-6 of the orbit, or more where that would drown in the forcing's rounding
            h = max(1e-6 * scale, 1e-8 * math.sqrt(A * scale))
            qa, va, st1, w1 = _map(q + h, v, k, A, r, bk, bs, zeta, c, settings, budget - work, False, acc)
            qb, vb, st2, w2 = _map(q, v + h, k, A, r, bk, bs, zeta, c, settings, budget - work, False, acc)
            work += w1 + w2
            if st1 != 0 or st2 != 0:
                return q, v, False, work
            j11 = (qa - q1) / h - 1.0
            j21 = (va - v1) / h
            j12 = (qb - q1) / h
            j22 = (vb - v1) / h - 1.0
        radius = _spectral_radius(j11 + 1.0, j12, j21, j22 + 1.0)
        b11, b12, b21, b22 = j11, j12, j21, j22
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


#: A march that found no period-k orbit (k <= max_orbit_period) is `aperiodic` when its largest
#: Lyapunov exponent (per forcing period, over the march's second half) is above -1/max_orbit_period:
#: nearby states draw together by less than a factor e over the longest period looked for, so the
#: motion is chaotic (exponent > 0), quasi-periodic (~0) or locked onto a longer period (static
#: friction at r = 0.33, beta = 0.08: 1222 periods, exponent -1.3e-3). A motion that contracts faster
#: and still has not repeated is a transient the budget cut short: `period_cap`.
#: periods over which the exponent is averaged (the second half of the march, at least this many)
LYAPUNOV_PERIODS = 256
#: shooting through sticks accepts only an orbit within this fraction of the orbit's size from the march
STICK_SHOT_REACH = 0.05
#: at the period cap, a march whose state repeats at some lag k to this fraction of its size shoots for
#: the period-k orbit
LAG_SHOT = 1e-3
#: an aperiodic motion is measured as the average over this many forcing periods
APERIODIC_WINDOW = 256


@jit
def _subharmonic(r):
    """r = 1/(2n) to the tie tolerance (friction_sweep.ties.subharmonic_order)."""
    n = math.floor(0.5 / r + 0.5)
    return n >= 1.0 and abs(2.0 * n * r - 1.0) <= TIE_RTOL


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
    acc_y = np.empty(ACC_SIZE)
    map_error = _map_error(r, settings)

    q = settings[SET_Q0]
    v = settings[SET_V0]
    off_resonance = abs(1.0 - r) > TIE_RTOL
    if bk == 0.0 and bs == 0.0 and zeta == 0.0 and off_resonance:
        # Nothing dissipates: a transient from any start would never decay, and the orbit would be forced
        # plus free motion forever. The steady state meant is the forced one (the limit of vanishing
        # damping): start on it, q = A/(1 - r^2), v = 0 at the excitation's maximum, whatever the given start.
        q = A / ((1.0 - r) * (1.0 + r))
        v = 0.0
    mode = _mode_of(q, v, A, r, bs)
    hq[0], hv[0], hm[0] = q, v, mode
    work = 0
    status = SteadyState.PERIOD_CAP
    orbit = 0
    shot = False
    n = 0
    held = v == 0.0 and stuck_for_good(q, A, bs)
    if bk > 0.0 and bs == bk and zeta == 0.0 and not held and _subharmonic(r):
        # r = 1/(2n): stick-free orbits form a continuum (DESIGN.md §6), so the map has no isolated
        # fixed point to march to or shoot for. Its half-wave symmetric member is Den Hartog's, which
        # at U(r) = 0 starts from q = A/(1 - r^2), v = 0 at the excitation's maximum; one exact period
        # confirms it (no stop, back to the start). With static = kinetic friction the fixed points
        # form one convex set, here the family, so this holds whatever the start (a swept start too).
        qf = A / ((1.0 - r) * (1.0 + r))
        mf = _mode_of(qf, 0.0, A, r, bs)
        reset_accumulator(acc)
        q1, v1, _, st, w = _advance(qf, 0.0, mf, A, r, bk, bs, zeta, c, settings, budget, True, acc)
        work += w
        scale = max(abs(qf), acc[ACC_QMAX])
        if (st == 0 and mf != 0 and acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0
                and abs(q1 - qf) + abs(v1) <= tol * scale + map_error * max(scale, A)):
            q, v, mode = qf, 0.0, mf
            orbit = 1
            status = SteadyState.FAMILY
            shot = True  # measured already
            n = 1
    # shoot at the first stop-free period from shoot_after on, and again shoot_every periods after a miss
    next_shot = shoot_after
    # Over the march's second half a companion state at relative distance 1e-7 measures the largest
    # Lyapunov exponent (Benettin: renormalised after every period), to tell a motion that never
    # repeats from one that is still settling when the periods run out.
    lyap_from = max(1, max_periods - max(LYAPUNOV_PERIODS, max_periods // 2))
    yq = yv = delta = log_growth = 0.0
    ym = 0
    tracked = 0
    while n < max_periods and status == SteadyState.PERIOD_CAP:
        n += 1
        q, v, mode, st, w = _period(q, v, mode, A, r, bk, bs, zeta, c, settings, budget - work, acc)
        work += w
        if st == BUDGET or work > budget:
            status = SteadyState.EVENT_BUDGET
            break
        if not (math.isfinite(q) and math.isfinite(v)):
            status = SteadyState.NONFINITE
            break
        rho = math.hypot(q, v)
        rho_hist[n % 64] = rho
        # the orbit's size, not the state at the section, which may sit near (0, 0)
        size = max(rho, acc[ACC_QMAX])
        if rho > 1e12 * max(A, 1.0):
            status = SteadyState.GROWING
            break
        # Once shooting has had its chance, a state that moves by no more than the map's own rounding
        # (relative to the forcing: a motion far smaller than A just below the no-motion threshold
        # jitters at ~1e-17) has settled as far as double precision can tell.
        floor = map_error * max(size, A) if n > shoot_every else 0.0
        for k in range(1, min(kmax, n) + 1):
            j = (n - k) % (kmax + 1)
            scale = max(size, math.hypot(hq[j], hv[j]))
            near = abs(q - hq[j]) + abs(v - hv[j]) <= tol * scale + floor
            # modes must agree, except at rest on both sides of a decision tie
            same = hm[j] == mode or (abs(v) <= tol * scale and abs(hv[j]) <= tol * scale)
            if near and same:
                orbit = k
                break
        if orbit > 0:
            status = SteadyState.CONVERGED
            break
        i = n % (kmax + 1)
        hq[i], hv[i], hm[i] = q, v, mode
        if bs > bk and n >= lyap_from:  # only static friction can keep a motion from settling (below)
            if tracked > 0:
                yq, yv, ym, st, w = _period(yq, yv, ym, A, r, bk, bs, zeta, c, settings, budget - work, acc_y)
                work += w
                d = math.hypot(yq - q, yv - v)
                log_growth += math.log(d / delta) if d > 0.0 else -math.inf
            else:
                delta = 1e-7 * max(size, A)
                yq, yv = q, v
                d = 0.0
            # renormalise along the current separation (or along q to start)
            if d > 0.0 and math.isfinite(d):
                yq = q + delta * (yq - q) / d
                yv = v + delta * (yv - v) / d
            else:
                yq = q + delta
                yv = v
            ym = _mode_of(yq, yv, A, r, bs)
            tracked += 1
        no_stops = acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0
        # a march that still has not settled after shoot_every periods shoots through its sticks too
        if n >= next_shot and (no_stops or n >= shoot_every):
            qs, vs, ok, w = _shoot(q, v, 1, A, r, bk, bs, zeta, c, settings, tol, budget - work, acc)
            work += w
            next_shot = n + shoot_every
            # Through sticks the map is only piecewise smooth and Newton may land on another orbit than
            # the one the march approaches (at r = 1, b = pi/4 a stick-slip orbit of amplitude 0.8 while
            # the march from rest grows): accept only an orbit next to the march's state.
            if ok and not no_stops:
                ok = math.hypot(qs - q, vs - v) <= STICK_SHOT_REACH * max(size, A)
            if ok:
                q, v = qs, vs
                mode = _mode_of(q, v, A, r, bs)
                orbit = 1
                status = SteadyState.CONVERGED
                shot = True
                break
        # Steady linear growth (resonance with friction below pi/4): 48 rising periods at a rate that
        # does not decay, after shooting had its chances. Only next to r = 1, without damping and with
        # friction up to pi/4 of the force: a pure sinusoid pumps without bound only there (paper
        # Eqs. 14-15), while Coulomb transients elsewhere also approach their (bounded) steady state
        # at a constant rate, which must not be mistaken for growth.
        if (n >= 128 and n % 16 == 0 and abs(1.0 - r) * (1.0 + r) < 1e-6 and zeta == 0.0
                and bk <= RESONANCE_FRICTION_LIMIT * A * (1.0 + TIE_RTOL)):
            rising = True
            for m in range(n - 47, n + 1):
                if rho_hist[m % 64] <= rho_hist[(m - 1) % 64]:
                    rising = False
                    break
            if rising:
                d_old = rho_hist[(n - 32) % 64] - rho_hist[(n - 47) % 64]
                d_new = rho_hist[n % 64] - rho_hist[(n - 15) % 64]
                if d_new >= 0.9 * d_old:
                    status = SteadyState.GROWING
                    break
    if status == SteadyState.PERIOD_CAP and n >= 2:
        # Out of periods: a period-k orbit that the march approaches too slowly (static friction locks
        # onto long periods) is solved for directly, from the lag at which the march repeats best.
        best = math.inf
        lag = 0
        for k in range(1, min(kmax, n - 1) + 1):
            j = (n - k) % (kmax + 1)
            d = abs(q - hq[j]) + abs(v - hv[j])
            if d < best:
                best, lag = d, k
        if lag > 0 and best <= LAG_SHOT * max(math.hypot(q, v), acc[ACC_QMAX], A):
            qs, vs, ok, w = _shoot(q, v, lag, A, r, bk, bs, zeta, c, settings, tol, budget - work, acc)
            work += w
            if ok:
                q, v = qs, vs
                mode = _mode_of(q, v, A, r, bs)
                orbit = lag
                status = SteadyState.CONVERGED
                shot = True
    # only static friction above kinetic can keep a motion from settling: with bs == bk the friction
    # law is monotone and the period map does not expand distances (README, "Where the physics gets
    # hard"), so there a motion that has not repeated is a transient the budget cut short
    if (status == SteadyState.PERIOD_CAP and bs > bk and tracked > LYAPUNOV_PERIODS // 2
            and log_growth > -(tracked - 1) / kmax):
        status = SteadyState.APERIODIC
        orbit = APERIODIC_WINDOW
    out[OUT_PERIODS] = n
    out[OUT_STEADY] = status.value  # a float slot: numba casts no IntEnum to float
    out[OUT_WORK] = work
    # where the march ends (on the orbit, or where it gave up): a seed for another solve
    out[OUT_Q], out[OUT_V], out[OUT_MODE] = q, v, mode
    if status == SteadyState.GROWING:
        out[OUT_REGIME] = Regime.UNBOUNDED.value
        return
    if status != SteadyState.CONVERGED and status != SteadyState.FAMILY and status != SteadyState.APERIODIC:
        out[OUT_REGIME] = Regime.UNSETTLED.value
        return
    # measure over the k periods of the orbit (the state on the orbit, kept above, starts replays); a
    # shooting solve measured its confirming period already
    if not shot:
        reset_accumulator(acc)
        for _ in range(orbit):
            q, v, mode, st, w = _advance(q, v, mode, A, r, bk, bs, zeta, c, settings, budget - work, True, acc)
            work += w
            if st == BUDGET or work > budget:  # the measurement is part of the point's budget
                out[OUT_STEADY] = SteadyState.EVENT_BUDGET.value
                out[OUT_WORK] = work
                out[OUT_REGIME] = Regime.UNSETTLED.value
                return
    T = TWO_PI / r
    total = orbit * T
    stuck_fraction = acc[ACC_STUCK] / total
    # No motion: stuck the whole time, or sticking and slipping by less than the steady-state
    # tolerance (a start beyond the edge of the stuck band creeps towards it, ever more slowly: the
    # limit is stuck at the edge, and the orbit accepted within tolerance moves by less than that)
    moved = max(acc[ACC_QHI], out[OUT_Q]) - min(acc[ACC_QLO], out[OUT_Q])
    all_stuck = acc[ACC_STUCK] >= total * (1.0 - 1e-15) or (
        acc[ACC_STOPS] > 0.0 and moved <= tol * max(A, abs(out[OUT_Q])))
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
    out[OUT_STOPS] = 0.0 if all_stuck else acc[ACC_STOPS] / orbit
    out[OUT_STUCK] = 1.0 if all_stuck else stuck_fraction
    out[OUT_ORBIT] = orbit
    out[OUT_WORK] = work
    if all_stuck:
        out[OUT_REGIME] = Regime.STUCK.value
    elif acc[ACC_STOPS] > 0.0:
        out[OUT_REGIME] = Regime.STICK_SLIP.value
    else:
        out[OUT_REGIME] = Regime.CONTINUOUS.value


@jit
def sample_orbit(q, v, mode, A, r, bk, bs, zeta, c, vtol, budget, periods, ts, sq, sv):
    """Replay `periods` forcing periods from a state on the orbit, sampling q, v at the local
    times ts (sorted, in [0, T)) of every period; sq, sv have shape (periods, ts.size). Returns
    BUDGET if the replay ran out of `budget` (the samples are then incomplete), else 0."""
    acc = np.empty(ACC_SIZE)
    work = 0
    for k in range(periods):
        reset_accumulator(acc)
        q, v, mode, st, w = advance_period(q, v, mode, A, r, bk, bs, zeta, c, vtol, budget - work, False, acc,
                                           ts, sq[k], sv[k])
        work += w
        if st == BUDGET or work > budget:
            return BUDGET
    return 0


@jit
def solve_points(A, r, bk, bs, zeta, c, settings, out):
    """solve_point over 1-D arrays of points; out has shape (n, OUT_SIZE)."""
    for i in range(r.size):
        solve_point(A[i], r[i], bk[i], bs[i], zeta[i], c[i], settings, out[i])


@jit
def solve_points_from(A, r, bk, bs, zeta, c, settings, q0, v0, out):
    """solve_points with a start (q0[i], v0[i]) of its own for each point (at the excitation's maximum)."""
    own = settings.copy()
    for i in range(r.size):
        own[SET_Q0] = q0[i]
        own[SET_V0] = v0[i]
        solve_point(A[i], r[i], bk[i], bs[i], zeta[i], c[i], own, out[i])


@jit
def solve_sweep(A, r, bk, bs, zeta, c, settings, out):
    """A stepped-sine sweep over the points in the order given (one force ratio): each point starts
    from the state, at the excitation's maximum, of the orbit the previous point settled on, as a rig
    stepping its frequency does; the first from the settings' start. After a point with no steady
    state (unbounded, unsettled) the next starts afresh from the settings' start."""
    own = settings.copy()
    for i in range(r.size):
        solve_point(A[i], r[i], bk[i], bs[i], zeta[i], c[i], own, out[i])
        regime = out[i, OUT_REGIME]
        # a float slot against the codes' values: numba casts no IntEnum to float
        if regime == Regime.UNBOUNDED.value or regime == Regime.UNSETTLED.value:
            own[SET_Q0] = settings[SET_Q0]
            own[SET_V0] = settings[SET_V0]
        else:
            own[SET_Q0] = out[i, OUT_Q]
            own[SET_V0] = out[i, OUT_V]
