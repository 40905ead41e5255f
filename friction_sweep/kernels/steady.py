"""Steady state of one grid point: march the period map, shoot, recognise growth, measure.

Where the steady state is unique (_unique), solve_point first solves P(x) = x by Newton shooting
(shoot.py) from a guess the method passes (Den Hartog's orbit): one measured period settles a
continuous point. Otherwise, or where that fails, it marches forcing periods of the period map P
(period_map.py) from the settings' start until P^k repeats (period 1 or k), shooting from the first
smooth period (through sticks where the steady state is unique) and again every shoot_every periods,
recognises steady linear growth (resonance below pi/4) and then measures over the k periods of the
orbit. Everything is recorded as numbers and codes in one float row per point, whose slots are named
in OUTPUT_FIELDS (the cube's variable names where the row holds one). A point's parameters travel as
one kernels.point.Point; solve_points and its variants build it from the parameter arrays the methods
pass.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels.balance import balanced
from friction_sweep.kernels.event import advance_period
from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_JAC,
    ACC_JAC_OK,
    ACC_QHI,
    ACC_QLO,
    ACC_QMAX,
    ACC_SIZE,
    ACC_SLIDE,
    ACC_STOPS,
    ACC_STUCK,
    ACC_TMAX,
    ACC_XMAX,
    ACC_XMIN,
    BUDGET,
    reset_accumulator,
)
from friction_sweep.kernels.period_map import advance, map_error, map_k, mode_of, period
from friction_sweep.kernels.point import Point
from friction_sweep.kernels.segments import TWO_PI
from friction_sweep.kernels.settings import (
    SET_INITIAL_DISPLACEMENT,
    SET_INITIAL_VELOCITY,
    SET_MAX_ORBIT_PERIOD,
    SET_MAX_PERIODS,
    SET_SHOOT_AFTER,
    SET_SHOOT_EVERY,
    SET_STABILITY,
    SET_STEADY_TOL,
    SET_WORK_BUDGET,
)
from friction_sweep.kernels.shoot import FIRST_GIVEN, FIRST_MEASURED, FIRST_PLAIN, shoot, spectral_radius
from friction_sweep.kernels.stick import stuck_for_good
from friction_sweep.theory import phase
from friction_sweep.ties import RESONANCE_FRICTION_LIMIT, TIE_RTOL

#: what solve_point writes for a point, in slot order
OUTPUT_FIELDS = (
    "transmissibility", "peak_transmissibility", "phase", "peak_phase", "stops_per_period", "stuck_fraction",
    "regime", "periods", "steady_state", "orbit_period",
    "work",  # stop-search steps, RK4 steps and events spent
    "end_q", "end_v", "end_mode",  # where the march ended (on the orbit, or where it gave up): a seed
    "friction_energy",  # kinetic friction x sliding distance of q, per forcing period (docs/equations.md §6)
    "floquet_multiplier",  # largest |multiplier| of the orbit's period map P^k (setting stability only)
)
OUT = {name: i for i, name in enumerate(OUTPUT_FIELDS)}
OUT_SIZE = len(OUTPUT_FIELDS)
OUT_TRANSMISSIBILITY = OUT["transmissibility"]
OUT_PEAK_TRANSMISSIBILITY = OUT["peak_transmissibility"]
OUT_PHASE = OUT["phase"]
OUT_PEAK_PHASE = OUT["peak_phase"]
OUT_STOPS_PER_PERIOD = OUT["stops_per_period"]
OUT_STUCK_FRACTION = OUT["stuck_fraction"]
OUT_REGIME = OUT["regime"]
OUT_PERIODS = OUT["periods"]
OUT_STEADY_STATE = OUT["steady_state"]
OUT_ORBIT_PERIOD = OUT["orbit_period"]
OUT_WORK = OUT["work"]
OUT_END_Q = OUT["end_q"]
OUT_END_V = OUT["end_v"]
OUT_END_MODE = OUT["end_mode"]
OUT_FRICTION_ENERGY = OUT["friction_energy"]
OUT_FLOQUET = OUT["floquet_multiplier"]

#: the slots _record_measurement fills: NaN again where the orbit is refused (kernels/balance.py)
MEASURED_SLOTS = (OUT_TRANSMISSIBILITY, OUT_PEAK_TRANSMISSIBILITY, OUT_PHASE, OUT_PEAK_PHASE, OUT_STOPS_PER_PERIOD,
                  OUT_STUCK_FRACTION, OUT_FRICTION_ENERGY, OUT_ORBIT_PERIOD)

#: the phase convention of friction_sweep.theory.phase, compiled
wrap_degrees = jit_inline(phase.wrap_degrees)


@jit_inline
def lag_degrees(radians):
    """A lag in radians as degrees in [-90, 270). The conversion rounds twice, (x 180) / pi, where
    np.degrees multiplies by 180 / pi once; the two differ by an ulp in a quarter of the values, so each
    side keeps its own to keep its results (an ulp of 90 degrees is half of a phase near 0)."""
    return wrap_degrees(radians * 180.0 / math.pi)


# A march that found no period-k orbit (k <= max_orbit_period) is `aperiodic` when its largest
# Lyapunov exponent (per forcing period, over the march's second half) is above -1/max_orbit_period:
# nearby states draw together by less than a factor e over the longest period looked for, so the
# motion is chaotic (exponent > 0), quasi-periodic (~0) or locked onto a longer period (static
# friction at r = 0.33, beta = 0.08: 1222 periods, exponent -1.3e-3). A motion that contracts faster
# and still has not repeated is a transient the budget cut short: `period_cap`.
#: periods over which the exponent is averaged (the second half of the march, at least this many)
LYAPUNOV_PERIODS = 256
#: shooting through sticks accepts only an orbit within this fraction of the orbit's size from the march
STICK_SHOT_REACH = 0.05
#: at the period cap, a march whose state repeats at some lag k to this fraction of its size shoots for
#: the period-k orbit
LAG_SHOT = 1e-3
#: an aperiodic motion is measured as the average over this many forcing periods
APERIODIC_WINDOW = 256


#: a state |(q, v)| beyond this multiple of max(A, 1) has grown without bound, whatever the rate
RUNAWAY = 1e12
#: Steady linear growth is looked for only GROWTH_AFTER periods into the march, every
#: GROWTH_CHECK_EVERY periods, and only within GROWTH_DETUNING of r = 1 (|1 - r^2|)
GROWTH_AFTER = 128
GROWTH_CHECK_EVERY = 16
GROWTH_DETUNING = 1e-6
#: growth is GROWTH_WINDOW periods in which |(q, v)| rises every period, with the rise over the window's last
#: third at least GROWTH_KEPT of that over its first third (a rate that does not decay)
GROWTH_WINDOW = 48
GROWTH_KEPT = 0.9
#: |(q, v)| at the section is kept for this many periods (a ring; at least GROWTH_WINDOW + 1)
RHO_HISTORY = 64


@jit_inline
def _start(p, settings):
    """The state the march starts from: the settings' start, except where nothing dissipates.

    Without friction or damping a transient from any start would never decay, and the orbit would be
    forced plus free motion forever. The steady state meant is the forced one (the limit of vanishing
    damping): start on it, q = A/(1 - r^2), v = 0 at the excitation's maximum, whatever the given start.
    """
    if p.bk == 0.0 and p.bs == 0.0 and p.zeta == 0.0 and abs(1.0 - p.r) > TIE_RTOL:
        return p.A / ((1.0 - p.r) * (1.0 + p.r)), 0.0
    return settings[SET_INITIAL_DISPLACEMENT], settings[SET_INITIAL_VELOCITY]


@jit
def _subharmonic(r):
    """r = 1/(2n) to the tie tolerance (friction_sweep.ties.subharmonic_order)."""
    n = math.floor(0.5 / r + 0.5)
    return n >= 1.0 and abs(2.0 * n * r - 1.0) <= TIE_RTOL


@jit_inline
def _in_family(q, v, p):
    """Whether the point lies on a stick-free family: r = 1/(2n), static = kinetic friction, no damping.

    At r = 1/(2n) stick-free orbits form a continuum (docs/equations.md §6), so the map has no isolated fixed
    point to march to or shoot for. Its half-wave symmetric member is Den Hartog's, which at U(r) = 0
    starts from q = A/(1 - r^2), v = 0 at the excitation's maximum (_family_start); one exact, measured
    period confirms it (_returns_to_start). With static = kinetic friction the fixed points form one
    convex set, here the family, so this holds whatever the start (a swept start too), unless the start
    is held.
    """
    held = v == 0.0 and stuck_for_good(q, p.A, p.bs)
    return p.bk > 0.0 and p.bs == p.bk and p.zeta == 0.0 and not held and _subharmonic(p.r)


@jit_inline
def _family_start(p):
    """Den Hartog's member of the family: q = A/(1 - r^2) at rest, and the mode it starts in."""
    qf = p.A / ((1.0 - p.r) * (1.0 + p.r))
    return qf, mode_of(qf, 0.0, p)


