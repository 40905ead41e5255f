"""Steady state of one grid point with a Jenkins contact (effect contact_stiffness): march, shoot, measure.

The driver of steady.py for the state (q, v, w) of kernels/jenkins.py, kept apart so that a point without
the effect runs exactly the code it always ran. On the section (the excitation's maximum) a slipping
slider sits where the slip puts it, w = q - sig bk / kappa, so Newton moves (q, v) there and (q, v, w)
where the slider is stuck. The Jacobian is jenkins.py's exact 3 x 3 monodromy matrix M of P^k where it
is valid (restricted to (q, v) where the slider slips at the section: M's column of w is zero there, so
its eigenvalues are those of the 2 x 2 block and 0), forward differences of the period map elsewhere; the
largest |eigenvalue| of the converged orbit's is its `floquet_multiplier`.

Without damping a stuck slider dissipates nothing, so the stuck oscillator's free motion never dies out.
Where the start (or a state the march reaches after a period without slips) can never carry the contact
force across the band, forced and free motion together (_held_forever), the limit of vanishing damping is
the forced motion about the slider's place, q = kappa w/(1 + kappa) + A cos(r t)/(1 + kappa - r^2): the
point settles there, confirmed by one measured period, regime `stuck` (the slider never slips; the mass
vibrates on the contact spring). A start whose free motion reaches the band slips first, and with static
above kinetic friction those slips can leave the mass moving: the march decides. Points without friction
(beta = 0) are the rigid model's, solved by steady.solve_point.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels.jenkins import (
    JACC_JAC,
    JACC_JAC_OK,
    JACC_JUMP,
    JACC_SIZE,
    JACC_SLIPS,
    STUCK_HELD,
    advance_period_jenkins,
)
from friction_sweep.kernels.jenkins_rk4 import advance_period_jenkins_rk4, stick_substeps
from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_QMAX,
    ACC_SLIDE,
    ACC_STOPS,
    ACC_STUCK,
    ACC_TMAX,
    ACC_XMAX,
    ACC_XMIN,
    BUDGET,
    reset_accumulator,
)
from friction_sweep.kernels.period_map import MAP_ROUNDING, map_error
from friction_sweep.kernels.point import JenkinsPoint, Point
from friction_sweep.kernels.segments import TWO_PI
from friction_sweep.kernels.settings import (
    KERNEL_RK4,
    SET_INITIAL_DISPLACEMENT,
    SET_INITIAL_VELOCITY,
    SET_KERNEL,
    SET_MAX_ORBIT_PERIOD,
    SET_MAX_PERIODS,
    SET_SHOOT_AFTER,
    SET_SHOOT_EVERY,
    SET_STABILITY,
    SET_STEADY_TOL,
    SET_STEPS_PER_PERIOD,
    SET_STOP_TOL,
    SET_WORK_BUDGET,
)
from friction_sweep.kernels.steady import (
    FLOQUET_FD_STEP,
    OUT_END_MODE,
    OUT_END_Q,
    OUT_END_V,
    OUT_FRICTION_ENERGY,
    OUT_ORBIT_PERIOD,
    OUT_PEAK_PHASE,
    OUT_PEAK_TRANSMISSIBILITY,
    OUT_PERIODS,
    OUT_PHASE,
    OUT_REGIME,
    OUT_SIZE,
    OUT_STEADY_STATE,
    OUT_STOPS_PER_PERIOD,
    OUT_STUCK_FRACTION,
    OUT_TRANSMISSIBILITY,
    OUT_WORK,
    OUTPUT_FIELDS,
    RHO_HISTORY,
    RUNAWAY,
    _growing,
    lag_degrees,
    solve_point,
)
from friction_sweep.ties import TIE_RTOL

#: what solve_point_jenkins writes for a point: steady.py's slots, then these
JENKINS_OUTPUT_FIELDS = (
    *OUTPUT_FIELDS,
    "slips_per_period",  # slips of the slider per forcing period (NaN without friction)
    "end_w",  # the slider's position where the march ended
)
JOUT = {name: i for i, name in enumerate(JENKINS_OUTPUT_FIELDS)}
JOUT_SIZE = len(JENKINS_OUTPUT_FIELDS)
JOUT_SLIPS = JOUT["slips_per_period"]
JOUT_END_W = JOUT["end_w"]
JOUT_FLOQUET = JOUT["floquet_multiplier"]  # steady.py's slot

#: evaluations of the period map a shooting solve may take (finite differences aside)
NEWTON_ITERATIONS = 30
#: forward-difference step, relative to the orbit's size
FD_STEP = 1e-7


@jit_inline
def _monodromy(acc):
    """The monodromy matrix d(q, v, w)(end)/d(q, v, w)(start) in acc's JACC_JAC slots, as a 3 x 3 array."""
    return acc[JACC_JAC:JACC_JAC + 9].copy().reshape((3, 3))


