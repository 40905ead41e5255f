"""Fixed-step classical Runge-Kutta for structures, with the exact engine's modes and switches (method rk4).

The same contract as period.advance (carry z over [0, T] from mode st, the same measurement and
monodromy slots), and the same modes: every contact slipping (a constant force), stuck (a Jenkins
spring, or a rigid constraint on its relative velocity: a real stick mode, never a regularised sgn) or
without friction, built by flow.build_mode and cached by period.lookup; the same event functions
(flow.event_rows) and the same switch (period.switch: the next mode from the forces). Only the flow
between events differs: instead of the exact exp(A s), classical RK4 on the mode's z' = A z,

    k1 = A z, k2 = A (z + s/2 k1), k3 = A (z + s/2 k2), k4 = A (z + s k3),
    z <- z + s/6 (k1 + 2 k2 + 2 k3 + k4) = P4(sA) z,  P4(x) = 1 + x + x^2/2 + x^3/6 + x^4/24

(on a linear autonomous system the stages collapse to P4, applied here by Horner's rule; the forcing is
the oscillator in z, integrated with the rest), on a grid of steps_per_period steps aligned with the
period: local error O(s^5), global O(h^4).

Events within a step, to the method's order: the quintic Hermite interpolant of z on the step (z, z' = A z,
z'' = A^2 z at both ends; error O(s^6) on the step, below RK4's own) is written as Taylor coefficients
zk[0..5] at the step's start, so that each event function's polynomial d_k = c . zk[k] goes to
roots.first_root (the engine's root search: no root missed, a function leaving zero at a mode's start
not an event) and the step's measurement to period._measure_step (8-point Gauss-Legendre is exact on
the quintic). At the first root the state is the interpolant's there (the event function zero to
rounding, as in the engine), the switch is taken, and the rest of the grid step follows in the new mode,
so the grid stays aligned with the period (as kernels/rk4.py does for one mass).

Monodromy (jac): J <- P4(sA) J on each step, the exact Jacobian of the RK4 step, and the engine's
saltation at each switch: the Jacobian of the discrete map to O(h^4), enough for Newton shooting, whose
residual is the RK4 map's own (its fixed point is the RK4 orbit), and for the Floquet multiplier to the
method's order.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.structure.flow import dot, matvec, mode_rate, taylor_state, term_sizes
from friction_sweep.kernels.structure.period import (
    BUDGET,
    C_A,
    C_ACT,
    C_CK,
    C_COUNTS,
    C_L,
    C_OK,
    C_ROWS,
    FAILED,
    OK,
    W_COEF,
    W_D,
    W_DMAG,
    W_JTMP,
    W_JTMP2,
    W_ZK,
    W_ZNEW,
    W_ZQ,
    _measure_step,
    lookup,
    switch,
)
from friction_sweep.kernels.structure.roots import first_root

#: degree of the dense output (quintic Hermite), and its Taylor rows zk[0..DENSE]
DENSE = 5
#: rows of the cache's zk (KT + 1 of them) this stepper uses beyond the dense output's: z1', z1'' at the step's
#: end, and rk4_step's workspace
_D1, _D2, _H1 = 6, 7, 8


@jit
def rk4_step(A, s, z, out, tmp):
    """out = P4(sA) z, one classical RK4 step of length s on z' = A z, by Horner's rule:
    z + sA(z + s/2 A(z + s/3 A(z + s/4 A z))); tmp: a vector of z's size."""
    out[:] = z
    for q in range(4):
        f = s / (4 - q)
        matvec(A, out, tmp)
        for i in range(z.shape[0]):
            out[i] = z[i] + f * tmp[i]


@jit
def rk4_jac(A, s, J, Y, Z):
    """J <- P4(sA) J (the RK4 step's Jacobian, rk4_step on each column), Horner's rule as rk4_step; Y, Z:
    workspaces of J's shape."""
    N = A.shape[0]
    Nc = J.shape[1]
    Y[:, :] = J
    for q in range(4):
        f = s / (4 - q)
        for r in range(N):
            for c in range(Nc):
                acc = 0.0
                for k in range(N):
                    a = A[r, k]
                    if a != 0.0:
                        acc += a * Y[k, c]
                Z[r, c] = J[r, c] + f * acc
        Y[:, :] = Z
    J[:, :] = Y


@jit
def dense(z0, z1, s, zk):
    """zk[0..DENSE] = the Taylor coefficients (times k!) at the step's start of the quintic Hermite
    interpolant of z on a step of length s, from z0, z1 and their derivatives zk[1], zk[2] (z0', z0'') and
    zk[_D1], zk[_D2] (z1', z1''), already in place. In theta = t / s the interpolant is z0 + s z0' theta +
    s^2 z0''/2 theta^2 + b3 theta^3 + b4 theta^4 + b5 theta^5 with, for the residuals D0 = z1 - (z0 + s z0'
    + s^2 z0''/2), D1 = s (z1' - z0' - s z0''), D2 = s^2 (z1'' - z0''): b3 = 10 D0 - 4 D1 + D2/2,
    b4 = -15 D0 + 7 D1 - D2, b5 = 6 D0 - 3 D1 + D2/2."""
    zk[0, :] = z0
    s2 = s * s
    c3 = 6.0 / (s2 * s)
    c4 = 24.0 / (s2 * s2)
    c5 = 120.0 / (s2 * s2 * s)
    for i in range(z0.shape[0]):
        a1 = zk[1, i]
        a2 = zk[2, i]
        d0 = z1[i] - (z0[i] + s * a1 + 0.5 * s2 * a2)
        d1 = s * (zk[_D1, i] - a1 - s * a2)
        d2 = s2 * (zk[_D2, i] - a2)
        zk[3, i] = c3 * (10.0 * d0 - 4.0 * d1 + 0.5 * d2)
        zk[4, i] = c4 * (-15.0 * d0 + 7.0 * d1 - d2)
        zk[5, i] = c5 * (6.0 * d0 - 3.0 * d1 + 0.5 * d2)


