"""One stretch of time of a structure, exact between events: modes, events, switches, monodromy, measures.

`advance` carries the augmented state z from t = 0 to t = T (the forcing's phase at t = 0 is whatever
z's cos and sin slots hold) through the modes of flow.py. Each mode is stepped by its exact exp(A h); on
each step every armed event function is checked by roots.first_root, and the earliest root ends the mode.

Switches (the mode decision is taken from the forces, never by re-arming a root finder on a function
that starts at zero):
- a slipping Jenkins slider whose relative velocity reaches zero sticks (its force is continuous there; the
  relative velocity is then set to zero exactly, by the projection below, so that the stuck slider's force
  rate kt u' does not read the root's rounding residue as a release);
- a stuck Jenkins slider whose force reaches +-mus slips that way; where mus > mu the massless slider
  unloads at once to +-mu (p jumps), dissipating (mus^2 - mu^2) / (2 kt);
- a rigid contact that stops, or whose constraint force reaches +-mus, is resolved with every rigid
  contact at zero relative velocity (Z: stuck ones, and slipping ones within stop_tol of zero) together.
  Their relative velocities are first set to zero exactly (an M^-1-weighted projection, a change at
  rounding level); then the present statuses with the switching contact's change are kept where they
  are consistent (below); otherwise the stick set is chosen by enumeration (3^|Z| assignments, m <= 8 in
  the issue's tests), the first consistent one with the most stuck contacts, contacts in lexical order.
  The rule (one for several contacts changing at the same instant): in the trial mode every stuck force
  stays within its static band (mus_j - |lambda_j| >= 0, and where that is zero to rounding it moves
  inwards), every released contact accelerates in its slip direction (sig u' grows from zero, under
  kinetic friction), and a contact breaking away slips; each judged by its first derivative that is not
  zero to rounding (roots.at_start, the test first_root applies at the mode's start, so the chosen mode
  does not switch again at once). With static = kinetic friction a break-away has no jump in force
  (u'' = 0 there): two contacts reaching their bands together (a symmetric structure) break away
  together, told by the third derivative and the forces' rates. Where no assignment is consistent, the
  least violating one.

Monodromy (jac): J = dz(t)/dz_dyn(0) is carried as J <- exp(A s) J on each piece and J <- S J at each
switch, S = R + (f+ - R f-) c^T / (c . f-) (R: the switch's reset, linear in z; c: the event's gradient;
f-/f+: the fields before and after). A switch where c . f- vanishes (a touch) is not smooth: jac_ok = 0.

Measurement (meas): the first harmonic of every x_i by 8-point Gauss-Legendre quadrature on each step
(exact to rounding: the integrand's Taylor series on a step falls like 2^-k / k!), max |x_i| at the
nodes and at every zero of v_i (refined on its Taylor polynomial), and per contact its stops (rigid:
slip to stick; Jenkins: a stick during which the relative velocity returns to zero, the contact then
holding the mass, as the 1-DoF Jenkins kernel labels it, with its creep rule: a slip begun from a held
stick during which the load never drives the contact, sig u'' <= 0 throughout (_driven_step; the mass
coasts on the contact spring's swing), leaves the contact holding the mass, held from the next stick's
start and no new stop), slips (Jenkins: slider slip phases), stuck time (Jenkins: the time held) and
friction energy (mu x sliding distance, plus the unloading loss above). The label state (the columns outside MC_SUMS)
carries over a period's end: steady._measure sets it by one pass over the orbit before it measures.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.structure.flow import (
    CP_EY,
    CP_KT,
    CP_MU,
    CP_MUS,
    CP_SLOT,
    INACTIVE,
    KT,
    STEP_RATE,
    STUCK,
    build_mode,
    dot,
    event_rows,
    expm_apply,
    expm_nodes,
    expm_taylor,
    matvec,
    mode_rate,
    mode_workspace,
    powers,
    solve_small,
    sparsity,
    taylor_state,
    term_sizes,
)
from friction_sweep.kernels.structure.fourier import fourier_step
from friction_sweep.kernels.structure.roots import ZERO_RTOL, at_start, first_root

_GX, _GW = np.polynomial.legendre.leggauss(8)
GAUSS_X = 0.5 * (_GX + 1.0)
GAUSS_W = 0.5 * _GW

#: mode cache size (modes repeat period after period)
CACHE = 16
#: quick no-root test: Taylor terms of g'' used, and the margin over the dropped ones (ratio <= 1/2 / 6)
_QUICK = 5
_QUICK_MARGIN = 1.25

#: halvings of the node interval that brackets a zero of a velocity (the extreme of its displacement)
_EXTREME_HALVINGS = 30

#: advance's status
OK, BUDGET, FAILED = 0, 1, 2
#: per-contact measurement columns
MC_STOPS, MC_SLIPS, MC_STUCK, MC_ENERGY, MC_HELD, MC_SIGN, MC_ANCHOR = 0, 1, 2, 3, 4, 5, 6
MC_SIZE = 7
#: the columns that are sums over the measured periods (the others, MC_HELD, MC_SIGN, MC_ANCHOR, are a Jenkins
#: contact's label state, which carries across a period's end)
MC_SUMS = (MC_STOPS, MC_SLIPS, MC_STUCK, MC_ENERGY)
#: samples of u'' per step when judging whether the load drives a Jenkins slip (_driven_step), and the
#: golden-section iterations refining the largest (jenkins.DRIVEN_REFINE's rule)
_DRIVEN_SAMPLES = 16
_DRIVEN_REFINE = 40


#: the derivatives of an event function by which a switch judges a trial mode (_leaves): g to g'''
_TRIAL_DERIVS = 4


@jit
def switch_workspace(n, m, N):
    """resolve's workspace: build_mode's (mode_workspace), a trial mode's event rows' A-powers
    (2m x _TRIAL_DERIVS x N), two rows of _TRIAL_DERIVS for an event function's derivatives (_leaves), the
    set Z, the trial and best statuses, and the trial's event rows and their flags (event_rows)."""
    m1 = max(m, 1)
    fb, ib = mode_workspace(n, m, N)
    return (fb, ib, np.empty((2 * m1, _TRIAL_DERIVS, N)), np.empty((2, _TRIAL_DERIVS)), np.empty(m1, dtype=np.int64),
            np.empty(m1, dtype=np.int64), np.empty(m1, dtype=np.int64), np.empty((2 * m1, N)),
            np.empty(2 * m1, dtype=np.bool_))