@jit_inline
def _advance(q, v, w, mode, anchor, p, settings, budget, measure, acc, rk4):
    """One period with the integrator `rk4` chooses (a compile-time switch, as period_map.advance)."""
    if rk4 is None:
        return advance_period_jenkins(q, v, w, mode, anchor, p, settings[SET_STOP_TOL], budget, measure, acc,
                                      None, None, None)
    return advance_period_jenkins_rk4(q, v, w, mode, anchor, p, int(settings[SET_STEPS_PER_PERIOD]), budget,
                                      measure, acc)


@jit_inline
def _map_error(p, settings):
    """period_map.map_error for the Jenkins kernels: for RK4 also the stick's truncation over a period, in the
    stuck oscillator's time (frequency Omega = sqrt(1 + kappa), step Omega h / m, jenkins_rk4.stick_substeps):
    T Omega (Omega h / m)^4 / 120."""
    error = map_error(p.r, settings)
    if settings[SET_KERNEL] == KERNEL_RK4:
        om = math.sqrt(1.0 + p.kappa)
        hs = om * TWO_PI / (p.r * settings[SET_STEPS_PER_PERIOD] * stick_substeps(p.kappa))
        error = max(error, om * TWO_PI / p.r * hs ** 4 / 120.0)
    return error


@jit_inline
def _period(q, v, w, mode, anchor, p, settings, budget, measure, acc, rk4):
    reset_accumulator(acc)
    return _advance(q, v, w, mode, anchor, p, settings, budget, measure, acc, rk4)


@jit_inline
def _map_k(q, v, w, mode, anchor, k, p, settings, budget, measure, acc, rk4):
    """P^k from (q, v, w, mode, anchor), measured together in acc if asked, with P^k's monodromy matrix (the
    product of the periods') in acc's JACC_JAC slots. Returns (q, v, w, mode, anchor, status, work)."""
    reset_accumulator(acc)
    work = 0
    chain = np.eye(3) if k > 1 else np.empty((0, 0))
    chain_ok = True
    for _ in range(k):
        q, v, w, mode, anchor, st, wk = _advance(q, v, w, mode, anchor, p, settings, budget - work, measure, acc, rk4)
        work += wk
        if st != 0:
            return q, v, w, mode, anchor, st, work
        if k > 1:
            chain = _monodromy(acc) @ chain
            chain_ok = chain_ok and acc[JACC_JAC_OK] == 1.0
    if k > 1:
        acc[JACC_JAC:JACC_JAC + 9] = chain.ravel()
        acc[JACC_JAC_OK] = 1.0 if chain_ok else 0.0
    return q, v, w, mode, anchor, 0, work


@jit_inline
def _slipping(mode):
    return mode == 1 or mode == -1


@jit_inline
def _same_kind(m1, m2):
    """Two modes of one orbit point: the same slip direction, or both stuck (held or not)."""
    return m1 == m2 or (not _slipping(m1) and not _slipping(m2))


