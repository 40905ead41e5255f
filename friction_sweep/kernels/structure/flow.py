"""One mode of a structure: its augmented matrix, its contact forces, its event functions, its exact flow.

The state is z = (x, v, p, cos wt, sin wt, 1): n absolute displacements x, their velocities v, the
positions p of the Jenkins sliders (one slot per contact with a stiffness), and the forcing written as an
oscillator. Contact j acts on u_j = w_j.x - ey_j cos wt (ey_j: the base amplitude where its other end is
the base), with force lambda_j on it (the masses feel -w_j lambda_j):

- slipping in direction sig (st = +-1): lambda = sig mu (kinetic), a constant;
- stuck Jenkins (st = 0, stiffness kt): lambda = kt (u - p), p' = 0; slipping Jenkins: p' = u';
- stuck rigid (st = 0): u'' = 0, lambda the constraint force: with f = F(z) the other forces and the
  stuck set S, G = W_S M^-1 W_S^T, lambda_S = G^-1 (W_S M^-1 f + ey_S w^2 cos wt), linear in z;
- without friction (st = INACTIVE): no force, no event.

Then M v' = f - W_S^T lambda_S, so z' = A z with a constant A (rows of x: v; of v: the accelerations;
of p: u' for a slipping slider; cos, sin: the rotation; 1: zero), and z(t) = exp(A t) z(0) exactly: at
resonance, with a singular stiffness, with or without damping (nothing divides by K - w^2 M).
exp(A h) is the Taylor series on steps short against every rate of A (|A| h <= 1/2 in the mode's scale,
so the series converges like 2^-k / k! and is exact to rounding); longer times are products or squares.

Event functions (2 slots per contact, g >= 0 while the mode holds): slipping, g = sig u'; stuck,
g = mus - lambda and g = mus + lambda (a rigid contact's mus times 1 + TIE_RTOL: a force that reaches the band
only to within the tie stays stuck, as the 1-DoF kernels decide it, ties.py).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.ties import TIE_RTOL

#: contact status codes (st): stuck 0, slipping +1 / -1, and no friction
STUCK = 0
INACTIVE = 2
#: columns of a contact's parameter row
CP_EY, CP_MU, CP_MUS, CP_KT, CP_SLOT = 0, 1, 2, 3, 4
CP_SIZE = 5
#: Taylor terms kept for an event function on one step (|A h| <= 1/2: the next term is below 2^-17/17!)
KT = 16
#: the step against the mode's fastest rate. Not longer: a Jenkins contact's labels (a held stick's return of
#: u' to zero, a creep's drive) are read at the step's ends and samples, and at |A| h <= 1 (KT 20) the 10-mass
#: chain at w 0.5, scale 2 lost its stick-slip label (2 stops a period, against the independent integrator's)
STEP_RATE = 0.5


@jit
def solve_small(G, B, X):
    """X = G^-1 B by Gaussian elimination with partial pivoting (G s x s, B s x N); False where G is
    singular to rounding (dependent stuck contacts), X untouched then. G and B are overwritten (the
    callers build them afresh in a workspace each time: no copies)."""
    s = G.shape[0]
    N = B.shape[1]
    a = G
    b = B
    scale = 0.0
    for i in range(s):
        for k in range(s):
            scale = max(scale, abs(a[i, k]))
    if scale == 0.0:
        return False
    for c in range(s):
        piv = c
        for i in range(c + 1, s):
            if abs(a[i, c]) > abs(a[piv, c]):
                piv = i
        if abs(a[piv, c]) <= 1e-12 * scale:
            return False
        if piv != c:
            for k in range(s):
                a[c, k], a[piv, k] = a[piv, k], a[c, k]
            for k in range(N):
                b[c, k], b[piv, k] = b[piv, k], b[c, k]
        for i in range(c + 1, s):
            f = a[i, c] / a[c, c]
            if f != 0.0:
                for k in range(c, s):
                    a[i, k] -= f * a[c, k]
                for k in range(N):
                    b[i, k] -= f * b[c, k]
    for c in range(s - 1, -1, -1):
        for k in range(N):
            acc = b[c, k]
            for i in range(c + 1, s):
                acc -= a[c, i] * X[i, k]
            X[c, k] = acc / a[c, c]
    return True


@jit
def mode_workspace(n, m, N):
    """build_mode's (and the switch's projection's) workspace: one float buffer holding every matrix it
    needs for any stuck set (sliced and reshaped, no copy), one int buffer for the stuck set; built once
    per point, so that a mode build allocates nothing."""
    m1 = max(m, 1)
    return np.empty(2 * n * N + 2 * n * m1 + m1 * m1 + 2 * m1 * N + N), np.empty(m1, dtype=np.int64)


@jit
def build_mode(st, Minv, K, C, W, F, cp, omega, A, L, ws):
    """Fill A (N x N) and the contact-force rows L (m x N, lambda_j = L_j . z) of mode st; False where
    the stuck rigid directions are dependent. ws: a mode_workspace."""
    n = K.shape[0]
    m = W.shape[0]
    N = A.shape[0]
    V0 = n
    P0 = 2 * n
    IC = N - 3
    IS = N - 2
    I1 = N - 1
    A[:, :] = 0.0
    L[:, :] = 0.0
    fb = ws[0]
    Fz = fb[:n * N].reshape((n, N))
    Fz[:, :] = 0.0
    for i in range(n):
        for k in range(n):
            Fz[i, k] = -K[i, k]
            Fz[i, V0 + k] = -C[i, k]
        Fz[i, IC] = F[0, i]
        Fz[i, IS] = F[1, i]
    ns = 0
    for j in range(m):
        s = st[j]
        if s == INACTIVE:
            continue
        kt = cp[j, CP_KT]
        if s != STUCK:
            f = s * cp[j, CP_MU]
            L[j, I1] = f
            for i in range(n):
                Fz[i, I1] -= f * W[j, i]
        elif kt > 0.0:
            slot = P0 + int(cp[j, CP_SLOT])
            ey = cp[j, CP_EY]
            for i in range(n):
                L[j, i] = kt * W[j, i]
                for k in range(n):
                    Fz[i, k] -= kt * W[j, i] * W[j, k]
                Fz[i, IC] += kt * ey * W[j, i]
                Fz[i, slot] += kt * W[j, i]
            L[j, IC] = -kt * ey
            L[j, slot] = -kt
        else:
            ns += 1
    o = n * N
    MF = fb[o:o + n * N].reshape((n, N))
    o += n * N
    matmul(Minv, Fz, MF)
    if ns > 0:
        idx = ws[1][:ns]
        c = 0
        for j in range(m):
            if st[j] == STUCK and cp[j, CP_KT] <= 0.0:
                idx[c] = j
                c += 1
        # G = W_S M^-1 W_S^T, rhs = W_S M^-1 f (+ the base's acceleration), lambda_S = G^-1 rhs
        MW = fb[o:o + n * ns].reshape((n, ns))
        o += n * ns
        for i in range(n):
            for a in range(ns):
                acc = 0.0
                for k in range(n):
                    acc += Minv[i, k] * W[idx[a], k]
                MW[i, a] = acc
        G = fb[o:o + ns * ns].reshape((ns, ns))
        o += ns * ns
        for a in range(ns):
            for b in range(ns):
                acc = 0.0
                for k in range(n):
                    acc += W[idx[a], k] * MW[k, b]
                G[a, b] = acc
        rhs = fb[o:o + ns * N].reshape((ns, N))
        o += ns * N
        for a in range(ns):
            for k in range(N):
                acc = 0.0
                for i in range(n):
                    acc += W[idx[a], i] * MF[i, k]
                rhs[a, k] = acc
            rhs[a, IC] += cp[idx[a], CP_EY] * omega * omega
        lam = fb[o:o + ns * N].reshape((ns, N))
        if not solve_small(G, rhs, lam):
            return False
        for i in range(n):
            for k in range(N):
                acc = 0.0
                for a in range(ns):
                    acc += MW[i, a] * lam[a, k]
                MF[i, k] -= acc
        for a in range(ns):
            L[idx[a], :] = lam[a, :]
    for i in range(n):
        A[i, V0 + i] = 1.0
        for k in range(N):
            A[V0 + i, k] = MF[i, k]
    for j in range(m):
        if cp[j, CP_KT] > 0.0 and st[j] != STUCK and st[j] != INACTIVE:
            slot = P0 + int(cp[j, CP_SLOT])
            for i in range(n):
                A[slot, V0 + i] = W[j, i]
            A[slot, IS] = cp[j, CP_EY] * omega
    A[IC, IS] = -omega
    A[IS, IC] = omega
    return True


@jit
def event_rows(st, W, cp, omega, L, N, rows, active):
    """The mode's event functions g = rows[f] . z (2 slots per contact; active[f] where one is armed)."""
    n = W.shape[1]
    m = W.shape[0]
    rows[:, :] = 0.0
    active[:] = False
    for j in range(m):
        s = st[j]
        if s == INACTIVE:
            continue
        if s != STUCK:
            for i in range(n):
                rows[2 * j, n + i] = s * W[j, i]
            rows[2 * j, N - 2] = s * cp[j, CP_EY] * omega
            active[2 * j] = True
        else:
            # a rigid contact's band edge is a tie (ties.py): a force that reaches it to within TIE_RTOL, as at
            # beta = A where the forcing's swing touches it tangentially, leaves the contact stuck (the stuck
            # force's rounding would otherwise decide: a slip of 1e-8 of a period, 2 stops where none is). Not
            # a Jenkins slider's: one sticks with its force on the edge (mu_s = mu), and whether it slips again
            # at once is the motion's, not a tie (the 1-DoF kernel's slips)
            mus = cp[j, CP_MUS] * (1.0 + TIE_RTOL) if cp[j, CP_KT] <= 0.0 else cp[j, CP_MUS]
            for k in range(N):
                rows[2 * j, k] = -L[j, k]
                rows[2 * j + 1, k] = L[j, k]
            rows[2 * j, N - 1] += mus
            rows[2 * j + 1, N - 1] += mus
            active[2 * j] = True
            active[2 * j + 1] = True