#: new_cache's slots by name (numba indexes a tuple of arrays by constants: these are). The mode cache: each
#: slot's statuses, A, exp(A h), contact-force rows, event rows and their A-powers, which events are armed,
#: h, whether the mode could be built, the counts; each mode's node matrices and whether they are built
C_ST, C_A, C_E, C_L, C_ROWS, C_CK, C_ACT, C_H, C_OK, C_COUNTS = range(10)
C_G, C_GOK = 25, 26
#: advance's workspaces (new_cache's docstring), the switch's last
(W_ZK, W_ZNEW, W_D, W_DMAG, W_R, W_ATMP, W_LTMP, W_JTMP, W_JTMP2, W_FV, W_CROW, W_BEFORE, W_S, W_ZQ,
 W_COEF) = range(10, 25)
W_SWITCH = 27


@jit
def new_cache(n, m, N):
    """The mode cache's arrays, built once per point, and advance's workspaces (zk, znew, d, dmag, R, Atmp,
    Ltmp, two of J's shape, f-/f+/R f-, the event row, the statuses before a switch, S, the states at the
    Gauss nodes and their Taylor coefficients, each mode's node matrices (_node_matrices) and whether they
    are built, the switch's workspace), in the order of the C_ and W_ names above: the hot loops allocate
    nothing. The counts (C_COUNTS): the modes cached, the next slot to replace, and the integrator: 0 the exact flow
    (advance), k > 0 classical RK4 with k steps per period (rk4.advance_rk4; steady.solve_point sets it from
    the settings)."""
    m1 = max(m, 1)
    return (np.full((CACHE, m1), -9, dtype=np.int64), np.zeros((CACHE, N, N)), np.zeros((CACHE, N, N)),
            np.zeros((CACHE, m1, N)), np.zeros((CACHE, 2 * m1, N)),
            np.zeros((CACHE, 2 * m1, KT + 1, N)), np.zeros((CACHE, 2 * m1), dtype=np.bool_),
            np.zeros(CACHE), np.zeros(CACHE, dtype=np.bool_), np.zeros(3, dtype=np.int64),
            np.empty((KT + 1, N)), np.empty(N), np.empty(KT + 1), np.empty(4), np.empty((N, N)),
            np.empty((N, N)), np.empty((m1, N)), np.empty((N, N - 3)), np.empty((N, N - 3)), np.empty((3, N)),
            np.empty(N),
            np.empty(m1, dtype=np.int64), np.empty((N, N)), np.empty((GAUSS_X.shape[0] + 1, N)),
            np.empty((GAUSS_X.shape[0] + 1, KT + 1)), np.empty((CACHE, GAUSS_X.shape[0], N, N)),
            np.zeros(CACHE, dtype=np.bool_), switch_workspace(n, m, N))


@jit
def find(st, c_st, c_cnt):
    """Index of mode st in the cache (its C_ST and C_COUNTS), -1 where it is not there. The callers on the
    hot paths (a mode's entry, a switch's trials) try it before lookup: a call that carries the whole
    cache tuple costs about a microsecond (numba counts a reference to each of its arrays in and out),
    this one, inlined, nanoseconds."""
    for i in range(c_cnt[0]):
        same = True
        for j in range(st.shape[0]):
            if c_st[i, j] != st[j]:
                same = False
                break
        if same:
            return i
    return -1


@jit
def event_powers(rows, act, A, ck):
    """ck[f, k] = rows[f] A^k for every armed event function f (act[f]) and k < ck.shape[1]: the Taylor
    coefficients' rows of g = rows[f] . z(t) (a mode's, in the cache; a trial's, _violation). The products
    skip A's zeros (flow.sparsity), each column summed over the rows of A in order: the dense row-times-matrix
    loop's values bit for bit where the rows are finite."""
    N = A.shape[0]
    cols = np.empty(N * N, dtype=np.int64)
    starts = np.empty(N + 1, dtype=np.int64)
    sparsity(A, cols, starts)
    for f in range(rows.shape[0]):
        if act[f]:
            ck[f, 0, :] = rows[f, :]
            for k in range(1, ck.shape[1]):
                out = ck[f, k]
                out[:] = 0.0
                for q in range(N):
                    c = ck[f, k - 1, q]
                    for e in range(starts[q], starts[q + 1]):
                        out[cols[e]] += c * A[q, cols[e]]