@jit
def _jacobian(q, v, w, mode, anchor, k, q1, v1, w1, p, settings, budget, acc, rk4):
    """Forward differences of P^k at (q, v, w) (P^k = (q1, v1, w1) there) in the coordinates Newton moves:
    (q, v) with the slider following where it slips, else (q, v, w). Returns (J, dim, ok, work)."""
    dim = 2 if _slipping(mode) else 3
    jac = np.zeros((3, 3))
    scale = max(math.hypot(q, v), acc[ACC_QMAX], 1e-300)
    h = FD_STEP * max(scale, p.A)
    work = 0
    base = np.array([q, v, w])
    end = np.array([q1, v1, w1])
    for j in range(dim):
        x = base.copy()
        x[j] += h
        if dim == 2:
            x[2] = x[0] - mode * p.bk / p.kappa
        qa, va, wa, ma, _, st, wk = _map_k(x[0], x[1], x[2], mode, anchor, k, p, settings, budget - work, False,
                                           acc, rk4)
        work += wk
        if st != 0 or not _same_kind(ma, mode):
            return jac, dim, False, work
        jac[0, j] = (qa - end[0]) / h
        jac[1, j] = (va - end[1]) / h
        jac[2, j] = (wa - end[2]) / h
    return jac, dim, True, work


@jit
def _radius(jac, dim):
    """Largest |eigenvalue| of the leading dim x dim block; NaN where it is not finite (eigvals would raise)."""
    block = jac[:dim, :dim]
    if not np.all(np.isfinite(block)):
        return math.nan
    ev = np.linalg.eigvals(block.astype(np.complex128))
    return np.max(np.abs(ev))


@jit
def _central_radius(q, v, w, mode, anchor, k, p, settings, budget, size, rk4):
    """The largest |multiplier| of P^k at the orbit's state by central differences (the rk4 kernel, which
    builds no monodromy matrix), in Newton's coordinates (_jacobian), step steady.FLOQUET_FD_STEP of the
    larger of the orbit and the forcing. Returns (radius, periods, work); NaN where a perturbed start
    fails or changes mode."""
    dim = 2 if _slipping(mode) else 3
    jac = np.zeros((3, 3))
    h = FLOQUET_FD_STEP * max(size, p.A)
    acc = np.empty(JACC_SIZE)
    work = 0
    periods = 0
    base = np.array([q, v, w])
    for j in range(dim):
        for sign in (1.0, -1.0):
            x = base.copy()
            x[j] += sign * h
            if dim == 2:
                x[2] = x[0] - mode * p.bk / p.kappa
            qa, va, wa, ma, _, st, wk = _map_k(x[0], x[1], x[2], mode, anchor, k, p, settings, budget - work, False,
                                               acc, rk4)
            work += wk
            periods += k
            if st != 0 or not _same_kind(ma, mode):
                return math.nan, periods, work
            jac[0, j] += sign * qa / (2.0 * h)
            jac[1, j] += sign * va / (2.0 * h)
            jac[2, j] += sign * wa / (2.0 * h)
    return _radius(jac, dim), periods, work