@jit
def advance_rk4(z, st, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas, harm, xmax, mc):
    """period.advance's contract (carry z over [0, T] from mode st, both in place; budget[0]: events and
    steps left; OK, BUDGET or FAILED) with classical RK4 on cache[C_COUNTS][2] steps per period."""
    c_L, c_rows, c_ck, c_act, c_ok = cache[C_L], cache[C_ROWS], cache[C_CK], cache[C_ACT], cache[C_OK]
    zk, znew, d, dmag = cache[W_ZK], cache[W_ZNEW], cache[W_D], cache[W_DMAG]
    Jtmp, Jtmp2 = cache[W_JTMP], cache[W_JTMP2]
    zq, coef = cache[W_ZQ], cache[W_COEF]
    steps = cache[C_COUNTS][2]
    n = K.shape[0]
    m = W.shape[0]
    N = z.shape[0]
    h = T / steps
    poly = zk[:DENSE + 1]
    dd = d[:DENSE + 1]
    k = 0  # the grid step [k h, (k + 1) h] that holds t
    t = 0.0
    while t < T:
        mi = lookup(st, Minv, K, C, W, F, cp, omega, T, cache)
        if not c_ok[mi]:
            return FAILED
        A = cache[C_A][mi]
        start = True
        fired = -1
        have = False  # zk[1], zk[2] hold z', z'' at z in this mode
        while t < T:
            tk1 = T if k + 1 >= steps else (k + 1) * h
            s = tk1 - t
            if s <= 0.0:
                k += 1
                continue
            budget[0] -= 1
            if budget[0] < 0:
                return BUDGET
            rk4_step(A, s, z, znew, zk[_H1])
            if not have:
                matvec(A, z, zk[1])
                matvec(A, zk[1], zk[2])
            matvec(A, znew, zk[_D1])
            matvec(A, zk[_D1], zk[_D2])
            dense(z, znew, s, zk)
            se = -1.0
            for f in range(2 * m):
                if not c_act[mi, f]:
                    continue
                row = c_rows[mi, f]
                for q in range(DENSE + 1):
                    dd[q] = dot(row, poly[q])
                # the size of the terms of each derivative at the start, as the engine measures it (from the
                # row's A-powers, c A^q . z): what is zero to rounding there is judged alike (roots.at_start)
                term_sizes(c_ck[mi, f], z, dmag)
                r = first_root(dd, dmag, s, start)
                if r >= 0.0 and (se < 0.0 or r < se):
                    se = r
                    fired = f
            if se < 0.0:
                if meas:
                    _measure_step(poly, s, n, m, st, W, cp, N, omega, harm, xmax, mc, c_L[mi], C, F, zq, coef)
                if jac:
                    rk4_jac(A, s, J, Jtmp, Jtmp2)
                z[:] = znew
                zk[1, :] = zk[_D1]
                zk[2, :] = zk[_D2]
                have = True
                t = tk1
                k += 1
                start = False
                for i in range(N):
                    if not np.isfinite(z[i]):
                        return FAILED
                continue
            # an event at t + se: the interpolant's state there
            taylor_state(poly, se, znew)
            if meas:
                _measure_step(poly, se, n, m, st, W, cp, N, omega, harm, xmax, mc, c_L[mi], C, F, zq, coef)
            if jac:
                rk4_jac(A, se, J, Jtmp, Jtmp2)
            z[:] = znew
            if se >= s:
                t = tk1
                k += 1
            else:
                t += se
            break
        if fired < 0:
            break
        if not switch(z, st, mi, fired, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas,
                      mc):
            return FAILED
    return OK


@jit
def balance_tolerance(cache, n, T):
    """The relative error to which an RK4 orbit balances its energy (the forcing's work against the viscous
    and friction dissipation, steady._measure's test of an orbit): (rho h)^4, RK4's error scale, with h the
    step T / steps and rho the fastest rate (flow.mode_rate) of the modes the orbit went through (those
    cached). At the exact flow's 1e-6 a coarse grid's orbit (a long period: 128 steps at w = 0.3 on the blade
    of tests/test_structure_rk4.py) would be refused as no orbit, and the march would run to its cap."""
    rho = 0.0
    for i in range(cache[C_COUNTS][0]):
        if cache[C_OK][i]:
            rho = max(rho, mode_rate(cache[C_A][i], n))
    x = rho * T / cache[C_COUNTS][2]
    return x * x * x * x