@jit
def lookup(st, Minv, K, C, W, F, cp, omega, T, cache):
    """Index of mode st in the cache, built there (A, exp(A h), forces, event rows and their A-powers)
    if it is not."""
    found = find(st, cache[C_ST], cache[C_COUNTS])
    if found >= 0:
        return found
    c_st, c_A, c_E, c_L, c_rows, c_ck, c_act, c_h, c_ok, c_cnt = cache[:10]
    m = W.shape[0]
    n = K.shape[0]
    used = c_cnt[0]
    if used < CACHE:
        i = used
        c_cnt[0] = used + 1
    else:
        i = c_cnt[1]
        c_cnt[1] = (i + 1) % CACHE
    for j in range(m):
        c_st[i, j] = st[j]
    A = c_A[i]
    ok = build_mode(st, Minv, K, C, W, F, cp, omega, A, c_L[i], cache[W_SWITCH])
    c_ok[i] = ok
    cache[C_GOK][i] = False
    if not ok:
        return i
    h = STEP_RATE / mode_rate(A, n)
    h = min(h, T / 4.0)
    c_h[i] = h
    expm_taylor(A, h, c_E[i])
    N = A.shape[0]
    event_rows(st, W, cp, omega, c_L[i], N, c_rows[i], c_act[i])
    event_powers(c_rows[i], c_act[i], A, c_ck[i])
    return i


@jit
def rel_velocity(z, W, cp, j, n, N, omega):
    acc = cp[j, CP_EY] * omega * z[N - 2]
    for i in range(n):
        acc += W[j, i] * z[n + i]
    return acc


@jit
def rel_position(z, W, cp, j, n, N):
    acc = -cp[j, CP_EY] * z[N - 3]
    for i in range(n):
        acc += W[j, i] * z[i]
    return acc


@jit
def _project(z, Z, nz, Minv, W, cp, omega, R, fb):
    """Set the relative velocities of contacts Z[:nz] to zero (M^-1-weighted); R gets the reset's matrix
    (identity where nothing is projected). False where their directions are dependent. fb: build_mode's
    float workspace (a switch_workspace's first; nothing allocated; the array, not the workspace tuple,
    whose every array a call would count a reference to)."""
    N = z.shape[0]
    n = W.shape[1]
    _identity(R)
    if nz == 0:
        return True
    WZ = fb[:nz * n].reshape((nz, n))
    o = nz * n
    for a in range(nz):
        for i in range(n):
            WZ[a, i] = W[Z[a], i]
    MW = fb[o:o + n * nz].reshape((n, nz))  # M^-1 W_Z^T
    o += n * nz
    for i in range(n):
        for a in range(nz):
            acc = 0.0
            for k in range(n):
                acc += Minv[i, k] * WZ[a, k]
            MW[i, a] = acc
    G = fb[o:o + nz * nz].reshape((nz, nz))
    o += nz * nz
    for a in range(nz):
        for b in range(nz):
            acc = 0.0
            for i in range(n):
                acc += WZ[a, i] * MW[i, b]
            G[a, b] = acc
    rows = fb[o:o + nz * N].reshape((nz, N))  # u'_Z = rows . z
    o += nz * N
    rows[:, :] = 0.0
    for a in range(nz):
        for i in range(n):
            rows[a, n + i] = WZ[a, i]
        rows[a, N - 2] = cp[Z[a], CP_EY] * omega
    X = fb[o:o + nz * N].reshape((nz, N))
    o += nz * N
    if not solve_small(G, rows, X):
        return False
    for i in range(n):
        for k in range(N):
            acc = 0.0
            for a in range(nz):
                acc += MW[i, a] * X[a, k]
            R[n + i, k] -= acc
    zt = fb[o:o + N]
    matvec(R, z, zt)
    z[:] = zt
    return True


@jit
def _leaves(ck, z, at_zero, dd):
    """How far g = c . z(t) misses staying >= 0 from z (0: it stays; the same test as first_root's at a
    mode's start, roots.at_start, so a chosen mode never fires at once), from ck[k] = c A^k (k <
    _TRIAL_DERIVS, the mode's A): g > 0 beyond rounding, or zero to rounding (at_zero: zero by
    construction) and its first derivative not zero to rounding positive. Otherwise -g where it is
    negative, else the tiny 1e-300 (an outward derivative: the contact would switch again at once). dd: a
    workspace for the derivatives and the sizes of their terms (switch_workspace's)."""
    N = z.shape[0]
    d = dd[0]
    dmag = dd[1]
    for k in range(d.shape[0]):
        acc = 0.0
        mag = 0.0
        for i in range(N):
            acc += ck[k, i] * z[i]
            mag += abs(ck[k, i] * z[i])
        d[k] = acc
        dmag[k] = mag
    if at_zero:
        d[0] = 0.0
    elif abs(d[0]) > ZERO_RTOL * dmag[0]:
        return 0.0 if d[0] > 0.0 else -d[0]
    return 0.0 if at_start(d, dmag) else 1e-300