@jit
def shoot_jenkins(q, v, w, mode, anchor, k, p, settings, tol, budget, acc, rk4):
    """Newton on P^k(x) = x from (q, v, w, mode) (anchor: jenkins.py's label, kept), with P^k's exact
    monodromy matrix where the map is smooth there, forward differences elsewhere. Returns (q, v, w, mode,
    ok, work, periods); on success acc holds the measurement of the k periods from the returned state. A
    solution counts only if it attracts: the largest |multiplier| of the exact matrix there (of the last
    Jacobian where that is not valid) below 1."""
    work = 0
    periods = 0
    last_step = math.inf
    radius = math.nan
    size = max(math.hypot(q, v), 1e-300)
    for _ in range(NEWTON_ITERATIONS):
        if _slipping(mode):
            w = q - mode * p.bk / p.kappa
        q1, v1, w1, m1, _, st, wk = _map_k(q, v, w, mode, anchor, k, p, settings, budget - work, False, acc, rk4)
        work += wk
        periods += k
        if st != 0 or not _same_kind(m1, mode) or not (math.isfinite(q1) and math.isfinite(v1)):
            return q, v, w, mode, False, work, periods
        size = max(size, acc[ACC_QMAX])
        scale = max(math.hypot(q, v), size)
        noise = MAP_ROUNDING * max(scale, p.A)
        res = abs(q1 - q) + abs(v1 - v) + (0.0 if _slipping(mode) else abs(w1 - w))
        if res <= tol * scale + noise and last_step <= 1e-8 * scale + noise:
            # converged: measure the k periods from here, with the creep anchor the orbit itself carries
            # across the section (one unmeasured pass), not the one the march had where shooting began:
            # the labels of a slip begun before t = 0 depend on it
            _, _, _, _, anchor, st, wk = _map_k(q, v, w, mode, anchor, k, p, settings, budget - work, False, acc, rk4)
            work += wk
            periods += k
            if st != 0:
                return q, v, w, mode, False, work, periods
            _, _, _, _, _, st, wk = _map_k(q, v, w, mode, anchor, k, p, settings, budget - work, True, acc, rk4)
            work += wk
            periods += k
            if st == 0 and acc[JACC_JAC_OK] == 1.0:
                radius = _radius(_monodromy(acc), 2 if _slipping(mode) else 3)
            ok = st == 0 and radius < 1.0
            return q, v, w, mode, ok, work, periods
        if acc[JACC_JAC_OK] == 1.0:
            jac = _monodromy(acc)
            dim = 2 if _slipping(mode) else 3
        else:
            jac, dim, ok, wk = _jacobian(q, v, w, mode, anchor, k, q1, v1, w1, p, settings, budget - work, acc, rk4)
            work += wk
            periods += dim * k
            if not ok:
                return q, v, w, mode, False, work, periods
        radius = _radius(jac, dim)
        b = jac[:dim, :dim] - np.eye(dim)
        f = np.array([q1 - q, v1 - v, w1 - w])[:dim]
        if not np.all(np.isfinite(b)) or abs(np.linalg.det(b)) == 0.0:
            return q, v, w, mode, False, work, periods
        dx = -np.linalg.solve(b, f)
        step = np.sum(np.abs(dx))
        # the map is only piecewise smooth: a step longer than the motion leaves the piece that proposed it
        reach = max(scale, p.A)
        if step > reach:
            dx *= reach / step
            step = reach
        q += dx[0]
        v += dx[1]
        if dim == 3:
            w += dx[2]
        last_step = step
        if not (math.isfinite(q) and math.isfinite(v) and math.isfinite(w)):
            return q, v, w, mode, False, work, periods
    return q, v, w, mode, False, work, periods


#: a repeat at lag k > 1 is a period-k orbit only where every proper divisor d of k moves the state by more
#: than this many times the repeat's bound (the structure engine's _DISTINCT rule)
DISTINCT = 1e3


@jit_inline
def _lag_gap(q, v, w, n, hq, hv, hw, kmax, k, size):
    """How far the state is from the one k periods back, and the scale it is judged against."""
    j = (n - k) % (kmax + 1)
    return abs(q - hq[j]) + abs(v - hv[j]) + abs(w - hw[j]), max(size, math.hypot(hq[j], hv[j]))


@jit_inline
def _repeat_lag(q, v, w, mode, n, hq, hv, hw, hm, kmax, tol, size, floor):
    """The smallest k <= kmax at which the state repeats the one k periods back (0 if none). A repeat at lag
    k > 1 where a proper divisor d of k moves the state by less than DISTINCT x the bound is no period-k orbit
    but a decaying transient whose free motion nearly returns after k periods (a stuck slider's oscillator at
    close to a multiple of 1/k of the forcing frequency: kappa 10, zeta 0.05, beta 1.5, r 2 repeated at lag 3
    while P moved the state by a few steady_tol): 0, the march goes on until the period-d orbit repeats."""
    for k in range(1, min(kmax, n) + 1):
        j = (n - k) % (kmax + 1)
        gap, scale = _lag_gap(q, v, w, n, hq, hv, hw, kmax, k, size)
        if gap <= tol * scale + floor and _same_kind(hm[j], mode):
            for d in range(1, k):
                if k % d == 0:
                    near, dscale = _lag_gap(q, v, w, n, hq, hv, hw, kmax, d, size)
                    if near <= DISTINCT * (tol * dscale + floor):
                        return 0
            return k
    return 0