@jit
def mode_rate(A, n):
    """The mode's fastest rate: the forcing frequency, sqrt of the stiffness rows, the damping rows (inf norms)."""
    N = A.shape[0]
    rate = abs(A[N - 2, N - 3])
    kx = 0.0
    cv = 0.0
    kp = 0.0
    for i in range(n):
        a = 0.0
        b = 0.0
        c = 0.0
        for k in range(n):
            a += abs(A[n + i, k])
            b += abs(A[n + i, n + k])
        for k in range(2 * n, N - 3):
            c += abs(A[n + i, k])
        kx = max(kx, a)
        cv = max(cv, b)
        kp = max(kp, c)
    for r in range(2 * n, N - 3):
        for k in range(n, 2 * n):
            kp = max(kp, abs(A[r, k]))
    rate = max(rate, np.sqrt(kx), cv, np.sqrt(kp))
    return max(rate, 1e-300)


@jit
def matvec(A, z, out):
    """out = A z, a plain loop: numba's `@` on these tiny arrays calls BLAS and allocates its result,
    which costs more than the product."""
    for i in range(A.shape[0]):
        acc = 0.0
        for k in range(A.shape[1]):
            acc += A[i, k] * z[k]
        out[i] = acc


@jit
def dot(a, b):
    """a . b, a plain loop (as matvec)."""
    acc = 0.0
    for k in range(a.shape[0]):
        acc += a[k] * b[k]
    return acc