@jit
def _rows_violation(trial, Z, nz, z, ck, dd):
    """_violation from the trial mode's event rows and their A-powers ck (2 per contact)."""
    bad = 0.0
    for a in range(nz):
        j = Z[a]
        if trial[j] == STUCK:
            bad += _leaves(ck[2 * j], z, False, dd)
            bad += _leaves(ck[2 * j + 1], z, False, dd)
        else:
            # g = sig u' is zero here (resolve projected it); the slip holds where it grows
            bad += _leaves(ck[2 * j], z, True, dd)
    return bad


@jit
def _violation(trial, Z, nz, z, Minv, K, C, W, F, cp, omega, T, cache):
    """How far statuses `trial` miss consistency at z (0: consistent; module docstring): a stuck force
    beyond its static band or on its edge moving out (g = mus -+ lambda, the mode's event rows), a
    released contact (at zero relative velocity) not accelerating in its slip direction (g = sig u');
    judged by the first derivative not zero to rounding, so that two contacts whose forces reach their
    bands together (static = kinetic friction: no jump in force, u'' = 0 at the break-away) are told by
    the next derivatives. The derivatives come from the mode cache's event rows where the trial mode is
    there or a slot is free (it is built there: a trial is mostly a mode the orbit enters, or one tried
    again at the next switch, period after period), else from rows built aside (a full cache: trials
    evict nothing)."""
    ws = cache[W_SWITCH]
    # not in the cache (_cached_violation): built there where a slot is free
    i = lookup(trial, Minv, K, C, W, F, cp, omega, T, cache) if cache[C_COUNTS][0] < CACHE else -1
    if i >= 0:
        if not cache[C_OK][i]:
            return np.inf
        return _rows_violation(trial, Z, nz, z, cache[C_CK][i], ws[3])
    A = cache[W_ATMP]
    L = cache[W_LTMP]
    if not build_mode(trial, Minv, K, C, W, F, cp, omega, A, L, ws):
        return np.inf
    event_rows(trial, W, cp, omega, L, z.shape[0], ws[7], ws[8])
    event_powers(ws[7], ws[8], A, ws[2])
    return _rows_violation(trial, Z, nz, z, ws[2], ws[3])


@jit
def _cached_violation(trial, Z, nz, z, c_st, c_cnt, c_ok, c_ck, dd):
    """_violation where the trial mode is in the cache (its C_ST, C_COUNTS, C_OK, C_CK), -1 where it is not:
    a call that carries only these arrays, where one with the whole cache tuple costs about a microsecond
    (numba counts a reference to each of its arrays in and out)."""
    i = find(trial, c_st, c_cnt)
    if i < 0:
        return -1.0
    return _rows_violation(trial, Z, nz, z, c_ck[i], dd) if c_ok[i] else np.inf


@jit
def resolve(z, st, j0, sig0, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache):
    """The rigid contacts' new statuses at a switch of contact j0 (sig0 != 0: j0 breaks away that way;
    j0 < 0: the start), projecting z and filling the reset R (the cache's W_R); False where the projection
    fails. The relative velocities of the contacts at zero (Z) are projected to zero first; then the present
    statuses with j0's switch (stuck, or slipping sig0) are kept if consistent; else the enumeration of the
    module docstring (each trial costs one unit of budget). cache: the point's mode cache (new_cache: the
    trials' modes, T the period its step lengths are built for, and the workspaces; nothing allocated)."""
    m = W.shape[0]
    n = W.shape[1]
    N = z.shape[0]
    ws = cache[W_SWITCH]
    R = cache[W_R]
    c_st, c_cnt, c_ok, c_ck = cache[C_ST], cache[C_COUNTS], cache[C_OK], cache[C_CK]
    Z = ws[4]
    nz = 0
    vscale = 0.0
    for i in range(n):
        vscale = max(vscale, abs(z[n + i]) + omega * abs(z[i]))
    for j in range(m):
        vscale = max(vscale, omega * abs(cp[j, CP_EY]))
    for j in range(m):
        if cp[j, CP_KT] > 0.0 or st[j] == INACTIVE:
            continue
        if j == j0 or st[j] == STUCK or abs(rel_velocity(z, W, cp, j, n, N, omega)) <= vtol * vscale:
            Z[nz] = j
            nz += 1
    if not _project(z, Z, nz, Minv, W, cp, omega, R, ws[0]):
        return False
    trial = ws[5][:m]
    trial[:] = st
    if j0 >= 0:
        trial[j0] = STUCK if sig0 == 0 else sig0
        bad = _cached_violation(trial, Z, nz, z, c_st, c_cnt, c_ok, c_ck, ws[3])
        if bad < 0.0:
            bad = _violation(trial, Z, nz, z, Minv, K, C, W, F, cp, omega, T, cache)
        if bad == 0.0:
            st[:] = trial
            return True
    best = ws[6][:m]
    best[:] = st
    best_bad = np.inf
    found = False
    total = 1
    for _ in range(nz):
        total *= 3
    for nst in range(nz, -1, -1):
        for code in range(total):
            c = code
            cnt = 0
            for a in range(nz):
                digit = c % 3
                c //= 3
                trial[Z[a]] = STUCK if digit == 0 else (1 if digit == 1 else -1)
                if digit == 0:
                    cnt += 1
            if cnt != nst:
                continue
            if sig0 != 0 and trial[j0] != sig0:
                continue
            budget[0] -= 1
            bad = _cached_violation(trial, Z, nz, z, c_st, c_cnt, c_ok, c_ck, ws[3])
            if bad < 0.0:
                bad = _violation(trial, Z, nz, z, Minv, K, C, W, F, cp, omega, T, cache)
            if bad == 0.0:
                best[:] = trial
                found = True
                break
            if bad < best_bad:
                best_bad = bad
                best[:] = trial
        if found or budget[0] < 0:
            break
    st[:] = best
    return True