@jit_inline
def _resting_slider(q0, p):
    """Where the slider sits at the start from rest: the contact spring holds the mass at q0 against the
    forcing at the section, kappa (q0 - w) = A - q0, as the rigid contact holds a mass at rest; where that
    needs more than the static friction, at the band's edge (the mass then slips at once, as the rigid one
    does). A relaxed spring instead (w = q0) would let the suddenly applied force swing the mass by twice its
    static deflection, carrying the contact force to about 2 A whatever kappa, so that from rest the
    contact would not approach the rigid model (A < beta_s < 2 A: the rigid mass stays, the contact slips)."""
    hold = p.bs * (1.0 - TIE_RTOL)  # inside the band: a start on its edge is a tie the stick cannot leave
    return q0 - max(-hold, min(hold, p.A - q0)) / p.kappa


@jit_inline
def _held_forever(q, v, w, p):
    """Whether the undamped stuck slider at w, the mass at (q, v) at the section, settles without slipping
    in the limit of vanishing damping, and the forced orbit it then settles on: returns (held, q, w) of
    that orbit at the section (at rest there: the excitation's maximum).

    Stuck, q = K + F cos(r t) + C cos(Omega t) + D sin(Omega t) with K = kappa w / Omega^2 (the rest
    position), F = A / (Omega^2 - r^2), C = q - K - F, D = v / Omega. Vanishing damping removes the free
    part; before it does, the contact force kappa (q - w) comes arbitrarily close to |kappa (K - w)| +
    kappa |F| + kappa hypot(C, D) (r and Omega are incommensurate but on a set of measure zero). With static
    above kinetic friction, a free part that carries the force across the band slips first, and those slips
    can leave the mass moving: not held, the march decides. With static equal to kinetic friction the
    steady state is the same from every start, so only the forced orbit matters: held where it stays
    inside the band about the relaxed slider, kappa |F| < beta (the free part's slips shave it off ever
    more finely: a march would approach that orbit without reaching it)."""
    om2 = 1.0 + p.kappa
    detuning = (math.sqrt(om2) - p.r) * (math.sqrt(om2) + p.r)
    if p.zeta != 0.0 or detuning == 0.0:
        return False, math.nan, w
    F = p.A / detuning
    if p.bs <= p.bk:
        return p.kappa * abs(F) < p.bs * (1.0 - TIE_RTOL), F, 0.0
    K = p.kappa * w / om2
    reach = p.kappa * (abs(K - w) + abs(F) + math.hypot(q - K - F, v / math.sqrt(om2)))
    return reach < p.bs * (1.0 - TIE_RTOL), K + F, w