@jit
def matmul(A, B, out):
    """out = A B (out distinct from A and B), a plain loop (as matvec)."""
    for i in range(A.shape[0]):
        for c in range(B.shape[1]):
            out[i, c] = 0.0
        for k in range(A.shape[1]):
            a = A[i, k]
            if a != 0.0:
                for c in range(B.shape[1]):
                    out[i, c] += a * B[k, c]


@jit
def sparsity(A, cols, starts):
    """The nonzero columns of each row of A: cols[starts[r]:starts[r + 1]] (a mode's A is mostly zeros:
    the x rows hold one 1, the slider and forcing rows a few entries, the last row none)."""
    at = 0
    for r in range(A.shape[0]):
        starts[r] = at
        for c in range(A.shape[1]):
            if A[r, c] != 0.0:
                cols[at] = c
                at += 1
    starts[A.shape[0]] = at


@jit
def expm_taylor(A, h, E):
    """E = exp(A h) by its Taylor series, for h short against A's rates (expm_nodes at the one fraction 1)."""
    expm_nodes(A, h, _ONE, E.reshape((1, E.shape[0], E.shape[1])))


#: expm_taylor's one node fraction
_ONE = np.ones(1)


@jit
def expm_nodes(A, h, xs, G):
    """G[q] = exp(A xs[q] h) for every fraction xs[q] in (0, 1] by one Taylor series, for h short against
    A's rates (terms fall like (|A| h)^k / k!): G_q = sum_k xs_q^k T_k, T_0 = I, T_k = T_{k-1} (A h) / k,
    up to the first T_k below 1e-18 of the largest sum (the nodes below 1 have converged by then); the
    products skip A's zeros. At the one fraction 1 this is exp(A h) term for term (x^k = 1 exactly)."""
    N = A.shape[0]
    nq = xs.shape[0]
    cols = np.empty(N * N, dtype=np.int64)
    starts = np.empty(N + 1, dtype=np.int64)
    sparsity(A, cols, starts)
    term = np.zeros((N, N))
    nxt = np.empty((N, N))
    xk = np.ones(nq)
    G[:, :, :] = 0.0
    for q in range(nq):
        for i in range(N):
            G[q, i, i] = 1.0
    for i in range(N):
        term[i, i] = 1.0
    for k in range(1, 80):
        f = h / k
        nxt[:, :] = 0.0
        for i in range(N):
            for q in range(N):
                t = term[i, q]
                if t != 0.0:
                    t *= f
                    for e in range(starts[q], starts[q + 1]):
                        c = cols[e]
                        nxt[i, c] += t * A[q, c]
        for q in range(nq):
            xk[q] *= xs[q]
        big = 0.0
        tot = 0.0
        for i in range(N):
            for c in range(N):
                v = nxt[i, c]
                term[i, c] = v
                big = max(big, abs(v))
                for q in range(nq):
                    G[q, i, c] += xk[q] * v
                    tot = max(tot, abs(G[q, i, c]))
        if big <= 1e-18 * tot:
            break