@jit
def _taylor_at(zk, col, s):
    """Component col of z(s) = sum_k zk[k] s^k / k! (s within one step)."""
    acc = 0.0
    c = 1.0
    for k in range(zk.shape[0]):
        acc += c * zk[k, col]
        c *= s / (k + 1)
    return acc


@jit
def _node_states(zk, s, zq, coef):
    """zq[q] = z(x_q s) at the Gauss nodes x_q and zq[-1] = z(s), each sum_k zk[k] (x s)^k / k! as
    taylor_state forms it (the same coefficients, summed in the same order: bit for bit its values), but
    with the coefficients of all nodes formed first (coef) and each component summed in a register: the
    per-node loop kept the division chain and a store per term on its critical path."""
    nq = GAUSS_X.shape[0]
    K1 = zk.shape[0]
    for q in range(nq + 1):
        x = s if q == nq else GAUSS_X[q] * s
        c = 1.0
        for k in range(K1):
            coef[q, k] = c
            c *= x / (k + 1)
    for q in range(nq + 1):
        for i in range(zk.shape[1]):
            acc = 0.0
            for k in range(K1):
                acc += coef[q, k] * zk[k, i]
            zq[q, i] = acc


@jit
def _measure_step(zk, s, n, m, st, W, cp, N, omega, harm, xmax, mc, Lm, Cmat, F, zq, coef):
    """Add one step (Taylor coefficients zk, length s) to the measurement; harm[:, 2] and harm[:, 3] (first
    rows) gather the excitation's work and the viscous dissipation (see energy_work); zq: a workspace for
    the state at the Gauss nodes and at s (the extremes' search reads its velocities there); coef:
    _node_states's workspace."""
    _node_states(zk, s, zq, coef)
    _measure_nodes(zk, True, zk, zk[0], s, n, m, st, W, cp, N, omega, harm, xmax, mc, Lm, Cmat, F, zq)


#: a mode's node matrices cost about 16 N^3 to build and save about 8 N^2 on each full measured step (the
#: KT matrix-vector products of powers and the nodes' Taylor sums, against one product per node): they are
#: built where one measured period of the mode has more full steps than NODES_PAY x N
NODES_PAY = 2.0


@jit
def _node_matrices(h, T, N):
    """Whether the measurement of a mode's full steps (length h) goes through its node matrices
    G[q] = exp(A x_q h) (zq[q] = G[q] z; advance builds them once per mode, in the cache): where a period
    holds enough of its steps to repay them (NODES_PAY)."""
    return T / h > NODES_PAY * N


@jit
def _node_products(G, z, zq):
    """zq[q] = G[q] z for every Gauss node q (matvec's sums, in its order): one loop, where a matvec call per
    node made a view of G[q] and of zq[q] each, whose reference counting cost twice the products."""
    N = z.shape[0]
    for q in range(GAUSS_X.shape[0]):
        for i in range(N):
            acc = 0.0
            for k in range(N):
                acc += G[q, i, k] * z[k]
            zq[q, i] = acc