@jit
def _march(q, v, w, mode, anchor, p, settings, work, acc, rk4):
    """March the period map until it repeats (period k), a shooting solve lands on the orbit, the motion
    grows without bound (next to r = 1 below pi/4, steady.py's test), or the periods or the work run out.
    Returns (q, v, w, mode, anchor, status, orbit, periods, work, shot)."""
    tol = settings[SET_STEADY_TOL]
    max_periods = int(settings[SET_MAX_PERIODS])
    kmax = int(settings[SET_MAX_ORBIT_PERIOD])
    budget = int(settings[SET_WORK_BUDGET])
    shoot_every = int(settings[SET_SHOOT_EVERY])
    hq = np.empty(kmax + 1)
    hv = np.empty(kmax + 1)
    hw = np.empty(kmax + 1)
    hm = np.empty(kmax + 1, dtype=np.int64)
    rho_hist = np.empty(RHO_HISTORY)
    hq[0], hv[0], hw[0], hm[0] = q, v, w, mode
    n = 0
    periods = 0
    # shoot from the second period on (the first leaves the start), and again every shoot_every periods
    next_shot = max(2, int(settings[SET_SHOOT_AFTER]))
    while n < max_periods:
        n += 1
        periods += 1
        q, v, w, mode, anchor, st, wk = _period(q, v, w, mode, anchor, p, settings, budget - work, False, acc, rk4)
        work += wk
        if st == BUDGET or work > budget:
            return q, v, w, mode, anchor, SteadyState.EVENT_BUDGET, 0, periods, work, False
        if not (math.isfinite(q) and math.isfinite(v) and math.isfinite(w)):
            return q, v, w, mode, anchor, SteadyState.NONFINITE, 0, periods, work, False
        rho = math.hypot(q, v)
        rho_hist[n % RHO_HISTORY] = rho
        size = max(rho, acc[ACC_QMAX])
        if rho > RUNAWAY * max(p.A, 1.0):
            return q, v, w, mode, anchor, SteadyState.GROWING, 0, periods, work, False
        floor = MAP_ROUNDING * max(size, p.A) if n > shoot_every else 0.0
        orbit = _repeat_lag(q, v, w, mode, n, hq, hv, hw, hm, kmax, tol, size, floor)
        if orbit > 0:
            return q, v, w, mode, anchor, SteadyState.CONVERGED, orbit, periods, work, False
        if acc[JACC_SLIPS] == 0.0 and not _slipping(mode):
            # undamped and stuck for good: the forced orbit about the slider's place (_held_forever)
            held, qf, wf = _held_forever(q, v, w, p)
            if held:
                return qf, 0.0, wf, STUCK_HELD, anchor, SteadyState.CONVERGED, 1, periods, work, False
        i = n % (kmax + 1)
        hq[i], hv[i], hw[i], hm[i] = q, v, w, mode
        # shooting needs a period in which the slider slipped: a stuck slider's position is a neutral
        # direction of the map (multiplier 1), and there the march settles by itself
        if n >= next_shot and acc[JACC_SLIPS] > 0.0:
            qs, vs, ws, ms, ok, wk, k = shoot_jenkins(q, v, w, mode, anchor, 1, p, settings, tol, budget - work,
                                                      acc, rk4)
            work += wk
            periods += k
            next_shot = n + shoot_every
            if ok:
                return qs, vs, ws, ms, anchor, SteadyState.CONVERGED, 1, periods, work, True
        if _growing(rho_hist, n, p):
            return q, v, w, mode, anchor, SteadyState.GROWING, 0, periods, work, False
    return q, v, w, mode, anchor, SteadyState.PERIOD_CAP, 0, periods, work, False


@jit_inline
def _record(out, acc, orbit, p):
    """The outputs of the orbit measured in acc over `orbit` periods (steady._record_measurement's, with
    the Jenkins labels: `stuck` where the slider never slips)."""
    r, c = p.r, p.c
    total = orbit * (TWO_PI / r)
    slips = acc[JACC_SLIPS]
    all_stuck = slips == 0.0
    a1 = r / math.pi * acc[ACC_IC] / orbit + c
    b1 = r / math.pi * acc[ACC_IS] / orbit
    amp = math.hypot(a1, b1)
    out[OUT_TRANSMISSIBILITY] = amp
    out[OUT_PEAK_TRANSMISSIBILITY] = max(acc[ACC_XMAX], -acc[ACC_XMIN])
    if amp > 0.0:
        out[OUT_PHASE] = lag_degrees(math.atan2(b1, a1))
    if out[OUT_PEAK_TRANSMISSIBILITY] > 0.0:
        out[OUT_PEAK_PHASE] = lag_degrees(r * acc[ACC_TMAX])
    out[OUT_STOPS_PER_PERIOD] = 0.0 if all_stuck else acc[ACC_STOPS] / orbit
    out[OUT_STUCK_FRACTION] = 1.0 if all_stuck else acc[ACC_STUCK] / total
    out[OUT_FRICTION_ENERGY] = 0.0 if all_stuck else (p.bk * acc[ACC_SLIDE] + acc[JACC_JUMP]) / orbit
    out[OUT_ORBIT_PERIOD] = orbit
    out[JOUT_SLIPS] = slips / orbit
    if all_stuck:
        out[OUT_REGIME] = Regime.STUCK.value
    elif acc[ACC_STOPS] > 0.0:
        out[OUT_REGIME] = Regime.STICK_SLIP.value
    else:
        out[OUT_REGIME] = Regime.CONTINUOUS.value


