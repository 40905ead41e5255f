"""Closed-form slip segments: the motion between events, and the search for where one ends (docs/equations.md §3).

Equation in slip direction sig = +-1 (period-local time t, forcing phase r t):

    q'' + 2 zeta q' + q + sig bk = A cos(r t)

A slip segment is written from its own start t0 in local time s = t - t0, with the forcing split as
A cos(r t0) cos(r s) - A sin(r t0) sin(r s). For zeta = 0 the responses from rest to cos(r s) and
sin(r s) are written without dividing by 1 - r^2:

    C(s)  = (cos rs - cos s)/(1 - r^2)   = 2/(1+r) sin((1+r)s/2) g(s)
    Sn(s) = (sin rs - r sin s)/(1 - r^2) = (sin s - 2 cos((1+r)s/2) g(s)) / (1+r)
    g(s)  = sin((1-r)s/2)/(1-r) = (s/2) sin(u)/u,  u = (1-r)s/2

so the kernel is exact and cancellation-free at r = 1. With viscous damping (zeta > 0, a declared
effect) the standard damped closed form is used instead; zeta == 0 never touches that branch.
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jit import jit

TWO_PI = 2.0 * math.pi
#: force differences below this fraction of A + friction + |q| are ties that rounding decides: a mass at
#: rest that the force pushes out of its band by less cannot be set moving resolvably
FORCE_TIE = 1e-13


@jit
def sin_over(u):
    """sin(u)/u, with its series near 0."""
    if abs(u) < 1e-4:
        u2 = u * u
        return 1.0 - u2 / 6.0 * (1.0 - u2 / 20.0)
    return math.sin(u) / u


#: with damping, a slip piece is summed as its Taylor series up to this local time (times max(1, r),
#: the fastest frequency in it): the closed form
#: below adds terms of the forcing's size that cancel to the motion's, so a motion far smaller than A
#: (next to the no-motion threshold) would drown in their rounding, and a stop search from rest would
#: see the velocity's sign flicker. Its terms fall like (s max(1, r))^k / k!
DAMPED_SERIES_SPAN = 0.25
DAMPED_SERIES_TERMS = 22


@jit
def _damped_series(s, q0, v0, sig, A, r, bk, zeta, ca, sa):
    """(q, v) at local time s of a damped slip piece, by the Taylor series at its start.

    Derivatives from q'' = A cos(r t0 + r s) - sig bk - q - 2 zeta q': d_{k+2} = F_k - d_k - 2 zeta d_{k+1},
    F_0 = A ca - sig bk, F_k = A r^k cos(r t0 + k pi/2) (k >= 1). The net force F_0 - q0 is formed first,
    so a tiny excess over the friction keeps its relative precision.
    """
    d_prev = q0  # d_k
    d_cur = v0  # d_{k+1}
    q = q0
    v = v0
    term = s  # s^(k+1) / (k+1)!, the weight of d_{k+1} in q
    vterm = 1.0  # s^k / k!, the weight of d_{k+1} in v
    q += d_cur * term
    rk = 1.0
    # |d_k| grows at most like max(1, r)^k, so with s max(1, r) <= DAMPED_SERIES_SPAN the k-th term is
    # below 0.25^k / k! of the state's scale: 0.25^22 / 22! ~ 1e-35. A fixed count: a term that vanishes
    # by coincidence (a derivative through zero) must not end the sum early.
    for k in range(0, DAMPED_SERIES_TERMS):
        if k == 0:
            d_next = (A * ca - sig * bk - d_prev) - 2.0 * zeta * d_cur
        else:
            rk *= r
            m = k % 4  # cos(phi + k pi/2) from ca = cos phi, sa = sin phi
            fk = ca if m == 0 else (-sa if m == 1 else (-ca if m == 2 else sa))
            d_next = A * rk * fk - d_prev - 2.0 * zeta * d_cur
        term *= s / (k + 2)
        vterm *= s / (k + 1)
        q += d_next * term
        v += d_next * vterm
        d_prev, d_cur = d_cur, d_next
    return q, v


@jit
def slip_state(s, q0, v0, sig, A, r, bk, zeta, ca, sa):
    """(q, v) at local time s of a slip segment that starts at (q0, v0) with cos/sin(r t0) = ca, sa."""
    if zeta == 0.0:
        h = 0.5 * (1.0 + r) * s
        g = 0.5 * s * sin_over(0.5 * (1.0 - r) * s)
        sh = math.sin(h)
        ch = math.cos(h)
        inv = 1.0 / (1.0 + r)
        c_resp = 2.0 * inv * sh * g
        s_resp = (math.sin(s) - 2.0 * ch * g) * inv
        c_rate = (2.0 * ch * g + math.sin(r * s)) * inv
        s_rate = r * c_resp
        cs = math.cos(s)
        ss = math.sin(s)
        q = q0 * cs + v0 * ss - sig * bk * (1.0 - cs) + A * (ca * c_resp - sa * s_resp)
        v = -(q0 + sig * bk) * ss + v0 * cs + A * (ca * c_rate - sa * s_rate)
        return q, v
    if s * max(1.0, r) <= DAMPED_SERIES_SPAN:
        return _damped_series(s, q0, v0, sig, A, r, bk, zeta, ca, sa)
    # viscous damping, 0 < zeta < 1: particular solution Re[G e^{i r (t0 + s)}], G = A / (1 - r^2 + 2i zeta r)
    den_re = 1.0 - r * r
    den_im = 2.0 * zeta * r
    den2 = den_re * den_re + den_im * den_im
    g_re = A * den_re / den2
    g_im = -A * den_im / den2
    h_re = g_re * ca - g_im * sa
    h_im = g_re * sa + g_im * ca
    crs = math.cos(r * s)
    srs = math.sin(r * s)
    p = h_re * crs - h_im * srs
    dp = -r * (h_re * srs + h_im * crs)
    wd = math.sqrt(1.0 - zeta * zeta)
    c1 = q0 + sig * bk - h_re
    c2 = (v0 + r * h_im + zeta * c1) / wd
    e = math.exp(-zeta * s)
    cw = math.cos(wd * s)
    sw = math.sin(wd * s)
    q = -sig * bk + p + e * (c1 * cw + c2 * sw)
    v = dp + e * ((wd * c2 - zeta * c1) * cw - (zeta * c2 + wd * c1) * sw)
    return q, v


@jit
def acceleration(q, v, sig, A, bk, zeta, cos_phase):
    """The equation's right-hand side: q'' = A cos(r t) - q - sig bk - 2 zeta q' in slip direction sig,
    with cos(r t) = cos_phase."""
    return A * cos_phase - q - sig * bk - 2.0 * zeta * v


@jit
def curvature_bounds(rho, A, r, bk, zeta, hmax):
    """Bounds M2 >= |v''| and M3 >= |v'''| over the next hmax of a slip segment.

    In slip, d|(q, v)|/ds <= A + bk (damping only removes energy), so |(q, v)| <= rho_max below;
    then v' = A cos - q - sig bk - 2 zeta v, v'' = -A r sin - v - 2 zeta v', v''' = -A r^2 cos - v'' ...
    """
    rho_max = rho + (A + bk) * hmax
    a_max = A + bk + rho_max * (1.0 + 2.0 * zeta)
    m2 = A * r + rho_max + 2.0 * zeta * a_max
    m3 = A * r * r + a_max + 2.0 * zeta * m2
    return m2, m3


@jit
def find_stop(t0, q0, v0, sig, A, r, bk, zeta, s_end, vtol, hmax, budget):
    """First local time s in [0, s_end] at which the velocity in direction sig falls to vtol.

    Returns (s, found, work). A stop is the velocity in direction sig falling to vtol while it
    decelerates (a slow start from rest, w tiny but rising, is not one). No stop can be skipped: from a
    sample with w = sig v > 0 and
    w' = sig v', the bound sig v(s + d) >= w + w' d - M2 d^2 / 2 proves the next step d safe.
    Near a simple root this is a Newton step with a safety margin (quadratic convergence); at a
    grazing contact the steps shrink geometrically until w <= vtol, so no Zeno stall.
    A segment that starts at rest (after a stop) skips its initial zero with the same bounds:
    sig v >= w'(0) s - M2 s^2 / 2, or, if the start is a tie (w'(0) = 0), >= w''(0) s^2/2 - M3 s^3/6.
    """
    ca = math.cos(r * t0)
    sa = math.sin(r * t0)
    w = sig * v0
    if w < 0.0:
        return 0.0, True, 0
    s = 0.0
    if w <= vtol:
        a0 = acceleration(q0, v0, sig, A, bk, zeta, ca)
        wa = sig * a0
        m2, m3 = curvature_bounds(math.hypot(q0, v0), A, r, bk, zeta, hmax)
        s1 = 0.0
        if wa > 0.0:
            s1 = wa / m2
        wj = sig * (-A * r * sa - v0 - 2.0 * zeta * a0)
        # A tie: the force sits on the band edge (to rounding, |wa| <= atol) and moves outwards
        # (wj > 0). Then sig v >= -|wa| s + wj s^2/2 - M3 s^3/6, positive on (2|wa|/wj, 3wj/M3).
        atol = FORCE_TIE * (A + bk + abs(q0))
        if wj > 0.0 and wa >= -atol:
            s_tie = 1.5 * wj / m3
            if wa >= 0.0 or s_tie > 4.0 * (-wa) / wj:
                s1 = max(s1, s_tie)
        if s1 <= 0.0:
            return 0.0, True, 0  # cannot move in this direction: the caller decides again
        s = min(s1, hmax, s_end)
    work = 0
    while True:
        q, v = slip_state(s, q0, v0, sig, A, r, bk, zeta, ca, sa)
        w = sig * v
        wa = sig * acceleration(q, v, sig, A, bk, zeta, math.cos(r * (t0 + s)))
        # a stop is the velocity falling to zero: a slow start from rest (w tiny but rising) is not one,
        # or each restart would stop at once and time would creep forward geometrically (Zeno)
        if s > 0.0 and (w <= 0.0 or (w <= vtol and wa <= 0.0)):
            return s, True, work
        if s >= s_end:
            return s_end, False, work
        work += 1
        if work > budget:
            return s, False, work
        m2, _ = curvature_bounds(math.hypot(q, v), A, r, bk, zeta, hmax)
        disc = math.sqrt(wa * wa + 2.0 * m2 * w)
        if wa >= 0.0:
            d = (wa + disc) / m2
        else:
            d = 2.0 * w / (disc - wa)
        s = min(s + min(d, hmax), s_end)