@jit_inline
def _measure_nodes(zk, have, A, z, s, n, m, st, W, cp, N, omega, harm, xmax, mc, Lm, Cmat, F, zq):
    """_measure_step's body from the states at the nodes and at s (zq); zk: the step's Taylor coefficients
    where `have`, else a workspace that powers(A, z, zk) fills the first time a refinement needs them (a
    velocity's zero, a Jenkins stick's reversal, a creep's drive)."""
    nq = GAUSS_X.shape[0]
    for q in range(nq):
        zt = zq[q]
        wq = GAUSS_W[q] * s
        for i in range(n):
            harm[i, 0] += wq * zt[i] * zt[N - 3]
            harm[i, 1] += wq * zt[i] * zt[N - 2]
        # the excitation's work: f_ext . v, plus the contacts' work on the moving base
        pin = 0.0
        for i in range(n):
            pin += (F[0, i] * zt[N - 3] + F[1, i] * zt[N - 2]) * zt[n + i]
        for j in range(m):
            if st[j] != INACTIVE and cp[j, CP_EY] != 0.0:
                pin += dot(Lm[j], zt) * cp[j, CP_EY] * omega * zt[N - 2]
        vis = 0.0
        for i in range(n):
            for k in range(n):
                vis += zt[n + i] * Cmat[i, k] * zt[n + k]
        harm[0, 2] += wq * pin
        harm[0, 3] += wq * vis
    # extremes: at both ends and at every zero of v_i (sampled at the nodes, refined by bisection to
    # 2^-_EXTREME_HALVINGS of the node interval: x is stationary there, so its value is then exact to
    # rounding, the root's error entering squared)
    for i in range(n):
        prev_s = 0.0
        prev_v = z[n + i]
        xmax[i] = max(xmax[i], abs(z[i]))
        for q in range(nq + 1):
            sq = s if q == nq else GAUSS_X[q] * s
            v = zq[q, n + i]
            if (prev_v > 0.0 and v < 0.0) or (prev_v < 0.0 and v > 0.0):
                if not have:
                    powers(A, z, zk)
                    have = True
                lo = prev_s
                hi = sq
                for _ in range(_EXTREME_HALVINGS):
                    mid = 0.5 * (lo + hi)
                    vm = _taylor_at(zk, n + i, mid)
                    if (vm > 0.0) == (prev_v > 0.0):
                        lo = mid
                    else:
                        hi = mid
                xmax[i] = max(xmax[i], abs(_taylor_at(zk, i, 0.5 * (lo + hi))))
            prev_v = v
            prev_s = sq
        xmax[i] = max(xmax[i], abs(zq[nq, i]))
    _measure_contacts(zk, have, A, z, s, zq[nq], n, m, st, W, cp, N, omega, mc)


@jit
def _driven_step(zk, s, j, sig, n, W, cp, N, omega):
    """Whether the load drives contact j's slip (direction sig) somewhere on a step (Taylor coefficients
    zk, length s): sig u'' > 0, the relative acceleration under kinetic friction (jenkins._driven's test,
    sig q'' > 0, for a structure). u'' is sampled _DRIVEN_SAMPLES times and its largest sample's
    bracket refined by golden section."""
    K1 = zk.shape[0]
    a = np.empty(K1)  # Taylor coefficients of u'
    for k in range(K1):
        a[k] = cp[j, CP_EY] * omega * zk[k, N - 2] + W[j] @ zk[k, n:2 * n]
    h = s / _DRIVEN_SAMPLES
    best = -np.inf
    jbest = 0
    for q in range(_DRIVEN_SAMPLES + 1):
        f = sig * _u2(a, q * h)
        if f > 0.0:
            return True
        if f > best:
            best = f
            jbest = q
    lo = max(0.0, (jbest - 1) * h)
    hi = min(s, (jbest + 1) * h)
    g = (np.sqrt(5.0) - 1.0) / 2.0
    for _ in range(_DRIVEN_REFINE):
        x1 = hi - g * (hi - lo)
        x2 = lo + g * (hi - lo)
        f1 = sig * _u2(a, x1)
        f2 = sig * _u2(a, x2)
        if f1 > 0.0 or f2 > 0.0:
            return True
        if f1 >= f2:
            hi = x2
        else:
            lo = x1
    return False


@jit
def _u2(a, x):
    """u''(x) from u''s Taylor coefficients a (u'(x) = sum_k a[k] x^k / k!)."""
    acc = 0.0
    c = 1.0
    for k in range(1, a.shape[0]):
        acc += c * a[k]
        c *= x / k
    return acc


@jit_inline
def _measure_contacts(zk, have, A, z0, s, zend, n, m, st, W, cp, N, omega, mc):
    """Add one step (start state z0, length s, end state zend; Taylor coefficients zk where `have`, else
    powers(A, z0, zk) when a refinement needs them) to the per-contact measures mc: stuck time, sliding
    energy, a held Jenkins stick's reversal (its stop)."""
    K1 = zk.shape[0]
    for j in range(m):
        if st[j] == INACTIVE:
            continue
        if st[j] == STUCK:
            if cp[j, CP_KT] <= 0.0 or mc[j, MC_HELD] == 1.0:
                mc[j, MC_STUCK] += s
            else:
                # a Jenkins stick holds the mass from where u' returns to zero (its sign after the stick
                # was MC_SIGN); that instant is refined on u's Taylor polynomial over the step
                u1 = rel_velocity(zend, W, cp, j, n, N, omega)
                if mc[j, MC_SIGN] != 0.0 and u1 * mc[j, MC_SIGN] <= 0.0:
                    if not have:
                        powers(A, z0, zk)
                        have = True
                    lo = 0.0
                    hi = s
                    for _ in range(60):
                        mid = 0.5 * (lo + hi)
                        um = 0.0
                        c = 1.0
                        for k in range(K1):
                            um += c * (cp[j, CP_EY] * omega * zk[k, N - 2] + W[j] @ zk[k, n:2 * n])
                            c *= mid / (k + 1)
                        if um * mc[j, MC_SIGN] > 0.0:
                            lo = mid
                        else:
                            hi = mid
                    mc[j, MC_HELD] = 1.0
                    mc[j, MC_STOPS] += 1.0
                    mc[j, MC_STUCK] += s - hi
        else:
            if cp[j, CP_KT] > 0.0:
                slot = 2 * n + int(cp[j, CP_SLOT])
                mc[j, MC_ENERGY] += cp[j, CP_MU] * abs(zend[slot] - z0[slot])
                if mc[j, MC_ANCHOR] == 1.0:
                    if not have:
                        powers(A, z0, zk)
                        have = True
                    if _driven_step(zk, s, j, st[j], n, W, cp, N, omega):
                        mc[j, MC_ANCHOR] = 0.0
            else:
                mc[j, MC_ENERGY] += cp[j, CP_MU] * abs(rel_position(zend, W, cp, j, n, N)
                                                       - rel_position(z0, W, cp, j, n, N))