@jit
def solve_point_jenkins(p, settings, start_w, start_mode, out, rk4):
    """Steady state and measurements of one grid point with a Jenkins contact; results in `out` (slots of
    JENKINS_OUTPUT_FIELDS). The march starts from the settings' (q, v) with the slider at start_w in mode
    start_mode (NaN and 0: at rest on a relaxed contact spring, w = q; a sweep's or a second start's state
    is a settled orbit's, w and mode consistent with it)."""
    out[:] = math.nan
    if p.bk == 0.0 and p.bs == 0.0:
        # no friction, no contact force: the rigid model's point, exactly
        solve_point(Point(p.A, p.r, 0.0, 0.0, p.zeta, p.c), settings, math.nan, math.nan, out[:OUT_SIZE], rk4)
        return
    acc = np.empty(JACC_SIZE)
    budget = int(settings[SET_WORK_BUDGET])
    q0 = settings[SET_INITIAL_DISPLACEMENT]
    q, v, w, mode = q0, settings[SET_INITIAL_VELOCITY], _resting_slider(q0, p) if math.isnan(start_w) else start_w, \
        start_mode
    anchor = math.nan
    status = SteadyState.PERIOD_CAP
    orbit = 0
    work = 0
    periods = 0
    shot = False
    held, qf, wf = _held_forever(q, v, w, p) if not _slipping(mode) or p.bs <= p.bk else (False, math.nan, w)
    if held:
        # the start settles without slipping: the forced orbit about the slider's place, confirmed by a period
        q1, v1, w1, m1, _, st, work = _map_k(qf, 0.0, wf, STUCK_HELD, math.nan, 1, p, settings, budget, True, acc, rk4)
        periods = 1
        if st == 0 and acc[JACC_SLIPS] == 0.0 and abs(q1 - qf) + abs(v1) <= settings[SET_STEADY_TOL] * abs(qf) + \
                _map_error(p, settings) * max(abs(qf), p.A):
            q, v, w, mode, status, orbit, shot = qf, 0.0, wf, STUCK_HELD, SteadyState.CONVERGED, 1, True
    if status != SteadyState.CONVERGED:
        q, v, w, mode, anchor, status, orbit, marched, work, shot = _march(q, v, w, mode, anchor, p, settings, work,
                                                                           acc, rk4)
        periods += marched
    out[OUT_PERIODS] = periods
    out[OUT_STEADY_STATE] = status.value
    out[OUT_WORK] = work
    out[OUT_END_Q], out[OUT_END_V], out[OUT_END_MODE] = q, v, mode
    out[JOUT_END_W] = w
    if status == SteadyState.GROWING:
        out[OUT_REGIME] = Regime.UNBOUNDED.value
        return
    if status != SteadyState.CONVERGED:
        out[OUT_REGIME] = Regime.UNSETTLED.value
        return
    if not shot:
        q1, v1, w1, m1, _, st, wk = _map_k(q, v, w, mode, anchor, orbit, p, settings, budget - work, True, acc, rk4)
        work += wk
        out[OUT_WORK] = work
        out[OUT_PERIODS] = periods + orbit
        if st != 0:
            out[OUT_STEADY_STATE] = SteadyState.EVENT_BUDGET.value
            out[OUT_REGIME] = Regime.UNSETTLED.value
            return
    _record(out, acc, orbit, p)
    # the orbit's multipliers (steady._floquet's rules): where the slider never slips its position is neutral
    # (multiplier 1 of a continuum), undefined; the event kernel's exact matrix of the measured periods, NaN
    # where the map is not smooth at the orbit; central differences for rk4
    if settings[SET_STABILITY] != 0.0 and acc[JACC_SLIPS] > 0.0:
        if rk4 is None:
            radius = _radius(_monodromy(acc), 2 if _slipping(mode) else 3) if acc[JACC_JAC_OK] == 1.0 else math.nan
        else:
            radius, k, wk = _central_radius(q, v, w, mode, anchor, orbit, p, settings, budget - int(out[OUT_WORK]),
                                            max(math.hypot(q, v), acc[ACC_QMAX]), rk4)
            out[OUT_PERIODS] += k
            out[OUT_WORK] += wk
        out[JOUT_FLOQUET] = radius