@jit
def expm_apply(A, s, J, Y, Z):
    """J <- exp(A s) J without forming exp(A s) (s within a step): the Taylor series applied to J's
    columns, Y_0 = J, Y_k = (s / k) A Y_{k-1}, J <- sum_k Y_k, up to the first Y_k below 1e-18 of the sum
    (the criterion of expm_taylor); Y, Z: workspaces of J's shape. A's zeros are skipped: for a partial
    step this costs about a third of expm_taylor followed by the product."""
    N = A.shape[0]
    Nc = J.shape[1]
    cols = np.empty(N * N, dtype=np.int64)
    starts = np.empty(N + 1, dtype=np.int64)
    sparsity(A, cols, starts)
    Y[:, :] = J
    for k in range(1, 80):
        f = s / k
        big = 0.0
        # J's rows past Nc (the forcing's) are zero and A maps them only among themselves
        # (period._jac_step): those rows of every Y_k are zero, and the terms reading them exact zeros
        for r in range(Nc):
            for c in range(Nc):
                Z[r, c] = 0.0
            for e in range(starts[r], starts[r + 1]):
                q = cols[e]
                if q >= Nc:
                    continue
                a = A[r, q] * f
                for c in range(Nc):
                    Z[r, c] += a * Y[q, c]
        tot = 0.0
        for r in range(Nc):
            for c in range(Nc):
                v = Z[r, c]
                Y[r, c] = v
                J[r, c] += v
                big = max(big, abs(v))
                tot = max(tot, abs(J[r, c]))
        if big <= 1e-18 * tot:
            break


@jit
def expm(A, t, h, E):
    """E = exp(A t) by scaling and squaring: Taylor on t / 2^s <= h, then s squarings."""
    s = 0
    tt = t
    while tt > h:
        tt *= 0.5
        s += 1
    expm_taylor(A, tt, E)
    if s > 0:
        tmp = np.empty_like(E)
        for _ in range(s):
            matmul(E, E, tmp)
            E[:, :] = tmp


@jit
def term_sizes(ck, z, dmag):
    """dmag[k] = sum_i |ck[k, i] z[i]|, the size of the terms of an event function's k-th derivative c A^k . z
    (ck[k] = c A^k): what is zero to rounding against it (roots.at_start) is judged the same by every
    integrator."""
    for k in range(dmag.shape[0]):
        acc = 0.0
        for i in range(z.shape[0]):
            acc += abs(ck[k, i] * z[i])
        dmag[k] = acc


@jit
def powers(A, z, zk):
    """zk[k] = A^k z for k = 0..KT (the Taylor coefficients of z(t) at t = 0, times k!). The products skip A's
    zeros (sparsity): a mode's A is mostly zeros (a chain's v rows hold a few stiffnesses each), and the
    sums over the rest, in matvec's order, are matvec's bit for bit where z is finite (a skipped term is an
    exact zero)."""
    N = A.shape[0]
    cols = np.empty(N * N, dtype=np.int64)
    starts = np.empty(N + 1, dtype=np.int64)
    sparsity(A, cols, starts)
    zk[0, :] = z
    for k in range(1, zk.shape[0]):
        for i in range(N):
            acc = 0.0
            for e in range(starts[i], starts[i + 1]):
                acc += A[i, cols[e]] * zk[k - 1, cols[e]]
            zk[k, i] = acc


@jit
def taylor_state(zk, s, out):
    """z(s) = sum_k zk[k] s^k / k! (s within one step); the components are independent sums (no
    dependency chain through a division per term, as Horner's rule would have)."""
    out[:] = 0.0
    c = 1.0
    for k in range(zk.shape[0]):
        for i in range(zk.shape[1]):
            out[i] += c * zk[k, i]
        c *= s / (k + 1)