@jit_inline
def _returns_to_start(qf, mf, q1, v1, st, p, settings, acc):
    """One period from (qf, 0) in mode mf, measured in `acc`, ended at (q1, v1) with status st: an orbit
    of the family if it moved, never stopped, and came back to its start within the steady tolerance
    (plus the map's own error)."""
    scale = max(abs(qf), acc[ACC_QMAX])
    return (st == 0 and mf != 0 and acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0
            and abs(q1 - qf) + abs(v1) <= settings[SET_STEADY_TOL] * scale + map_error(p.r, settings) * max(scale, p.A))


@jit_inline
def _repeat_lag(q, v, mode, n, hq, hv, hm, kmax, tol, size, floor):
    """The smallest k <= kmax at which the state repeats the one k periods back (0 if none): within
    tol of the orbit's size plus `floor`, in the same mode (or at rest on both sides of a decision tie)."""
    for k in range(1, min(kmax, n) + 1):
        j = (n - k) % (kmax + 1)
        scale = max(size, math.hypot(hq[j], hv[j]))
        near = abs(q - hq[j]) + abs(v - hv[j]) <= tol * scale + floor
        same = hm[j] == mode or (abs(v) <= tol * scale and abs(hv[j]) <= tol * scale)
        if near and same:
            return k
    return 0