@jit
def solve_points_jenkins(A, r, bk, bs, zeta, c, kappa, settings, out, rk4):
    """solve_point_jenkins over 1-D arrays of points from the settings' start; out has shape (n, JOUT_SIZE).
    rk4: the integrator, kernels.period_map.integrator(settings) (compile-time: None, the event kernel)."""
    for i in range(r.size):
        solve_point_jenkins(JenkinsPoint(A[i], r[i], bk[i], bs[i], zeta[i], c[i], kappa[i]), settings, math.nan, 0,
                            out[i], rk4)


@jit
def solve_points_jenkins_from(A, r, bk, bs, zeta, c, kappa, settings, q0, v0, w0, m0, out, rk4):
    """solve_points_jenkins with a start (q0[i], v0[i], w0[i], m0[i]) of its own for each point (at the
    excitation's maximum): the second, moving start where static friction exceeds kinetic."""
    own = settings.copy()
    for i in range(r.size):
        own[SET_INITIAL_DISPLACEMENT] = q0[i]
        own[SET_INITIAL_VELOCITY] = v0[i]
        solve_point_jenkins(JenkinsPoint(A[i], r[i], bk[i], bs[i], zeta[i], c[i], kappa[i]), own, w0[i],
                            int(m0[i]), out[i], rk4)


@jit
def solve_sweep_jenkins(A, r, bk, bs, zeta, c, kappa, settings, out, rk4):
    """A stepped-sine sweep over the points in the order given (steady.solve_sweep's rule): each point starts
    from the state (q, v, w, mode) at the excitation's maximum of the orbit the previous one settled on;
    the first, and any after a point with no steady state, from the settings' start."""
    own = settings.copy()
    w0 = math.nan
    m0 = 0
    for i in range(r.size):
        solve_point_jenkins(JenkinsPoint(A[i], r[i], bk[i], bs[i], zeta[i], c[i], kappa[i]), own, w0, m0, out[i], rk4)
        regime = out[i, OUT_REGIME]
        if regime == Regime.UNBOUNDED.value or regime == Regime.UNSETTLED.value or math.isnan(out[i, JOUT_END_W]):
            own[SET_INITIAL_DISPLACEMENT] = settings[SET_INITIAL_DISPLACEMENT]
            own[SET_INITIAL_VELOCITY] = settings[SET_INITIAL_VELOCITY]
            w0, m0 = math.nan, 0
        else:
            own[SET_INITIAL_DISPLACEMENT] = out[i, OUT_END_Q]
            own[SET_INITIAL_VELOCITY] = out[i, OUT_END_V]
            w0, m0 = out[i, JOUT_END_W], int(out[i, OUT_END_MODE])


@jit
def sample_orbit_jenkins(q, v, w, mode, p, vtol, budget, periods, ts, sq, sv, sw=None):
    """Replay `periods` forcing periods from a state (q, v, w, mode) on the orbit, sampling q, v at the local
    times ts (sorted, in [0, T)) of every period; sq, sv have shape (periods, ts.size). Returns BUDGET if the
    replay ran out of `budget` (the samples are then incomplete), else 0 (steady.sample_orbit's contract).
    sw: None (left out: not compiled), or where the slider's position at the samples goes, sq's shape."""
    acc = np.empty(JACC_SIZE)
    anchor = math.nan  # labels only: the motion does not depend on it
    work = 0
    for k in range(periods):
        reset_accumulator(acc)
        if sw is None:
            q, v, w, mode, anchor, st, wk = advance_period_jenkins(q, v, w, mode, anchor, p, vtol, budget - work,
                                                                   False, acc, ts, sq[k], sv[k])
        else:
            q, v, w, mode, anchor, st, wk = advance_period_jenkins(q, v, w, mode, anchor, p, vtol, budget - work,
                                                                   False, acc, ts, sq[k], sv[k], None, sw[k])
        work += wk
        if st == BUDGET or work > budget:
            return BUDGET
    return 0