@jit
def _jac_step(M, J, tmp):
    """J <- M J on its dynamic block (tmp: a workspace of J's shape). J = dz(t)/dz_dyn(0) has Nd =
    J.shape[1] columns, and its rows past Nd (the forcing's cos, sin and 1, which no start state moves)
    are zero and stay so: every transition matrix exp(A s) has a zero forcing-by-dynamic block, every
    reset R and saltation matrix S the identity's forcing rows (f+ and R f- agree there). So only M's
    dynamic block is read: the products it leaves out are exact zeros, the sums are matmul's, bit for bit."""
    Nd = J.shape[1]
    for i in range(Nd):
        for c in range(Nd):
            tmp[i, c] = 0.0
        for k in range(Nd):
            a = M[i, k]
            if a != 0.0:
                for c in range(Nd):
                    tmp[i, c] += a * J[k, c]
    for i in range(Nd):
        for c in range(Nd):
            J[i, c] = tmp[i, c]


@jit
def _identity(R):
    R[:, :] = 0.0
    for i in range(R.shape[0]):
        R[i, i] = 1.0


@jit
def switch(z, st, mi, fired, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas, mc):
    """The switch at event function `fired` of cached mode mi, z at the event (both in place): the next
    mode from the forces (the rules in this module's docstring), the per-contact labels where meas, and
    J <- S J (the saltation) where jac; jflag[1 + q] = 1 for each contact q it changes. False where it fails
    (dependent constraints, a mode that cannot be built). Shared by advance and the rk4 stepper (rk4.py)."""
    c_A, c_rows, c_ok, c_cnt = cache[C_A], cache[C_ROWS], cache[C_OK], cache[C_COUNTS]
    znew, R, Jtmp, fv, crow, before, S, sw = (cache[W_ZNEW], cache[W_R], cache[W_JTMP], cache[W_FV], cache[W_CROW],
                                             cache[W_BEFORE], cache[W_S], cache[W_SWITCH])
    n = K.shape[0]
    m = W.shape[0]
    N = z.shape[0]
    A = c_A[mi]
    j = fired // 2
    fminus = fv[0]
    matvec(A, z, fminus)
    crow[:] = c_rows[mi, fired]
    old = st[j]
    before[:m] = st
    sig = 0
    if old != STUCK:
        if cp[j, CP_KT] > 0.0:
            st[j] = STUCK
            # its relative velocity set to zero exactly (as a rigid stick's): the root leaves a rounding
            # residue that the stuck slider's first derivative kt u' would read as a release at once
            Zj = sw[4]
            Zj[0] = j
            if not _project(z, Zj, 1, Minv, W, cp, omega, R, sw[0]):
                return False
            if meas:
                if mc[j, MC_ANCHOR] == 1.0:
                    # a creep: a slip from a held stick that the load never drove (the mass coasted
                    # on the contact spring's swing); the contact still holds the mass, no new stop
                    mc[j, MC_HELD] = 1.0
                else:
                    # right after the stick u' has the sign opposite to the slip's (it decelerated
                    # to zero); a stop once it returns to zero
                    mc[j, MC_HELD] = 0.0
                    mc[j, MC_SIGN] = -old
                mc[j, MC_ANCHOR] = 0.0
        else:
            if not resolve(z, st, j, 0, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache):
                return False
    else:
        sig = 1 if fired % 2 == 0 else -1
        if cp[j, CP_KT] > 0.0:
            st[j] = sig
            _identity(R)
            slot = 2 * n + int(cp[j, CP_SLOT])
            kt = cp[j, CP_KT]
            R[slot, :] = 0.0
            for i in range(n):
                R[slot, i] = W[j, i]
            R[slot, N - 3] = -cp[j, CP_EY]
            R[slot, N - 1] = -sig * cp[j, CP_MU] / kt
            matvec(R, z, znew)
            z[:] = znew
            if meas:
                mc[j, MC_SLIPS] += 1.0
                # a slip from a held stick is a creep until the load drives it (_driven_step)
                mc[j, MC_ANCHOR] = mc[j, MC_HELD]
                mus = cp[j, CP_MUS]
                mu = cp[j, CP_MU]
                mc[j, MC_ENERGY] += (mus * mus - mu * mu) / (2.0 * kt)
        else:
            if not resolve(z, st, j, sig, Minv, K, C, W, F, cp, omega, T, vtol, budget, cache):
                return False
    if meas:
        for q in range(m):
            if cp[q, CP_KT] <= 0.0 and st[q] == STUCK and before[q] != STUCK:
                mc[q, MC_STOPS] += 1.0
    # the contacts this switch changed (jflag[1 + q], read by the steady search: a contact no switch of a pass
    # touched and stuck at its start was stuck all the pass)
    for q in range(m):
        if st[q] != before[q]:
            jflag[1 + q] = 1.0
    if jac:
        mj = find(st, cache[C_ST], c_cnt)
        if mj < 0:
            mj = lookup(st, Minv, K, C, W, F, cp, omega, T, cache)
        if not c_ok[mj]:
            return False
        fplus = fv[1]
        Rf = fv[2]
        matvec(c_A[mj], z, fplus)
        matvec(R, fminus, Rf)
        den = dot(crow, fminus)
        if abs(den) <= 1e-9 * (np.sqrt(dot(fminus, fminus)) * np.sqrt(dot(crow, crow))):
            jflag[0] = 0.0
        else:
            for a in range(N):
                for b in range(N):
                    S[a, b] = R[a, b] + (fplus[a] - Rf[a]) * crow[b] / den
            _jac_step(S, J, Jtmp)
    return True