@jit_inline
def _closest_lag(q, v, n, hq, hv, kmax):
    """The lag k (1 <= k < n, k <= kmax) at which the state comes closest to the one k periods back,
    and that distance (|dq| + |dv|)."""
    best = math.inf
    lag = 0
    for k in range(1, min(kmax, n - 1) + 1):
        j = (n - k) % (kmax + 1)
        d = abs(q - hq[j]) + abs(v - hv[j])
        if d < best:
            best, lag = d, k
    return lag, best


@jit_inline
def _may_grow(p):
    """Whether the motion can grow without bound: next to r = 1, without damping, with friction up to
    pi/4 of the force (a pure sinusoid pumps without bound only there, paper Eqs. 14-15)."""
    return (abs(1.0 - p.r) * (1.0 + p.r) < GROWTH_DETUNING and p.zeta == 0.0
            and p.bk <= RESONANCE_FRICTION_LIMIT * p.A * (1.0 + TIE_RTOL))


@jit_inline
def _growing(rho_hist, n, p):
    """Steady linear growth (resonance with friction below pi/4): GROWTH_WINDOW rising periods at a rate
    that does not decay, after shooting had its chances. Only next to r = 1, without damping and with
    friction up to pi/4 of the force: a pure sinusoid pumps without bound only there (paper Eqs.
    14-15), while Coulomb transients elsewhere also approach their (bounded) steady state at a
    constant rate, which must not be mistaken for growth."""
    if not (n >= GROWTH_AFTER and n % GROWTH_CHECK_EVERY == 0 and _may_grow(p)):
        return False
    for m in range(n - GROWTH_WINDOW + 1, n + 1):
        if rho_hist[m % RHO_HISTORY] <= rho_hist[(m - 1) % RHO_HISTORY]:
            return False
    third = GROWTH_WINDOW // 3
    d_old = rho_hist[(n - 2 * third) % RHO_HISTORY] - rho_hist[(n - 3 * third + 1) % RHO_HISTORY]
    d_new = rho_hist[n % RHO_HISTORY] - rho_hist[(n - third + 1) % RHO_HISTORY]
    return d_new >= GROWTH_KEPT * d_old


@jit_inline
def _unique(p):
    """Whether the point has one steady state whatever the start, so that Newton may start anywhere
    (and through sticks): something that dissipates; kinetic friction equal to static (the friction
    law is then monotone and the period map does not expand distances in the energy norm, so its fixed
    points form one convex set, and an attracting one is the only one); the force able to move the
    mass (no continuum of stuck states); and no resonance that can grow without bound (_may_grow: at
    r = 1, b = pi/4, the tie the tool calls unbounded (friction_sweep.ties), Newton finds a stick-slip
    orbit of amplitude 0.8)."""
    return ((p.bk > 0.0 or p.zeta > 0.0) and p.bs == p.bk and not stuck_for_good(0.0, p.A, p.bs)
            and not _may_grow(p))


