"""Steady state of one structure at one point: march the period map, shoot, measure (DESIGN §7).

From rest (model.rest_state: v = 0, every contact unstretched, the springs in equilibrium with the base
at y(0); each Jenkins slider loaded as its contact would be as a rigid link, _rest_sliders; the stick set at
t = 0 chosen as at any switch), march
forcing periods of the exact period map (period.advance) until P^k(s) repeats within steady_tol (k up
to max_orbit_period), and from period shoot_after on (then again after 1, 2, 4, ... periods, the gaps
doubling up to shoot_every: a miss early in the transient is retried soon, a long march not shot at every
period; every shoot_every periods where static friction holds several steady states) try Newton shooting
on P^k(s) = s with the exact monodromy (transition matrices times saltation matrices; a contact stuck
all of an iterate's periods kept where it is, its position being a neutral direction, _step; least squares
on the rest), k = 1 unless the march suggests a period-k orbit (_suggested_lag; P alone where P^k's Newton
misses), k lowered to the orbit's least period (_least_period). An orbit with a contact stuck all period is
taken only where the march's last period held that contact stuck at the same position (_kept_where_marched:
the member of the stuck family the motion from rest settles on). Newton's orbit is refused, and the march
goes on, where a contact slips less than _MICRO_SLIP steady_tol x the state's size per period
(_micro_slip: a stuck orbit's neutral family, the stuck positions, has a member at its band's edge, which
Newton from a still-slipping transient lands on, the slip then a tolerance's residue; the march settles
inside the band), _MICRO_TRIES times at most. A
converged orbit is measured over its k periods; its largest Floquet multiplier
(eigenvalue of the monodromy of P^k) where the settings ask. Amplitude still growing at the cap: GROWING;
otherwise PERIOD_CAP; the events-and-steps budget: EVENT_BUDGET; a non-finite state or a mode that
cannot be built: NONFINITE. A point may start instead from a given state at the section (another
orbit's end state, state_size's layout, made consistent as after a Newton step, _section), and returns the
state where its search stopped (the steady orbit's, where it converged): the second start with static
friction and the stepped-sine sweeps (friction_sweep.structures.starts) ride on these.

One float row per point, laid out by row_layout(n, m): first harmonic cos and sin parts and max |x| per
mass, per contact stops, slips, stuck fraction, friction energy per period, then steady_state,
orbit_period, periods, floquet_multiplier, work (events and steps spent).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.codes import SteadyState
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.settings import (
    KERNEL_RK4,
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

# with static above kinetic friction Newton's orbit is taken only within STICK_SHOT_REACH of the state's size
# from the march, as for one mass: static friction holds several orbits, and the march's start decides which one
# a point settles on
from friction_sweep.kernels.steady import STICK_SHOT_REACH
from friction_sweep.kernels.structure.flow import (
    CP_EY,
    CP_KT,
    CP_MU,
    CP_MUS,
    CP_SLOT,
    INACTIVE,
    STUCK,
    build_mode,
    mode_workspace,
    solve_small,
)
from friction_sweep.kernels.structure.period import (
    C_COUNTS,
    MC_ENERGY,
    MC_SIZE,
    MC_SLIPS,
    MC_STOPS,
    MC_STUCK,
    MC_SUMS,
    OK,
    advance,
    new_cache,
    rel_position,
    rel_velocity,
    resolve,
)
from friction_sweep.kernels.structure.rk4 import advance_rk4, balance_tolerance
from friction_sweep.ties import TIE_RTOL

#: per-point slots after the per-mass and per-contact blocks
PT_STEADY, PT_ORBIT, PT_PERIODS, PT_FLOQUET, PT_WORK = 0, 1, 2, 3, 4
PT_SIZE = 5
_NEWTON_ITERATIONS = 12
_CONVERGED = int(SteadyState.CONVERGED)
_PERIOD_CAP = int(SteadyState.PERIOD_CAP)
_EVENT_BUDGET = int(SteadyState.EVENT_BUDGET)
_NONFINITE = int(SteadyState.NONFINITE)
_GROWING = int(SteadyState.GROWING)
_UNBALANCED = int(SteadyState.UNBALANCED)
#: an orbit is resolved while its size x stiffness x _RESOLVED stays below its largest force
_RESOLVED = 1e-10
#: the march suggests a period-k orbit (k > 1) where P^k moves the state by under this share of P's move
_LAG_SUGGESTS = 0.1
#: _newton's results: no orbit; an orbit; an orbit whose confirming period was measured
NO_ORBIT, ORBIT, MEASURED = 0, 1, 2
#: Newton measures its next period where its last relative residual squared is within this many tol
#: (_speculate): at the default steady_tol 1e-10, a residual of 1e-4 of the state
_SPECULATE = 100.0
#: Newton iterations in a row whose residual falls by under a tenth before the shooting is given up
_STALLED = 3
#: the march takes a repeat at lag k > 1 for a period-k orbit only where the state is farther than this many
#: steady_tol from the one d periods back for every proper divisor d of k (_distinct_points)
_DISTINCT = 1e3
#: Newton's orbit with a contact slipping under this many steady_tol x the state's size per period is
#: refused (_micro_slip), up to _MICRO_TRIES times per point
_MICRO_SLIP = 10.0
_MICRO_TRIES = 3
#: Newton's orbit keeps a contact it has stuck all period where the march holds it: within this many steady_tol x
#: the state's size (_kept_where_marched)
_KEPT = 10.0
#: a Newton iterate's work (events and steps) may be this many times a marched period's per period shot,
#: plus the slack
_NEWTON_COST = 8
_NEWTON_SLACK = 1000


def row_layout(n: int, m: int) -> dict[str, slice]:
    """Where solve_point writes each output in its row."""
    names = ("harm_cos", "harm_sin", "peak")
    per_contact = ("stops", "slips", "stuck_fraction", "friction_energy")
    out: dict[str, slice] = {}
    at = 0
    for name in names:
        out[name] = slice(at, at + n)
        at += n
    for name in per_contact:
        out[name] = slice(at, at + m)
        at += m
    out["point"] = slice(at, at + PT_SIZE)
    return out


def row_size(n: int, m: int) -> int:
    return 3 * n + 4 * m + PT_SIZE


@jit
def _section(z, st, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache):
    """Make the modes at the section (t = 0) agree with the state (after a Newton step): slip signs from
    the relative velocities, a slipping slider slaved to its spring, the rigid stick set re-chosen."""
    n = K.shape[0]
    m = W.shape[0]
    N = z.shape[0]
    for j in range(m):
        if st[j] == INACTIVE:
            continue
        kt = cp[j, CP_KT]
        u1 = rel_velocity(z, W, cp, j, n, N, omega)
        if kt > 0.0:
            slot = 2 * n + int(cp[j, CP_SLOT])
            if st[j] != STUCK:
                if st[j] * u1 > 0.0:
                    z[slot] = rel_position(z, W, cp, j, n, N) - st[j] * cp[j, CP_MU] / kt
                else:
                    st[j] = STUCK
            if st[j] == STUCK:
                lam = kt * (rel_position(z, W, cp, j, n, N) - z[slot])
                if abs(lam) > cp[j, CP_MUS]:
                    s = 1 if lam > 0.0 else -1
                    st[j] = s
                    z[slot] = rel_position(z, W, cp, j, n, N) - s * cp[j, CP_MU] / kt
        elif st[j] != STUCK and abs(u1) > 0.0:
            st[j] = 1 if u1 > 0.0 else -1
    return resolve(z, st, -1, 0, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache)


@jit
def _micro_slip(row, cp, n, m, bound):
    """Whether a measured orbit (row) has a contact that slips, but less than `bound` per period (its
    friction energy over its kinetic friction: the sliding distance, and for a Jenkins contact with static
    above kinetic friction that plus its unloading loss over mu)."""
    at = 3 * n + 3 * m
    for j in range(m):
        mu = cp[j, CP_MU]
        e = row[at + j]
        if mu > 0.0 and e > 0.0 and e <= bound * mu:
            return True
    return False


@jit
def _holds_several(cp):
    """Whether static friction exceeds kinetic at a contact with friction (a point may then hold several
    steady states, DESIGN §7 uniqueness)."""
    for j in range(cp.shape[0]):
        if cp[j, CP_MU] > 0.0 and cp[j, CP_MUS] > cp[j, CP_MU]:
            return True
    return False


@jit
def _norm(z, Nd):
    acc = 0.0
    for i in range(Nd):
        acc = max(acc, abs(z[i]))
    return acc


@jit
def _periods(z, st, k, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas, harm, xmax, mc):
    N = z.shape[0]
    for _ in range(k):
        if cache[C_COUNTS][2] > 0:  # method rk4 (new_cache's counts)
            code = advance_rk4(z, st, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas,
                               harm, xmax, mc)
        else:
            code = advance(z, st, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas, harm,
                           xmax, mc, None)
        if code != OK:
            return code
        z[N - 3] = 1.0
        z[N - 2] = 0.0
    return OK


@jit
def _lag_distance(z, hist, p, k, maxk, Nd):
    """max |z - the state k periods back| over the dynamic slots (hist: the march's ring of section
    states, p periods marched)."""
    prev = hist[(p - k) % maxk]
    d = 0.0
    for i in range(Nd):
        d = max(d, abs(z[i] - prev[i]))
    return d


@jit
def _distinct_points(z, hist, p, k, maxk, Nd, bound):
    """Whether the march's repeat at lag k is a period-k orbit: every proper divisor d of k moves the state
    by more than bound. A decaying transient whose free motion nearly returns after k periods (a mode at
    close to a multiple of 1/k of the forcing frequency: |mu^k - 1| << |mu - 1| for its multiplier mu)
    repeats at lag k to steady_tol while P itself still moves it by a few steady_tol: that is the period-d
    orbit still settling, not a period-k one (the 'between' structure at w 2.5, scale 2, stuck: lag 8 matched
    43 periods before lag 1 did)."""
    for d in range(1, k):
        if k % d == 0 and _lag_distance(z, hist, p, d, maxk, Nd) <= bound:
            return False
    return True


@jit
def _suggested_lag(z, hist, p, maxk, Nd):
    """The k of the period-k orbit the march suggests: the lag k <= min(maxk, p) at which the state comes
    closest to the one k periods back, where that is under _LAG_SUGGESTS times the one-period distance (a
    march spiralling onto a period-k orbit alternates between its k points, so P^1 moves it by about the
    orbit's spread while P^k moves it by the transient only); 1 otherwise."""
    best = np.inf
    lag = 1
    one = np.inf
    for k in range(1, min(maxk, p) + 1):
        d = _lag_distance(z, hist, p, k, maxk, Nd)
        if k == 1:
            one = d
        if d < best:
            best = d
            lag = k
    if lag > 1 and best <= _LAG_SUGGESTS * one:
        return lag
    return 1


@jit
def _least_period(z, st, k, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, tol, scale, J, jflag, harm, xmax,
                  mc):
    """The least d dividing k with P^d(z) = z within tol (a fixed point of P^k may be one of P: a march
    converging with a multiplier near -1 suggests lag 2 for a period-1 orbit)."""
    N = z.shape[0]
    Nd = N - 3
    ref = max(_norm(z, Nd), scale)
    for d in range(1, k):
        if k % d != 0:
            continue
        zd = z.copy()
        std = st.copy()
        if _periods(zd, std, d, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, False, J, jflag, False,
                    harm, xmax, mc) != OK:
            continue
        err = 0.0
        for i in range(Nd):
            err = max(err, abs(zd[i] - z[i]))
        if err <= tol * ref:
            return d
    return k


@jit
def _newton(z, st, k, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, tol, scale, J, jflag, harm, xmax, mc, cap):
    """Newton shooting on P^k(s) = s from z (in place where it converges): NO_ORBIT, or ORBIT, or MEASURED
    where the period that confirmed convergence was also measured (_speculate): harm, xmax, mc then hold
    the measurement of P^k from z (mc's label state after one pass) and J, jflag its monodromy, as
    _measure's own passes would give them bit for bit (the same passes from the same state). An iterate whose
    k periods cost more than k x `cap` units of work (events and steps) is no orbit: a step far off the orbit can
    land where contacts switch without end, and the march, which never goes there, is cheaper."""
    N = z.shape[0]
    Nd = N - 3
    zs = z.copy()
    sts = st.copy()
    last = np.inf
    before = np.inf
    stalled = 0
    # the residual is judged against the state Newton starts from, not the iterate: where no orbit exists
    # (resonance with too little friction) the iterates run off to infinity with a relative residual
    # that falls like 1 / |s| while the absolute one stays
    ref = max(_norm(z, Nd), scale)
    for _ in range(_NEWTON_ITERATIONS):
        if not _section(zs, sts, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache):
            return NO_ORBIT
        z0 = zs.copy()
        st0 = sts.copy()
        J[:, :] = 0.0
        for i in range(Nd):
            J[i, i] = 1.0
        jflag[:] = 0.0
        jflag[0] = 1.0
        meas = _speculate(last, before, ref, tol)
        if meas:
            mc[:, :] = 0.0
            harm[:, :] = 0.0
            xmax[:] = 0.0
        held_back = max(budget[0] - k * cap, 0)
        budget[0] -= held_back
        code = _periods(zs, sts, k, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, True, J, jflag, meas, harm,
                        xmax, mc)
        budget[0] += held_back
        if code != OK:
            return NO_ORBIT
        res = zs[:Nd] - z0[:Nd]
        err = _norm(res, Nd)
        if not np.isfinite(err):
            return NO_ORBIT
        if err <= tol * ref:
            z[:] = z0
            st[:] = st0
            return MEASURED if meas else ORBIT
        if err > 2.0 * last:
            return NO_ORBIT
        # a residual that has stopped falling (_STALLED times in a row under a tenth of a gain each) is
        # Newton stalled on a stick-slip sequence that its linearisation does not hold: the march goes on
        stalled = stalled + 1 if err >= 0.9 * last else 0
        if stalled >= _STALLED:
            return NO_ORBIT
        before = last
        last = err
        delta = _step(J, res, st0, jflag, W, cp, K.shape[0], Nd)
        zs[:] = z0
        sts[:] = st0
        for i in range(Nd):
            zs[i] += delta[i]
    return NO_ORBIT


@jit
def _step(J, res, st0, jflag, W, cp, n, Nd):
    """Newton's step delta on P^k(s) = s: (J - I) delta = -res, with every contact that was stuck all the
    iterate's k periods (stuck at its start, no switch changed it: jflag[1 + j] == 0) kept where it is, its
    relative position w_j . x (rigid) or its slider (Jenkins) unchanged. Those are the neutral directions of a
    stuck orbit (DESIGN §7: any stuck position whose force stays within the band is an orbit): the motion holds
    them fixed once the contact stops slipping, so the orbit the march settles on has the positions the
    contact stuck at, and a step along them would trade that member for another (a stuck damper from rest,
    never moved, reported with a peak of 21 % of the forced mass's). Least squares on what remains (a mass
    held only by a slipping contact leaves a neutral direction of its own)."""
    m = W.shape[0]
    Mx = J[:Nd, :] - np.eye(Nd)
    c = 0
    for j in range(m):
        if st0[j] == STUCK and jflag[1 + j] == 0.0:
            c += 1
    if c == 0:
        return np.linalg.lstsq(Mx, -res)[0]
    Cm = np.zeros((c, Nd))
    r = 0
    for j in range(m):
        if st0[j] == STUCK and jflag[1 + j] == 0.0:
            if cp[j, CP_KT] > 0.0:
                Cm[r, 2 * n + int(cp[j, CP_SLOT])] = 1.0
            else:
                for i in range(n):
                    Cm[r, i] = W[j, i]
            r += 1
    # the steps that keep them: the null space of Cm, from its SVD (rank: singular values above rounding)
    _, sv, vt = np.linalg.svd(Cm)
    rank = 0
    for q in range(sv.shape[0]):
        if sv[q] > 1e-12 * sv[0]:
            rank += 1
    Nc = np.ascontiguousarray(vt[rank:, :].T)
    y = np.linalg.lstsq(Mx @ Nc, -res)[0]
    return Nc @ y


@jit
def _kept_where_marched(zs, sts, jflag, z, settled, W, cp, n, bound):
    """Whether Newton's orbit (zs, sts; jflag the marks of its confirming pass) holds every contact it has
    stuck all period where the march (z) holds it: the march's last period had that contact stuck throughout
    (settled), and its relative position w_j . x (rigid) or its slider (Jenkins) is the march's within bound.
    A stuck orbit is one of a family (_step); the motion from rest settles on the member whose stuck
    positions are those where the contact last stopped slipping, which the march has reached once it holds
    them and Newton, keeping them (_step), then finds. Newton shot while the march still slips lands on
    another member: the blade's stuck points at w 1.44, friction_scale 10.6 slip in their first two periods,
    and an orbit shot after the first reports the blade's peak 33 % above where the motion settles."""
    N = zs.shape[0]
    for j in range(W.shape[0]):
        if sts[j] != STUCK or jflag[1 + j] != 0.0:
            continue
        if not settled[j]:
            return False
        if cp[j, CP_KT] > 0.0:
            slot = 2 * n + int(cp[j, CP_SLOT])
            gap = zs[slot] - z[slot]
        else:
            gap = rel_position(zs, W, cp, j, n, N) - rel_position(z, W, cp, j, n, N)
        if abs(gap) > bound:
            return False
    return True


@jit
def _repels(J, jflag, Nd):
    """Whether the monodromy of Newton's confirming pass (J, valid where jflag[0] == 1) has a multiplier
    outside the unit circle (beyond 1e-6: a neutral direction's 1 is no repeller)."""
    if jflag[0] != 1.0:
        return False
    ev = np.linalg.eigvals(J[:Nd, :].astype(np.complex128))
    for e in ev:
        if abs(e) > 1.0 + 1e-6:
            return True
    return False


@jit
def _speculate(last, before, ref, tol):
    """Whether the next Newton period is likely the one that confirms convergence, and so worth measuring
    as it goes (a measured step costs about twice a plain one; a right guess saves _measure a period,
    two with stability): the last residual e converging faster than linearly (under a tenth of the one
    before) and small enough that Newton's quadratic rate, e -> e^2 / |s|, takes it under tol:
    (e / |s|)^2 <= _SPECULATE x tol. A wrong guess costs the measurement, never a result."""
    rel = last / ref
    return last <= 0.1 * before and rel * rel <= _SPECULATE * tol


@jit
def _measured_pass(z, st, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm, xmax, mc):
    """One measured pass over the orbit's `orbit` periods from a copy of (z, st) into harm, xmax, mc:
    _CONVERGED, or the point's status where the advance fails."""
    zm = z.copy()
    stm = st.copy()
    if _periods(zm, stm, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, False, J, jflag, True, harm,
                xmax, mc) != OK:
        return _EVENT_BUDGET if budget[0] < 0 else _NONFINITE
    return _CONVERGED


@jit
def _measure(z, st, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm, xmax, mc, settings,
             row, measured):
    """Measure the orbit through z over its `orbit` periods into row; CONVERGED, or UNBALANCED where the
    excitation's work per period misses the viscous and friction dissipation (an orbit that is none), or
    the advance's failure. measured: Newton's confirming period was this pass (_newton's MEASURED; harm,
    xmax, mc, J and jflag hold what it gathered), so the passes it stands for are not run again."""
    n = K.shape[0]
    m = W.shape[0]
    N = z.shape[0]
    Nd = N - 3
    pt = 3 * n + 4 * m
    if not measured:
        mc[:, :] = 0.0
    jenkins = False
    for j in range(m):
        jenkins = jenkins or (cp[j, CP_KT] > 0.0 and st[j] != INACTIVE)
    if jenkins:
        # a Jenkins contact's labels depend on its label state at the section (a held stick or a creep
        # begun before t = 0): the orbit's own, from one pass over it (jenkins_steady.shoot_jenkins's rule;
        # Newton's measured period was that pass)
        if not measured:
            code = _measured_pass(z, st, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm,
                                  xmax, mc)
            if code != _CONVERGED:
                return code
        for col in MC_SUMS:
            mc[:, col] = 0.0
    if jenkins or not measured:
        harm[:, :] = 0.0
        xmax[:] = 0.0
        code = _measured_pass(z, st, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm,
                              xmax, mc)
        if code != _CONVERGED:
            return code
    tk = orbit * T
    fric = 0.0
    for j in range(m):
        fric += mc[j, MC_ENERGY]
    w_in = harm[0, 2]
    vis = harm[0, 3]
    # rounding of the work integrals: the state's size squared times the stiffness scale
    size = _norm(z, Nd)
    kscale = 0.0
    for i in range(n):
        kscale = max(kscale, abs(K[i, i]), abs(C[i, i]) * omega)
    # an orbit so large against its forces that rounding swallows them (fs / k below eps x its size) is
    # no resolved orbit: its energy balance cannot be judged (resonance without an orbit runs there)
    fs = 0.0
    for i in range(n):
        fs = max(fs, abs(F[0, i]) + abs(F[1, i]))
    for j in range(m):
        fs = max(fs, cp[j, CP_MU], abs(cp[j, CP_EY]) * kscale)
    if size * kscale * _RESOLVED > fs:
        return _UNBALANCED
    # rk4's orbit balances its energy to the method's order only (rk4.balance_tolerance)
    rel = 1e-6 if cache[C_COUNTS][2] == 0 else max(1e-6, balance_tolerance(cache, n, T))
    slack = rel * (abs(w_in) + vis + fric) + 10.0 * settings[SET_STEADY_TOL] * size * size * kscale * tk
    if abs(w_in - vis - fric) > slack:
        return _UNBALANCED
    for i in range(n):
        row[i] = 2.0 * harm[i, 0] / tk
        row[n + i] = 2.0 * harm[i, 1] / tk
        row[2 * n + i] = xmax[i]
    for j in range(m):
        row[3 * n + j] = mc[j, MC_STOPS] / orbit
        row[3 * n + m + j] = mc[j, MC_SLIPS] / orbit if cp[j, CP_KT] > 0.0 else np.nan
        row[3 * n + 2 * m + j] = mc[j, MC_STUCK] / tk
        row[3 * n + 3 * m + j] = mc[j, MC_ENERGY] / orbit
    row[pt + 1] = orbit
    if settings[SET_STABILITY] != 0.0:
        ok = True
        if not measured:
            zf = z.copy()
            stf = st.copy()
            J[:, :] = 0.0
            for i in range(Nd):
                J[i, i] = 1.0
            jflag[0] = 1.0
            ok = _periods(zf, stf, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, True, J, jflag,
                          False, harm, xmax, mc) == OK
        if ok and jflag[0] == 1.0:
            Phi = J[:Nd, :].astype(np.complex128)
            ev = np.linalg.eigvals(Phi)
            big = 0.0
            for e in ev:
                big = max(big, abs(e))
            row[pt + PT_FLOQUET] = big
    return _CONVERGED


def state_size(n: int, m: int, jenkins: int) -> int:
    """Length of a start or end state (solve_point): x and v of each mass, each Jenkins slider's
    position, each contact's status (flow.STUCK, +-1 slipping, flow.INACTIVE)."""
    return 2 * n + jenkins + m


@jit
def flow_size(K, W, cp):
    """N, the length of the flow's state: x and v of each mass, each Jenkins slider's position, and the
    forcing's cos, sin and 1 (DESIGN §7)."""
    mJ = 0
    for j in range(W.shape[0]):
        if cp[j, CP_KT] > 0.0:
            mJ += 1
    return 2 * K.shape[0] + mJ + 3


@jit
def _start(z, st, start, W, cp, n, Nd):
    """z and st from a start state (state_size's layout; sliders of every Jenkins contact, statuses as
    floats). A contact without friction here is INACTIVE whatever the start says; one the start had
    INACTIVE (no friction where the start came from) begins stuck, a Jenkins slider relaxed."""
    m = cp.shape[0]
    for i in range(Nd):
        z[i] = start[i]
    for j in range(m):
        code = int(start[Nd + j])
        if cp[j, CP_MU] <= 0.0:
            st[j] = INACTIVE
        elif code == INACTIVE or code < -1 or code > 1:
            st[j] = STUCK
            if cp[j, CP_KT] > 0.0:
                z[2 * n + int(cp[j, CP_SLOT])] = rel_position(z, W, cp, j, n, z.shape[0])
        else:
            st[j] = code


@jit
def _rest_sliders(z, st, Minv, K, W, F, cp, omega, n):
    """Each Jenkins slider's position at the start from rest (z: x at rest, v = 0, t = 0): loaded with the
    force its contact carries as a rigid link, every contact with friction held so (S), the structure at
    rest: u_S'' = 0, (W_S M^-1 W_S^T) lambda_S = W_S M^-1 f + ey_S w^2 with f = F cos 0 - K x (the least-norm
    lambda_S where the links are dependent); clipped to the static band, just inside it (a start on its
    edge is a tie the stick cannot leave; beyond it the contact slips at once, as a rigid one does). At
    n = 1 this is the 1-DoF Jenkins kernels' start (jenkins_steady._resting_slider): the contact holds the
    mass against the forcing, so that as the contact stiffens the start approaches the rigid contact's.
    A relaxed slider instead lets the suddenly applied force swing the mass to about twice its static
    deflection, whatever the stiffness, and from rest ends where the rigid contact never moves."""
    m = W.shape[0]
    N = z.shape[0]
    S = np.zeros(m, dtype=np.int64)
    s = 0
    jenkins = False
    for j in range(m):
        if st[j] != INACTIVE:
            S[s] = j
            s += 1
            jenkins = jenkins or cp[j, CP_KT] > 0.0
    if not jenkins:
        return
    f = F[0, :].copy()
    for i in range(n):
        for k in range(n):
            f[i] -= K[i, k] * z[k]
    Mf = Minv @ f
    G = np.empty((s, s))
    b = np.empty(s)
    for a in range(s):
        ja = S[a]
        b[a] = cp[ja, CP_EY] * omega * omega
        for i in range(n):
            b[a] += W[ja, i] * Mf[i]
        for c in range(s):
            acc = 0.0
            for i in range(n):
                for k in range(n):
                    acc += W[ja, i] * Minv[i, k] * W[S[c], k]
            G[a, c] = acc
    lam = np.linalg.lstsq(G, b)[0]
    for a in range(s):
        j = S[a]
        if cp[j, CP_KT] > 0.0:
            hold = cp[j, CP_MUS] * (1.0 - TIE_RTOL)
            load = max(-hold, min(hold, lam[a]))
            z[2 * n + int(cp[j, CP_SLOT])] = rel_position(z, W, cp, j, n, N) - load / cp[j, CP_KT]


@jit
def _undamped(C, F, n):
    """Whether nothing dissipates but friction: no dashpot, no sin forcing (base excitation's dashpots)."""
    for i in range(n):
        if F[1, i] != 0.0:
            return False
        for k in range(n):
            if C[i, k] != 0.0:
                return False
    return True


@jit
def _held_forever(z, st, Minv, K, C, W, F, cp, omega, n):
    """The undamped structure's steady state where every contact stays stuck for good (jenkins_steady's
    _held_forever, for any structure). Without damping (C = 0, no sin forcing) a stuck structure's free motion
    never dies out, and a march would only approach the answer: with every contact stuck the motion is
    x = c + X cos wt + x_f(t), the forced part X from (K_J - w^2 M) X + W_R^T L_X = F_cos + sum_J kt w_j ey_j,
    W_R X = ey_R (K_J: K with each Jenkins contact's spring kt w_j w_j^T; R the rigid contacts, L their
    forces), c the static position of the sliders' springs (K_J c + W_R^T L_c = sum_J kt w_j p_j, W_R c = 0),
    x_f the free motion. A contact's force is its parts' sum (Jenkins kt (w_j.x - ey_j cos wt - p_j), rigid
    the constraint force, for x_f L_f = -(W_R M^-1 W_R^T)^-1 W_R M^-1 K_J x_f).

    - Static equal to kinetic friction everywhere: the damped structures' steady state has the first harmonic
      X wherever a stuck orbit fits the bands (one from every start, DESIGN §7), and the free motion's slips
      shave it off ever more finely; so held where every contact's forced amplitude is below mu (1 - TIE_RTOL),
      taking the orbit about the relaxed sliders (c = 0, p = 0; the 1-DoF kernels' convention, its peak |X|;
      the damped motion's mean position is where its transient left the sliders).
    - Static above kinetic friction somewhere: the start decides, so the free motion from the state z (rest,
      or a marched period's end without a switch, every contact stuck) counts, c's rigid contacts where they
      stuck. It keeps its energy E = (x_f.K_J x_f + v.M v) / 2 at t = 0, so a force q.x_f stays within
      sqrt(2 E q.y), (K_J y + W_R^T mu = q, W_R y = 0) (the largest q.x on the energy's ellipsoid; at n = 1
      the free part's amplitude exactly, jenkins_steady's reach). Held where |centre| + |forced| + that bound
      stays below mu_s (1 - TIE_RTOL) for every contact: the orbit c + X cos wt with the sliders where they
      are (jenkins_steady tests it at the start and after every marched period without slips, as here).

    z, st set to that orbit at t = 0, True; False (z, st untouched) where damped, the stuck structure
    resonates or is not restrained, or a force may leave its band: the march decides."""
    m = W.shape[0]
    N = z.shape[0]
    if not _undamped(C, F, n):
        return False
    R = np.zeros(m, dtype=np.int64)
    r = 0
    for j in range(m):
        if st[j] != INACTIVE and cp[j, CP_KT] <= 0.0:
            R[r] = j
            r += 1
    KJ = K.copy()
    f = F[0, :].copy()
    pull = np.zeros(n)  # sum_J kt w_j p_j: the loaded sliders' pull at x = 0
    for j in range(m):
        kt = cp[j, CP_KT]
        if st[j] != INACTIVE and kt > 0.0:
            p = z[2 * n + int(cp[j, CP_SLOT])]
            for i in range(n):
                f[i] += kt * W[j, i] * cp[j, CP_EY]
                pull[i] += kt * W[j, i] * p
                for k in range(n):
                    KJ[i, k] += kt * W[j, i] * W[j, k]
    # the forced part, its first n rows times M^-1 (no inverse of M^-1 to compile):
    # (M^-1 K_J - w^2 I) X + M^-1 W_R^T L_X = M^-1 f
    G = np.zeros((n + r, n + r))
    B = np.zeros((n + r, 1))
    for i in range(n):
        for k in range(n):
            B[i, 0] += Minv[i, k] * f[k]
            for q in range(n):
                G[i, k] += Minv[i, q] * KJ[q, k]
        G[i, i] -= omega * omega
        for a in range(r):
            for k in range(n):
                G[i, n + a] += Minv[i, k] * W[R[a], k]
    for a in range(r):
        B[n + a, 0] = cp[R[a], CP_EY]
        for i in range(n):
            G[n + a, i] = W[R[a], i]
    X = np.empty((n + r, 1))
    if not solve_small(G, B, X):
        return False
    forced = np.zeros(m)
    a = 0
    for j in range(m):
        if st[j] == INACTIVE:
            continue
        if cp[j, CP_KT] > 0.0:
            amp = -cp[j, CP_EY]
            for i in range(n):
                amp += W[j, i] * X[i, 0]
            forced[j] = cp[j, CP_KT] * amp
        else:
            forced[j] = X[n + a, 0]
            a += 1
    if not _holds_several(cp):
        for j in range(m):
            if st[j] != INACTIVE and not abs(forced[j]) < cp[j, CP_MU] * (1.0 - TIE_RTOL):
                return False
        z[:N - 3] = 0.0
        for i in range(n):
            z[i] = X[i, 0]
        for j in range(m):
            if st[j] != INACTIVE:
                st[j] = STUCK
        return True
    # the free motion's force rows q_j over x: the x columns of the all-stuck mode's contact-force rows
    # (flow.build_mode: a Jenkins contact's kt w_j, a rigid one's -(W_R M^-1 W_R^T)^-1 W_R M^-1 K_J)
    stuck = st.copy()
    for j in range(m):
        if st[j] != INACTIVE:
            stuck[j] = STUCK
    L = np.empty((m, N))
    if not build_mode(stuck, Minv, K, C, W, F, cp, omega, np.empty((N, N)), L, mode_workspace(n, m, N)):
        return False
    Q = L[:, :n]
    # the static KKT, [K_J W_R^T; W_R 0], for the centre (column 0) and each contact's y_j (column 1 + j)
    S = np.zeros((n + r, n + r))
    BS = np.zeros((n + r, 1 + m))
    for i in range(n):
        BS[i, 0] = pull[i]
        for k in range(n):
            S[i, k] = KJ[i, k]
        for j in range(m):
            BS[i, 1 + j] = Q[j, i]
    for a in range(r):
        BS[n + a, 0] = rel_position(z, W, cp, R[a], n, N)  # W_R c = u_R, where it is stuck (W_R X = ey_R)
        for i in range(n):
            S[i, n + a] = W[R[a], i]
            S[n + a, i] = W[R[a], i]
    Y = np.empty((n + r, 1 + m))
    if not solve_small(S, BS, Y):
        return False
    # the free motion's start x_f(0) = x - c - X (in W_R's null space), v_f(0) = v (the other parts' velocity is
    # zero at t = 0), and twice its energy, x_f.K_J x_f + v.M v (M v from M^-1's elimination)
    xf = np.empty(n)
    for i in range(n):
        xf[i] = z[i] - Y[i, 0] - X[i, 0]
    energy = 0.0
    for i in range(n):
        for k in range(n):
            energy += xf[i] * KJ[i, k] * xf[k]
    moving = False
    for i in range(n):
        moving = moving or z[n + i] != 0.0
    if moving:
        Mv = np.empty((n, 1))
        if not solve_small(Minv.copy(), z[n:2 * n].copy().reshape((n, 1)), Mv):
            return False
        for i in range(n):
            energy += z[n + i] * Mv[i, 0]
    a = 0
    for j in range(m):
        if st[j] == INACTIVE:
            continue
        if cp[j, CP_KT] > 0.0:
            centre = -z[2 * n + int(cp[j, CP_SLOT])]
            for i in range(n):
                centre += W[j, i] * Y[i, 0]
            centre *= cp[j, CP_KT]
        else:
            centre = Y[n + a, 0]
            a += 1
        qy = 0.0
        for i in range(n):
            qy += Q[j, i] * Y[i, 1 + j]
        reach = abs(centre) + abs(forced[j]) + np.sqrt(max(energy, 0.0) * max(qy, 0.0))
        if not reach < cp[j, CP_MUS] * (1.0 - TIE_RTOL):
            return False
    for i in range(n):
        z[i] = Y[i, 0] + X[i, 0]
        z[n + i] = 0.0
    for j in range(m):
        if st[j] != INACTIVE:
            st[j] = STUCK
    return True


@jit
def solve_point(Minv, K, C, W, F, cp, omega, x_rest, settings, row, start, end):
    """Steady state and measurement of one point into row (row_layout). From rest, or from `start` (a state
    at the section t = 0, state_size's layout) where its first entry is not NaN; the state at the section
    where the search stopped (the steady orbit's where it converged) into `end`, NaN where not finite."""
    n = K.shape[0]
    m = W.shape[0]
    N = flow_size(K, W, cp)
    Nd = N - 3
    T = 2.0 * np.pi / omega
    tol = settings[SET_STEADY_TOL]
    vtol = settings[SET_STOP_TOL]
    max_periods = int(settings[SET_MAX_PERIODS])
    maxk = max(1, int(settings[SET_MAX_ORBIT_PERIOD]))
    shoot_after = int(settings[SET_SHOOT_AFTER])
    shoot_every = max(1, int(settings[SET_SHOOT_EVERY]))
    budget = np.array([int(settings[SET_WORK_BUDGET])])
    start_budget = budget[0]
    row[:] = np.nan
    cache = new_cache(n, m, N)
    if settings[SET_KERNEL] == KERNEL_RK4:
        cache[C_COUNTS][2] = max(1, int(settings[SET_STEPS_PER_PERIOD]))
    harm = np.zeros((n, 4))
    xmax = np.zeros(n)
    mc = np.zeros((max(m, 1), MC_SIZE))
    J = np.zeros((N, Nd))
    # the Jacobian's flag (0: a saltation divided by zero) and, per contact, whether a switch changed it
    jflag = np.ones(1 + m)
    # scale of the state: the static deflection under the largest force
    fs = 0.0
    for i in range(n):
        fs = max(fs, abs(F[0, i]) + abs(F[1, i]))
    for j in range(m):
        fs = max(fs, cp[j, CP_MUS] + abs(cp[j, CP_EY]))
    kmax = 0.0
    for i in range(n):
        kmax = max(kmax, abs(K[i, i]))
    scale = 1e-300 + fs / max(kmax, 1e-300) * 1e-6
    # start from rest
    z = np.zeros(N)
    z[:n] = x_rest
    z[N - 3] = 1.0
    z[N - 1] = 1.0
    st = np.zeros(max(m, 1), dtype=np.int64)[:m]
    for j in range(m):
        if cp[j, CP_MU] <= 0.0:
            st[j] = INACTIVE
    status = _PERIOD_CAP
    orbit = 0
    if np.isnan(start[0]):
        _rest_sliders(z, st, Minv, K, W, F, cp, omega, n)
        _held_forever(z, st, Minv, K, C, W, F, cp, omega, n)
        ready = resolve(z, st, -1, 0, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache)
    else:
        _start(z, st, start, W, cp, n, Nd)
        ready = _section(z, st, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache)
    if not ready:
        status = _NONFINITE
        max_periods = 0
    hist = np.zeros((maxk, Nd))
    norms = np.zeros(max(max_periods, 1))
    p = 0
    shooting = True
    pt = 3 * n + 4 * m
    zc = np.empty(N)
    stc = st.copy()
    held = 0
    next_shot = max(shoot_after, 1)
    # with static above kinetic friction the march from rest decides between steady states: Newton from an
    # early transient may find another, so the attempts keep shoot_every apart there
    several = _holds_several(cp)
    undamped = _undamped(C, F, n)
    gap = shoot_every if several else 1
    micro = 0
    # per contact, whether the march's last period had it stuck throughout (_kept_where_marched)
    settled = np.zeros(max(m, 1), dtype=np.bool_)
    while p < max_periods:
        hist[p % maxk, :] = z[:Nd]
        before = budget[0]
        for j in range(m):
            settled[j] = st[j] == STUCK
        jflag[1:] = 0.0
        code = _periods(z, st, 1, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, False, J, jflag, False,
                        harm, xmax, mc)
        for j in range(m):
            settled[j] = settled[j] and jflag[1 + j] == 0.0
        p += 1
        # a Newton iterate may cost _NEWTON_COST times a marched period per period (its periods start near
        # the march's state), and never more than the budget left
        cap = _NEWTON_COST * (before - budget[0]) + _NEWTON_SLACK
        if code != OK:
            status = _EVENT_BUDGET if budget[0] < 0 else _NONFINITE
            break
        size = max(_norm(z, Nd), scale)
        norms[p - 1] = size
        for k in range(1, min(maxk, p) + 1):
            if _lag_distance(z, hist, p, k, maxk, Nd) <= tol * size:
                if k == 1 or _distinct_points(z, hist, p, k, maxk, Nd, _DISTINCT * tol * size):
                    orbit = k
                break
        if orbit > 0:
            code = _measure(z, st, orbit, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm, xmax,
                            mc, settings, row, False)
            status = code
            if code == _UNBALANCED and p < max_periods:
                orbit = 0
                continue
            break
        unsure = False
        if several and undamped:
            # a period without switches, every contact stuck: stuck for good where the free motion cannot carry a
            # force across its band (_held_forever: the orbit about where the contacts are, confirmed by the next
            # period). Elsewhere it will slip again, and a stuck orbit Newton finds from here is not where the
            # march goes (a Jenkins mass, w 0.66, beta 0.7, mu_s/mu 1.5, stuck at 0.095 from its first period on
            # where it slips after and settles continuous at 0.821): no shot from such a period
            still = True
            for j in range(m):
                still = still and jflag[1 + j] == 0.0 and (st[j] == STUCK or st[j] == INACTIVE)
            if still and _held_forever(z, st, Minv, K, C, W, F, cp, omega, n):
                continue
            unsure = still
        # the march has come near the orbit a Newton shot found earlier (held back as too far from the
        # march then, with static friction): that is the orbit it approaches
        near = held > 0 and _norm(z[:Nd] - zc[:Nd], Nd) <= STICK_SHOT_REACH * size
        scheduled = shooting and p >= next_shot and not unsure
        if scheduled and several and p < shoot_every:
            # with static above kinetic friction Newton from a period with switches lands on whichever of the
            # point's states is nearest, not necessarily the one the march settles on (jenkins_steady's and
            # steady's rule: shoot from a period without switches, or after shoot_every periods; a Jenkins
            # mass at w 0.52, beta 0.1, mu_s/mu 1.3 took another stick-slip orbit 9e-5 of the amplitude away)
            for j in range(m):
                scheduled = scheduled and jflag[1 + j] == 0.0
        if scheduled:
            next_shot = p + gap
            gap = min(2 * gap, shoot_every)
        if near or scheduled:
            if near:
                zs = zc.copy()
                sts = stc.copy()
                lag = held
                found = ORBIT
                held = 0
            else:
                zs = z.copy()
                sts = st.copy()
                lag = _suggested_lag(z, hist, p, maxk, Nd)
                found = _newton(zs, sts, lag, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, tol, scale, J, jflag,
                                harm, xmax, mc, cap)
                if found == NO_ORBIT and lag > 1:
                    # the suggestion was wrong (a period-1 orbit approached with a multiplier near -1 whose P^k
                    # Newton misses): shoot on P as without it
                    zs[:] = z
                    sts[:] = st
                    lag = 1
                    found = _newton(zs, sts, 1, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, tol, scale, J,
                                    jflag, harm, xmax, mc, cap)
                if found != NO_ORBIT and not _kept_where_marched(zs, sts, jflag, z, settled, W, cp, n,
                                                                 _KEPT * tol * size):
                    found = NO_ORBIT
                if found != NO_ORBIT and several and _repels(J, jflag, Nd):
                    # static friction holds several states, and Newton found one the motion leaves, which no march
                    # settles on: the joined Jenkins mass at w 0.81, beta 0.5, mu_s/mu 1.3 has a period-2 orbit
                    # with multiplier 1.07 beside the period-7 one the march reaches; tests/test_structure_starts.py's
                    # swept damper at w 1.35 one with 1.007, where the march does not settle. (Without static
                    # friction none was found on the benchmark planes: the eigenvalues, 5-11 % of a point's cost,
                    # are spent only here.)
                    found = NO_ORBIT
                if found != NO_ORBIT and several and _norm(zs[:Nd] - z[:Nd], Nd) > STICK_SHOT_REACH * size:
                    # an orbit static friction holds elsewhere, or the one the march approaches from afar:
                    # held until the march comes near it (measured afresh then)
                    zc[:] = zs
                    stc[:] = sts
                    held = lag
                    found = NO_ORBIT
            if found != NO_ORBIT:
                least = _least_period(zs, sts, lag, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, tol, scale,
                                      J, jflag, harm, xmax, mc)
                # Newton's measured period covered P^lag: a shorter least period is measured afresh
                measured = found == MEASURED and least == lag
                lag = least
                code = _measure(zs, sts, lag, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, J, jflag, harm,
                                xmax, mc, settings, row, measured)
                if (code == _CONVERGED and micro < _MICRO_TRIES
                        and _micro_slip(row, cp, n, m, _MICRO_SLIP * tol * max(_norm(zs, Nd), scale))):
                    micro += 1
                elif code != _UNBALANCED:
                    status = code
                    orbit = lag
                    z[:] = zs
                    st[:] = sts
                    break
                else:
                    # an orbit that does not balance its energy: no orbit (growth at resonance); march on
                    shooting = False
            if budget[0] < 0:
                status = _EVENT_BUDGET
                break
    if status == _PERIOD_CAP and p >= 8:
        half = p // 2
        rising = 0
        for i in range(p - half, p):
            if norms[i] > norms[i - 1]:
                rising += 1
        if rising >= 0.9 * half and norms[p - 1] > 1.1 * norms[p - half]:
            status = _GROWING
    row[pt + 2] = p
    if status != _CONVERGED:
        row[:pt] = np.nan
        row[pt + 1] = np.nan
        row[pt + PT_FLOQUET] = np.nan
    row[pt + PT_STEADY] = status
    row[pt + PT_WORK] = start_budget - budget[0]
    finite = True
    for i in range(Nd):
        finite = finite and np.isfinite(z[i])
    for i in range(Nd):
        end[i] = z[i] if finite else np.nan
    for j in range(m):
        end[Nd + j] = st[j] if finite else np.nan


@jit
def point_forces(F_cos, F_sin_per_w, cp0, omega, scale, F, cp):
    """One point's forcing amplitudes F (the cos and sin rows at omega) and contact parameters cp (every
    friction of cp0 times scale), in place: what a batch varies from point to point."""
    for i in range(F_cos.shape[0]):
        F[0, i] = F_cos[i]
        F[1, i] = omega * F_sin_per_w[i]
    for j in range(cp.shape[0]):
        cp[j, CP_MU] = cp0[j, CP_MU] * scale
        cp[j, CP_MUS] = cp0[j, CP_MUS] * scale


@jit
def replay_start(Minv, K, C, W, F, cp, omega, settings, state):
    """A replay of an orbit from its state at the section (state_size's layout, t = 0; history.py,
    harmonics.py): (ok, z, st, cache, budget, J, jflag, harm, xmax, mc), the augmented state and the modes made
    to agree there (_start, _section; ok False where they cannot be), the mode cache, the settings' work
    budget, and the Jacobian's and measurement's workspaces advance takes where it is asked for neither."""
    n = K.shape[0]
    m = W.shape[0]
    N = flow_size(K, W, cp)
    Nd = N - 3
    budget = np.array([int(settings[SET_WORK_BUDGET])])
    cache = new_cache(n, m, N)
    z = np.zeros(N)
    z[N - 3] = 1.0
    z[N - 1] = 1.0
    st = np.zeros(max(m, 1), dtype=np.int64)[:m]
    _start(z, st, state, W, cp, n, Nd)
    ok = _section(z, st, Minv, K, C, W, F, cp, omega, 2.0 * np.pi / omega, settings[SET_STOP_TOL], budget, cache)
    return (ok, z, st, cache, budget, np.zeros((N, Nd)), np.ones(1 + m), np.zeros((n, 4)), np.zeros(n),
            np.zeros((max(m, 1), MC_SIZE)))


@jit
def solve_batch(Minv, K, C, W, F_cos, F_sin_per_w, cp0, x_rest, omegas, scales, settings, rows, starts, ends):
    """solve_point for each point i (frequency omegas[i], every friction times scales[i]) into rows[i], from
    starts[i] (a NaN row: from rest), its end state into ends[i]."""
    n = K.shape[0]
    F = np.empty((2, n))
    cp = cp0.copy()
    for p in range(omegas.shape[0]):
        point_forces(F_cos, F_sin_per_w, cp0, omegas[p], scales[p], F, cp)
        solve_point(Minv, K, C, W, F, cp, omegas[p], x_rest, settings, rows[p], starts[p], ends[p])