@jit
def advance(z, st, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas, harm, xmax, mc, fou):
    """Carry z (in place) over [0, T] from mode st (in place); budget[0]: events and steps left.
    Returns OK, BUDGET or FAILED. fou: None (a compile-time choice: the steady search compiles none of it),
    or fourier.new_fourier's record, to which every step adds its exact Fourier integrals."""
    c_st, c_A, c_E, c_L, c_rows, c_ck, c_act, c_h, c_ok, c_cnt = cache[:10]
    zk, znew, d, dmag, R, Atmp, Ltmp, Jtmp, Jtmp2, fv, crow, before, S, zq, coef, c_G, c_gok, sw = cache[10:]
    n = K.shape[0]
    m = W.shape[0]
    N = z.shape[0]
    t = 0.0
    while t < T:
        mi = find(st, c_st, c_cnt)
        if mi < 0:
            mi = lookup(st, Minv, K, C, W, F, cp, omega, T, cache)
        if not c_ok[mi]:
            return FAILED
        A = c_A[mi]
        E = c_E[mi]
        h = c_h[mi]
        start = True
        fired = -1
        while t < T:
            budget[0] -= 1
            if budget[0] < 0:
                return BUDGET
            s = min(h, T - t)
            full = s == h
            have_zk = False
            if full:
                matvec(E, z, znew)
            else:
                powers(A, z, zk)
                have_zk = True
                taylor_state(zk, s, znew)
            se = -1.0
            for f in range(2 * m):
                if not c_act[mi, f]:
                    continue
                ck = c_ck[mi, f]
                ga = dot(ck[0], z)
                g1a = dot(ck[1], z)
                gb = dot(ck[0], znew)
                if gb > 0.0 and ga > 0.0:
                    B = 0.0
                    c = 1.0
                    for k in range(_QUICK):
                        B += abs(dot(ck[k + 2], z)) * c
                        c *= s / (k + 1)
                    B *= _QUICK_MARGIN
                    gae = max(ga, 0.0)
                    if ga > 0.0 and min(ga, gb) > 0.125 * B * s * s:
                        continue
                    if gae + g1a * s - 0.5 * B * s * s > 0.0:
                        continue
                for k in range(KT + 1):
                    d[k] = dot(ck[k], z)
                term_sizes(ck, z, dmag)
                r = first_root(d, dmag, s, start)
                if r >= 0.0 and (se < 0.0 or r < se):
                    se = r
                    fired = f
            if se < 0.0:
                if meas:
                    if full and not have_zk and _node_matrices(h, T, N):
                        if not c_gok[mi]:
                            expm_nodes(A, h, GAUSS_X, c_G[mi])
                            c_gok[mi] = True
                        _node_products(c_G[mi], z, zq)
                        zq[GAUSS_X.shape[0], :] = znew
                        _measure_nodes(zk, False, A, z, s, n, m, st, W, cp, N, omega, harm, xmax, mc, c_L[mi], C, F,
                                       zq)
                    else:
                        if not have_zk:
                            powers(A, z, zk)
                        _measure_step(zk, s, n, m, st, W, cp, N, omega, harm, xmax, mc, c_L[mi], C, F, zq, coef)
                if fou is not None:
                    if not have_zk:
                        powers(A, z, zk)
                    fourier_step(fou, zk, s, full, mi, h, st, c_L[mi], n, m, N, omega)
                if jac:
                    if full:
                        _jac_step(E, J, Jtmp)
                    else:
                        expm_apply(A, s, J, Jtmp, Jtmp2)
                z[:] = znew
                t = T if s == T - t or T - (t + s) <= 1e-15 * T else t + s
                start = False
                for i in range(N):
                    if not np.isfinite(z[i]):
                        return FAILED
                continue
            # an event at t + se
            if not have_zk:
                powers(A, z, zk)
            taylor_state(zk, se, znew)
            if meas:
                _measure_step(zk, se, n, m, st, W, cp, N, omega, harm, xmax, mc, c_L[mi], C, F, zq, coef)
            if fou is not None:
                fourier_step(fou, zk, se, False, mi, h, st, c_L[mi], n, m, N, omega)
            if jac:
                expm_apply(A, se, J, Jtmp, Jtmp2)
            z[:] = znew
            t += se
            break
        if fired < 0:
            break
        # the switch
        if not switch(z, st, mi, fired, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, jac, J, jflag, meas,
                      mc):
            return FAILED
    return OK