@jit_inline
def _lyapunov_step(q, v, size, tracked, yq, yv, delta, log_growth, p):
    """Account for one period of the companion state that measures the largest Lyapunov exponent
    (Benettin: at relative distance 1e-7 from the march, renormalised along the current separation
    after every period; along q to start). (yq, yv): the companion after the period (unused on the
    first, tracked = 0). Returns the companion's next start (yq, yv, ym), delta and log_growth."""
    if tracked > 0:
        d = math.hypot(yq - q, yv - v)
        log_growth += math.log(d / delta) if d > 0.0 else -math.inf
    else:
        delta = 1e-7 * max(size, p.A)
        yq, yv = q, v
        d = 0.0
    if d > 0.0 and math.isfinite(d):
        yq = q + delta * (yq - q) / d
        yv = v + delta * (yv - v) / d
    else:
        yq = q + delta
        yv = v
    return yq, yv, mode_of(yq, yv, p), delta, log_growth


@jit_inline
def _march(q, v, mode, p, settings, work, acc, rk4):
    """March the period map from (q, v, mode) until it repeats, a shooting solve lands on the orbit, the
    motion grows without bound, or the periods or the work run out; at the cap, shoot for the orbit
    of the lag the march repeats best at, else tell an aperiodic motion from a cut-short transient.
    Returns (q, v, mode, status, orbit, periods, work, shot): periods every forcing period integrated
    (marched, shooting's evaluations, the Lyapunov companion's); shot when `acc` holds the orbit's
    measurement."""
    A, bk, bs = p.A, p.bk, p.bs
    tol = settings[SET_STEADY_TOL]
    max_periods = int(settings[SET_MAX_PERIODS])
    kmax = int(settings[SET_MAX_ORBIT_PERIOD])
    budget = int(settings[SET_WORK_BUDGET])
    shoot_every = int(settings[SET_SHOOT_EVERY])
    error = map_error(p.r, settings)
    hq = np.empty(kmax + 1)
    hv = np.empty(kmax + 1)
    hm = np.empty(kmax + 1, dtype=np.int64)
    rho_hist = np.empty(RHO_HISTORY)
    acc_y = np.empty(ACC_SIZE)
    hq[0], hv[0], hm[0] = q, v, mode
    n = 0
    periods = 0
    unique = _unique(p)
    # shoot at the first smooth period from shoot_after on (1 where it is 0: the guess had its shot before
    # the march), and again shoot_every periods after a miss
    next_shot = max(1, int(settings[SET_SHOOT_AFTER]))
    # the Lyapunov exponent is measured over the march's second half (only static friction can keep a
    # motion from settling: with bs == bk the period map does not expand distances)
    lyap_from = max(1, max_periods - max(LYAPUNOV_PERIODS, max_periods // 2))
    yq = yv = delta = log_growth = 0.0
    ym = 0
    tracked = 0
    while n < max_periods:
        n += 1
        periods += 1
        q0, v0 = q, v
        q, v, mode, st, w = period(q, v, mode, p, settings, budget - work, acc, rk4)
        work += w
        if st == BUDGET or work > budget:
            return q, v, mode, SteadyState.EVENT_BUDGET, 0, periods, work, False
        if not (math.isfinite(q) and math.isfinite(v)):
            return q, v, mode, SteadyState.NONFINITE, 0, periods, work, False
        rho = math.hypot(q, v)
        rho_hist[n % RHO_HISTORY] = rho
        # the orbit's size, not the state at the section, which may sit near (0, 0)
        size = max(rho, acc[ACC_QMAX])
        if rho > RUNAWAY * max(A, 1.0):
            return q, v, mode, SteadyState.GROWING, 0, periods, work, False
        # Once shooting has had its chance, a state that moves by no more than the map's own rounding
        # (relative to the forcing: a motion far smaller than A just below the no-motion threshold
        # jitters at ~1e-17) has settled as far as double precision can tell.
        floor = error * max(size, A) if n > shoot_every else 0.0
        orbit = _repeat_lag(q, v, mode, n, hq, hv, hm, kmax, tol, size, floor)
        if orbit > 0:
            return q, v, mode, SteadyState.CONVERGED, orbit, periods, work, False
        i = n % (kmax + 1)
        hq[i], hv[i], hm[i] = q, v, mode
        if bs > bk and n >= lyap_from:
            if tracked > 0:
                yq, yv, ym, _, w = period(yq, yv, ym, p, settings, budget - work, acc_y, rk4)
                work += w
                periods += 1
            yq, yv, ym, delta, log_growth = _lyapunov_step(q, v, size, tracked, yq, yv, delta, log_growth, p)
            tracked += 1
        # Shoot from a period over which the map is smooth: stop-free, or (event kernel) through sticks
        # where the period map has its exact Jacobian and the steady state is unique (_unique).
        no_stops = acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0
        smooth = no_stops or (acc[ACC_JAC_OK] == 1.0 and unique)
        # a march that still has not settled after shoot_every periods shoots through its sticks too
        if n >= next_shot and (smooth or n >= shoot_every):
            # Where the steady state is unique and the period just marched has the exact Jacobian, it is
            # Newton's first evaluation, from where it began; elsewhere Newton starts where the march is
            # (it lands on the orbit nearest its start, and the march from the settings' start decides
            # which of several that is).
            if unique and acc[ACC_JAC_OK] == 1.0:
                qs, vs, ok, w, k = shoot(q0, v0, 1, p, settings, tol, budget - work, acc, q, v, FIRST_GIVEN, rk4)
            else:
                qs, vs, ok, w, k = shoot(q, v, 1, p, settings, tol, budget - work, acc, 0.0, 0.0, FIRST_PLAIN, rk4)
            work += w
            periods += k
            next_shot = n + shoot_every
            # Where static friction exceeds kinetic, or the map is not smooth, Newton may land on another
            # orbit than the one the march approaches (static friction holds several): accept only an
            # orbit next to the march's state.
            if ok and not smooth:
                ok = math.hypot(qs - q, vs - v) <= STICK_SHOT_REACH * max(size, A)
            if ok:
                return qs, vs, mode_of(qs, vs, p), SteadyState.CONVERGED, 1, periods, work, True
        if _growing(rho_hist, n, p):
            return q, v, mode, SteadyState.GROWING, 0, periods, work, False
    if n >= 2:
        # Out of periods: a period-k orbit that the march approaches too slowly (static friction locks
        # onto long periods) is solved for directly, from the lag at which the march repeats best.
        lag, best = _closest_lag(q, v, n, hq, hv, kmax)
        if lag > 0 and best <= LAG_SHOT * max(math.hypot(q, v), acc[ACC_QMAX], A):
            qs, vs, ok, w, k = shoot(q, v, lag, p, settings, tol, budget - work, acc, 0.0, 0.0, FIRST_PLAIN, rk4)
            work += w
            periods += k
            if ok:
                return qs, vs, mode_of(qs, vs, p), SteadyState.CONVERGED, lag, periods, work, True
    # only static friction above kinetic can keep a motion from settling: with bs == bk the friction
    # law is monotone and the period map does not expand distances (README, "Where the physics gets
    # hard"), so there a motion that has not repeated is a transient the budget cut short
    if bs > bk and tracked > LYAPUNOV_PERIODS // 2 and log_growth > -(tracked - 1) / kmax:
        return q, v, mode, SteadyState.APERIODIC, APERIODIC_WINDOW, periods, work, False
    return q, v, mode, SteadyState.PERIOD_CAP, 0, periods, work, False


@jit_inline
def _measure_orbit(q, v, mode, orbit, p, settings, work, acc, rk4):
    """Measure the k = orbit periods from a state on the orbit into `acc`. Returns (work, done): not
    done when the point's work budget (which the measurement is part of) runs out."""
    budget = int(settings[SET_WORK_BUDGET])
    reset_accumulator(acc)
    for _ in range(orbit):
        q, v, mode, st, w = advance(q, v, mode, p, settings, budget - work, True, acc, rk4)
        work += w
        if st == BUDGET or work > budget:
            return work, False
    return work, True


@jit_inline
def _record_measurement(out, acc, orbit, p, tol):
    """The outputs of the orbit measured in `acc` over `orbit` periods from the state out[end_q]."""
    A, r, c = p.A, p.r, p.c
    q0 = out[OUT_END_Q]
    total = orbit * (TWO_PI / r)
    stuck_fraction = acc[ACC_STUCK] / total
    # No motion: stuck the whole time, or sticking and slipping by less than the steady-state
    # tolerance (a start beyond the edge of the stuck band creeps towards it, ever more slowly: the
    # limit is stuck at the edge, and the orbit accepted within tolerance moves by less than that)
    moved = max(acc[ACC_QHI], q0) - min(acc[ACC_QLO], q0)
    all_stuck = acc[ACC_STUCK] >= total * (1.0 - 1e-15) or (
        acc[ACC_STOPS] > 0.0 and moved <= tol * max(A, abs(q0)))
    ic = 0.0 if all_stuck else acc[ACC_IC]
    is_ = 0.0 if all_stuck else acc[ACC_IS]
    a1 = r / math.pi * ic / orbit + c  # the c cos(r t) part of x projects exactly onto (c, 0)
    b1 = r / math.pi * is_ / orbit
    amp = math.hypot(a1, b1)
    out[OUT_TRANSMISSIBILITY] = amp
    out[OUT_PEAK_TRANSMISSIBILITY] = max(acc[ACC_XMAX], -acc[ACC_XMIN])
    if amp > 0.0:
        out[OUT_PHASE] = lag_degrees(math.atan2(b1, a1))
    if out[OUT_PEAK_TRANSMISSIBILITY] > 0.0:
        out[OUT_PEAK_PHASE] = lag_degrees(r * acc[ACC_TMAX])
    out[OUT_STOPS_PER_PERIOD] = 0.0 if all_stuck else acc[ACC_STOPS] / orbit
    out[OUT_STUCK_FRACTION] = 1.0 if all_stuck else stuck_fraction
    # the energy friction dissipates per forcing period: bk times the distance q slides (a period-k
    # orbit's over its k periods, divided by k)
    out[OUT_FRICTION_ENERGY] = 0.0 if all_stuck else p.bk * acc[ACC_SLIDE] / orbit
    out[OUT_ORBIT_PERIOD] = orbit
    if all_stuck:
        out[OUT_REGIME] = Regime.STUCK.value
    elif acc[ACC_STOPS] > 0.0:
        out[OUT_REGIME] = Regime.STICK_SLIP.value
    else:
        out[OUT_REGIME] = Regime.CONTINUOUS.value


#: central-difference step of the Floquet multiplier where the integrator has no monodromy matrix (rk4),
#: relative to the orbit's size: the rk4 map is smooth between events to rounding, so the truncation
#: error (~FD_STEP^2) and the rounding (~1e-16 / FD_STEP) balance near here
FLOQUET_FD_STEP = 1e-5


@jit_inline
def _floquet(q, v, mode, orbit, p, settings, budget, acc, rk4):
    """The largest modulus among the multipliers of the period-k map P^k (k = orbit) at the orbit's state
    (q, v, mode), with `acc` holding the orbit's measurement (the monodromy matrix of its last period).
    Returns (multiplier, periods, work): the periods and work spent on it.

    Event kernel: the exact monodromy matrix (kernels/event.py, saltations included): for k = 1 the
    measured period's, free; for k > 1 the product of the k periods' matrices, replayed. NaN where the
    map is not smooth at the orbit (event.advance_period's jac_ok = 0: a stop that grazes, a stick that
    ends as it begins or where the force only touches the band, a period that starts held by static
    friction alone). RK4 kernel: central differences of P^k, 4 k periods. With a stick the matrix has
    rank 1 (a stop forgets the velocity): one multiplier is 0 and the other decides attraction.
    """
    if rk4 is None:
        if orbit == 1:
            if acc[ACC_JAC_OK] != 1.0:
                return math.nan, 0, 0
            return spectral_radius(acc[ACC_JAC], acc[ACC_JAC + 1], acc[ACC_JAC + 2], acc[ACC_JAC + 3]), 0, 0
        scratch = np.empty(ACC_SIZE)
        m11, m12, m21, m22 = 1.0, 0.0, 0.0, 1.0
        work = 0
        for i in range(orbit):
            reset_accumulator(scratch)
            q, v, mode, st, w = advance(q, v, mode, p, settings, budget - work, False, scratch, rk4)
            work += w
            if st != 0 or scratch[ACC_JAC_OK] != 1.0:
                return math.nan, i + 1, work
            j11, j12 = scratch[ACC_JAC], scratch[ACC_JAC + 1]
            j21, j22 = scratch[ACC_JAC + 2], scratch[ACC_JAC + 3]
            m11, m12, m21, m22 = (j11 * m11 + j12 * m21, j11 * m12 + j12 * m22,
                                  j21 * m11 + j22 * m21, j21 * m12 + j22 * m22)
        return spectral_radius(m11, m12, m21, m22), orbit, work
    scratch = np.empty(ACC_SIZE)
    h = FLOQUET_FD_STEP * max(math.hypot(q, v), acc[ACC_QMAX], 1e-300)
    cols = np.empty(8)  # P^k(q + h), P^k(q - h), P^k(v + h), P^k(v - h): (q, v) each
    work = 0
    for j in range(4):
        dq = h if j == 0 else (-h if j == 1 else 0.0)
        dv = h if j == 2 else (-h if j == 3 else 0.0)
        qa, va, st, w = map_k(q + dq, v + dv, orbit, p, settings, budget - work, False, scratch, rk4)
        work += w
        if st != 0:
            return math.nan, (j + 1) * orbit, work
        cols[2 * j], cols[2 * j + 1] = qa, va
    d = 2.0 * h
    return (spectral_radius((cols[0] - cols[2]) / d, (cols[4] - cols[6]) / d,
                            (cols[1] - cols[3]) / d, (cols[5] - cols[7]) / d), 4 * orbit, work)


@jit
def solve_point(p, settings, guess_q, guess_v, out, rk4):
    """Steady state and measurements of one grid point; results in `out` (slots of OUTPUT_FIELDS): the
    family's member, the orbit Newton finds from the guess (guess_q, guess_v) at the excitation's
    maximum (NaN: none) where the steady state is unique and shoot_after is 0, or the march's end from
    the settings' start; then the orbit's measurement."""
    out[:] = math.nan
    acc = np.empty(ACC_SIZE)
    q, v = _start(p, settings)
    mode = mode_of(q, v, p)
    status = SteadyState.PERIOD_CAP
    work = 0
    periods = 0  # every forcing period integrated for the point
    if _in_family(q, v, p):
        # Den Hartog's member of the family, confirmed (and measured) by one exact period
        qf, mf = _family_start(p)
        reset_accumulator(acc)
        q1, v1, _, st, work = advance(qf, 0.0, mf, p, settings, int(settings[SET_WORK_BUDGET]), True, acc, rk4)
        periods = 1
        if _returns_to_start(qf, mf, q1, v1, st, p, settings, acc):
            q, v, mode, status, orbit, shot = qf, 0.0, mf, SteadyState.FAMILY, 1, True
    elif settings[SET_SHOOT_AFTER] == 0 and math.isfinite(guess_q) and math.isfinite(guess_v) and _unique(p):
        reset_accumulator(acc)
        qs, vs, ok, work, periods = shoot(guess_q, guess_v, 1, p, settings, settings[SET_STEADY_TOL],
                                          int(settings[SET_WORK_BUDGET]), acc, 0.0, 0.0, FIRST_MEASURED, rk4)
        if ok:
            q, v, mode, status, orbit, shot = qs, vs, mode_of(qs, vs, p), SteadyState.CONVERGED, 1, True
    if status != SteadyState.FAMILY and status != SteadyState.CONVERGED:
        q, v, mode, status, orbit, marched, work, shot = _march(q, v, mode, p, settings, work, acc, rk4)
        periods += marched
    out[OUT_PERIODS] = periods
    out[OUT_STEADY_STATE] = status.value  # a float slot: numba casts no IntEnum to float
    out[OUT_WORK] = work
    out[OUT_END_Q], out[OUT_END_V], out[OUT_END_MODE] = q, v, mode
    if status == SteadyState.GROWING:
        out[OUT_REGIME] = Regime.UNBOUNDED.value
        return
    if status != SteadyState.CONVERGED and status != SteadyState.FAMILY and status != SteadyState.APERIODIC:
        out[OUT_REGIME] = Regime.UNSETTLED.value
        return
    # a shooting solve (or the family's check) measured its orbit already
    if not shot:
        work, done = _measure_orbit(q, v, mode, orbit, p, settings, work, acc, rk4)
        out[OUT_WORK] = work
        out[OUT_PERIODS] = periods + orbit
        if not done:
            out[OUT_STEADY_STATE] = SteadyState.EVENT_BUDGET.value
            out[OUT_REGIME] = Regime.UNSETTLED.value
            return
    _record_measurement(out, acc, orbit, p, settings[SET_STEADY_TOL])
    if (status != SteadyState.APERIODIC and out[OUT_REGIME] != Regime.STUCK.value
            and not balanced(acc, orbit, p, settings, q, v)):
        for slot in MEASURED_SLOTS:
            out[slot] = math.nan
        out[OUT_STEADY_STATE] = SteadyState.UNBALANCED.value
        out[OUT_REGIME] = Regime.UNSETTLED.value
        return
    # undefined on the family (a continuum: multiplier 1 along it) and at rest (a continuum of rest
    # positions); an aperiodic motion has no orbit
    if (settings[SET_STABILITY] != 0.0 and status == SteadyState.CONVERGED
            and out[OUT_REGIME] != Regime.STUCK.value):
        out[OUT_FLOQUET], k, w = _floquet(q, v, mode, orbit, p, settings,
                                          int(settings[SET_WORK_BUDGET]) - int(out[OUT_WORK]), acc, rk4)
        out[OUT_PERIODS] += k
        out[OUT_WORK] += w


@jit
def sample_orbit(q, v, mode, p, vtol, budget, periods, ts, sq, sv):
    """Replay `periods` forcing periods from a state on the orbit, sampling q, v at the local
    times ts (sorted, in [0, T)) of every period; sq, sv have shape (periods, ts.size). Returns
    BUDGET if the replay ran out of `budget` (the samples are then incomplete), else 0."""
    acc = np.empty(ACC_SIZE)
    work = 0
    for k in range(periods):
        reset_accumulator(acc)
        q, v, mode, st, w = advance_period(q, v, mode, p, vtol, budget - work, False, acc, ts, sq[k], sv[k])
        work += w
        if st == BUDGET or work > budget:
            return BUDGET
    return 0


@jit
def solve_points(A, r, bk, bs, zeta, c, settings, gq, gv, out, rk4):
    """solve_point over 1-D arrays of points, with guesses (gq[i], gv[i]); out has shape (n, OUT_SIZE). rk4:
    the integrator, period_map.integrator(settings) (a compile-time choice: None, the event kernel)."""
    for i in range(r.size):
        solve_point(Point(A[i], r[i], bk[i], bs[i], zeta[i], c[i]), settings, gq[i], gv[i], out[i], rk4)


@jit
def solve_points_from(A, r, bk, bs, zeta, c, settings, q0, v0, gq, gv, out, rk4):
    """solve_points with a start (q0[i], v0[i]) of its own for each point (at the excitation's maximum);
    where the steady state is unique the guess, if any, comes first (the start cannot matter there)."""
    own = settings.copy()
    for i in range(r.size):
        own[SET_INITIAL_DISPLACEMENT] = q0[i]
        own[SET_INITIAL_VELOCITY] = v0[i]
        solve_point(Point(A[i], r[i], bk[i], bs[i], zeta[i], c[i]), own, gq[i], gv[i], out[i], rk4)


@jit
def solve_sweep(A, r, bk, bs, zeta, c, settings, gq, gv, out, rk4):
    """A stepped-sine sweep over the points in the order given (one force ratio): each point starts
    from the state, at the excitation's maximum, of the orbit the previous point settled on, as a rig
    stepping its frequency does; the first from the settings' start. After a point with no steady
    state (unbounded, unsettled) the next starts afresh from the settings' start. Where the steady state
    is unique the guess, if any, comes first (the start cannot matter there)."""
    own = settings.copy()
    for i in range(r.size):
        solve_point(Point(A[i], r[i], bk[i], bs[i], zeta[i], c[i]), own, gq[i], gv[i], out[i], rk4)
        regime = out[i, OUT_REGIME]
        # a float slot against the codes' values: numba casts no IntEnum to float
        if regime == Regime.UNBOUNDED.value or regime == Regime.UNSETTLED.value:
            own[SET_INITIAL_DISPLACEMENT] = settings[SET_INITIAL_DISPLACEMENT]
            own[SET_INITIAL_VELOCITY] = settings[SET_INITIAL_VELOCITY]
        else:
            own[SET_INITIAL_DISPLACEMENT] = out[i, OUT_END_Q]
            own[SET_INITIAL_VELOCITY] = out[i, OUT_END_V]
