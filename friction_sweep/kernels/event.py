"""Event-driven advance over one forcing period, exact between events, with optional measurement.

State at a period boundary: (q, v, mode) with mode +1/-1 slipping and 0 stuck. Time inside the
kernel is period-local (0 <= t <= T = 2 pi / r), so the forcing phase r t never loses precision,
however many periods are marched. At every stop the next mode is decided from the force there
(stick if |A cos(r t) - q| <= bs, else slip towards it), never by re-arming a root finder.

Measurement goes into the accumulator record of kernels/measure.py. On slip pieces the first-harmonic
integrals are closed form (or Gauss-Legendre near resonance and with damping), the sliding distance is
exact (|q1 - q0| of each piece), sticks are measured exactly (measure.measure_stick, called from
stick.stick_phase). For c = 0 the extremes of the response x = q + c cos(r t) sit at events (q is
monotone between velocity zeros); for c != 0 (joined: x = z + cos r t) each slip piece is sampled and
its best samples refined by Newton on x' = 0. Along the way the period map's monodromy matrix (slots
jac11..jac22, for shooting) is built from the flow of slip pieces and the saltations at reversals, into
sticks and at releases.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.kernels import fourier
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_JAC,
    ACC_JAC_OK,
    ACC_SLIDE,
    BUDGET,
    OK,
    note_stop,
    offer_extreme,
)
from friction_sweep.kernels.segments import TWO_PI, acceleration, find_stop, sin_over, slip_state
from friction_sweep.kernels.stick import decide, slip_direction, stick_phase

_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
GL_X = np.ascontiguousarray(_GL_X)
GL_W = np.ascontiguousarray(_GL_W)

#: below this |1 - r^2| the first-harmonic integrals of a slip piece use Gauss-Legendre on the
#: cancellation-free slip_state; above it the closed form, whose terms are at most A/|1 - r^2|
CLOSED_FORM_DETUNING = 0.1
#: sample spacing times (1 + r) when searching a slip piece for the extremes of x (c != 0): x moves at
#: frequencies 1 and r, so one hump spans more than pi/(1 + r) and cannot hide between samples
EXTREME_SPACING = 0.15

NO_SAMPLES = np.empty(0)  # for callers from Python; jitted callers allocate their own


@jit
def _int_cos_sin(w, phi, S):
    """(integral of cos(w s + phi), of sin(w s + phi)) over 0 <= s <= S, without cancellation as w S -> 0."""
    h = 0.5 * w * S
    f = S * sin_over(h)
    return f * math.cos(phi + h), f * math.sin(phi + h)


@jit
def _closed_form(r, zeta):
    """Whether a slip piece is written as a sum of sinusoids (_slip_split): undamped, off resonance."""
    return zeta == 0.0 and abs((1.0 - r) * (1.0 + r)) >= CLOSED_FORM_DETUNING


@jit
def _slip_split(q0, v0, sig, A, r, bk, ca, sa):
    """(k, alpha, gamma, G) with q(s) = k + alpha cos s + gamma sin s + G cos(r t0 + r s) on an undamped
    slip piece from (q0, v0) with cos/sin(r t0) = ca, sa: G = A/(1 - r^2), k = -sig bk (segments.slip_state
    split differently: that one is exact at r = 1, this one only where _closed_form holds)."""
    G = A / ((1.0 - r) * (1.0 + r))
    return -sig * bk, q0 + sig * bk - G * ca, v0 + G * r * sa, G


@jit
def _slip_harmonic(acc, t0, q0, v0, sig, s_end, A, r, bk, zeta, ca, sa):
    """Add the integrals of q cos(r t), q sin(r t) over a slip piece to ACC_IC, ACC_IS.

    Where _closed_form holds, q is a sum of sinusoids (_slip_split), so q cos(r t) and q sin(r t) are
    sums of sinusoids at r, 1 + r, r - 1 and 2 r, integrated exactly. Otherwise 16-point
    Gauss-Legendre on sub-intervals short enough to resolve frequencies up to 1 + 2 r to rounding.
    """
    ph0 = r * t0
    if _closed_form(r, zeta):
        k, alpha, gamma, G = _slip_split(q0, v0, sig, A, r, bk, ca, sa)
        cr, sr = _int_cos_sin(r, ph0, s_end)
        cp, sp = _int_cos_sin(1.0 + r, ph0, s_end)
        cm, sm = _int_cos_sin(r - 1.0, ph0, s_end)
        c2, s2 = _int_cos_sin(2.0 * r, 2.0 * ph0, s_end)
        acc[ACC_IC] += k * cr + 0.5 * (alpha * (cp + cm) + gamma * (sp - sm) + G * (s_end + c2))
        acc[ACC_IS] += k * sr + 0.5 * (alpha * (sp + sm) + gamma * (cm - cp) + G * s2)
        return
    width = 2.0 / (1.0 + r)
    n = int(math.ceil(s_end / width))
    h = s_end / n
    for j in range(n):
        a = j * h
        for i in range(GL_X.size):
            s = a + 0.5 * h * (GL_X[i] + 1.0)
            q, _ = slip_state(s, q0, v0, sig, A, r, bk, zeta, ca, sa)
            ph = r * (t0 + s)
            wq = 0.5 * h * GL_W[i] * q
            acc[ACC_IC] += wq * math.cos(ph)
            acc[ACC_IS] += wq * math.sin(ph)


@jit
def _slip_x(s, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa):
    """(x, x', x'') at local time s of a slip piece, x = q + c cos(r t)."""
    q, v = slip_state(s, q0, v0, sig, A, r, bk, zeta, ca, sa)
    ph = r * (t0 + s)
    cp = math.cos(ph)
    x = q + c * cp
    xd = v - c * r * math.sin(ph)
    xdd = acceleration(q, v, sig, A, bk, zeta, cp) - c * r * r * cp
    return x, xd, xdd


@jit
def _piece_extreme(sign, a, b, s, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa):
    """Extreme of sign * x on [a, b] next to the sample s: Newton on x' = 0, kept inside [a, b] and on
    the concave side; golden-section search where Newton does not settle. Returns (s, x)."""
    y = s
    for _ in range(12):
        x, xd, xdd = _slip_x(y, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)
        if sign * xdd >= 0.0:
            break
        step = xd / xdd
        y -= step
        if not (a <= y <= b):
            break
        if abs(step) <= 1e-15 * (1.0 + abs(t0 + y)):
            return y, _slip_x(y, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1 = b - g * (b - a)
    x2 = a + g * (b - a)
    f1 = sign * _slip_x(x1, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
    f2 = sign * _slip_x(x2, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
    for _ in range(80):
        if f1 > f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - g * (b - a)
            f1 = sign * _slip_x(x1, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (b - a)
            f2 = sign * _slip_x(x2, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
        if b - a <= 1e-15 * (1.0 + abs(t0 + b)):
            break
    y = 0.5 * (a + b)
    return y, _slip_x(y, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]


@jit
def _slip_extremes(acc, t0, q0, v0, sig, s_end, q1, A, r, bk, zeta, c, ca, sa):
    """Offer the max and min of x = q + c cos(r t) over a slip piece, exact to rounding.

    The ends are offered as they are. For c = 0 that is all (q is monotone between velocity zeros);
    for c != 0 the piece is sampled at spacing <= EXTREME_SPACING/(1 + r) and the best sample of
    each kind is refined inside its two neighbouring intervals, unless it is an end the slope leaves.
    Refining per piece (not per period) keeps an extreme just across an event or the period end.
    q1: q at the piece's end.
    """
    x0 = q0 + c * ca
    offer_extreme(acc, x0, t0)
    x1 = q1 + c * math.cos(r * (t0 + s_end))
    offer_extreme(acc, x1, t0 + s_end)
    if c == 0.0 or s_end <= 0.0:
        return
    n = max(2, int(math.ceil(s_end * (1.0 + r) / EXTREME_SPACING)))
    h = s_end / n
    jmax = 0 if x0 >= x1 else n
    jmin = 0 if x0 <= x1 else n
    xmax = max(x0, x1)
    xmin = min(x0, x1)
    closed = _closed_form(r, zeta)
    k = alpha = gamma = gc = ch = sh = crh = srh = cs = ss = cb = sb = 0.0
    if closed:
        # phases advance by rotation: a sample costs no trig call
        k, alpha, gamma, G = _slip_split(q0, v0, sig, A, r, bk, ca, sa)
        gc = G + c
        ch, sh = math.cos(h), math.sin(h)
        crh, srh = math.cos(r * h), math.sin(r * h)
        cs, ss = 1.0, 0.0
        cb, sb = ca, sa
    for j in range(1, n):
        if closed:
            cs, ss = cs * ch - ss * sh, ss * ch + cs * sh
            cb, sb = cb * crh - sb * srh, sb * crh + cb * srh
            x = k + alpha * cs + gamma * ss + gc * cb
        else:
            x = _slip_x(j * h, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[0]
        if x > xmax:
            xmax, jmax = x, j
        if x < xmin:
            xmin, jmin = x, j
    for j, sign in ((jmax, 1.0), (jmin, -1.0)):
        s = j * h if j < n else s_end
        if j == 0 or j == n:
            slope = sign * _slip_x(s, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)[1]
            if (j == 0 and slope <= 0.0) or (j == n and slope >= 0.0):
                continue  # the end itself is the extreme, offered above
        a = max(0.0, (j - 1) * h)
        b = min(s_end, (j + 1) * h)
        y, x = _piece_extreme(sign, a, b, s, t0, q0, v0, sig, A, r, bk, zeta, c, ca, sa)
        offer_extreme(acc, x, t0 + y)


@jit
def _measure_slip(acc, t0, q0, v0, sig, s_end, q1, A, r, bk, zeta, c, ca, sa):
    """Measure a slip piece from (q0, v0) at t0 to q1 at t0 + s_end; ca, sa = cos/sin(r t0). q is monotone
    on a piece (it ends at the first velocity zero), so |q1 - q0| is the distance it slides, exactly."""
    acc[ACC_SLIDE] += abs(q1 - q0)
    if s_end > 0.0:
        _slip_harmonic(acc, t0, q0, v0, sig, s_end, A, r, bk, zeta, ca, sa)
    _slip_extremes(acc, t0, q0, v0, sig, s_end, q1, A, r, bk, zeta, c, ca, sa)


@jit
def _sample(ts, sq, sv, j, ta, tb, t0, q0, v0, sig, A, r, bk, zeta):
    """Fill the samples with ta <= ts[j] < tb from the piece anchored at t0; returns the next j."""
    while j < ts.size and ts[j] < tb:
        if ts[j] >= ta:
            if sig == 0:
                sq[j], sv[j] = q0, 0.0
            else:
                sq[j], sv[j] = slip_state(ts[j] - t0, q0, v0, sig, A, r, bk, zeta,
                                          math.cos(r * t0), math.sin(r * t0))
        j += 1
    return j


@jit
def _jac_flow(acc, s, zeta):
    """J <- Phi(s) J, Phi the flow of q'' + 2 zeta q' + q = 0 over a slip piece of length s (the
    friction and forcing terms do not depend on the state, so a slip piece is affine in it)."""
    if zeta == 0.0:
        p11 = math.cos(s)
        p12 = math.sin(s)
        p21 = -p12
        p22 = p11
    else:
        wd = math.sqrt(1.0 - zeta * zeta)
        e = math.exp(-zeta * s)
        cw = math.cos(wd * s)
        sw = math.sin(wd * s)
        p11 = e * (cw + zeta / wd * sw)
        p12 = e * sw / wd
        p21 = -p12
        p22 = e * (cw - zeta / wd * sw)
    j = ACC_JAC
    a, b, c, d = acc[j], acc[j + 1], acc[j + 2], acc[j + 3]
    acc[j] = p11 * a + p12 * c
    acc[j + 1] = p11 * b + p12 * d
    acc[j + 2] = p21 * a + p22 * c
    acc[j + 3] = p21 * b + p22 * d


@jit
def _jac_reversal(acc, a_before, a_after):
    """Saltation at a reversal (event v = 0, friction flips): S = I + (f+ - f-) n^T / (n^T f-) with
    n = (0, 1), f = (v, a), i.e. the velocity row of J scales by a+/a-."""
    if a_before == 0.0:
        acc[ACC_JAC_OK] = 0.0
        return
    f = a_after / a_before
    acc[ACC_JAC + 2] *= f
    acc[ACC_JAC + 3] *= f


@jit
def _jac_stick(acc):
    """Saltation into a stick: the mass is held at rest whatever the perturbation, so the velocity row
    of J is zeroed (the stop's position moves with q alone, as v = 0 there)."""
    acc[ACC_JAC + 2] = 0.0
    acc[ACC_JAC + 3] = 0.0


@jit
def _jac_release(acc, te, sig, p):
    """Saltation at the end of a stick at te, slipping in direction sig (docs/equations.md §3).

    The stick ends where the net force d = A cos(r t) - q_s reaches sig bs, so te moves with the stop
    as dte = dq_s / d'(te), d' = -A r sin(r te); a later release leaves the mass slower by a+ dte, a+ =
    sig (bs - bk) the acceleration at release. The velocity row (zero through the stick) becomes
    -a+/d' times the position row: nothing for bs = bk, where the release is tangential in velocity. A
    force that only touches the band edge (d' = 0) makes te non-smooth in q_s: no Jacobian then."""
    ddot = -p.A * p.r * math.sin(p.r * te)
    if ddot == 0.0 or sig * ddot <= 0.0:
        acc[ACC_JAC_OK] = 0.0
        return
    g = -sig * (p.bs - p.bk) / ddot
    acc[ACC_JAC + 2] = g * acc[ACC_JAC]
    acc[ACC_JAC + 3] = g * acc[ACC_JAC + 1]


@jit
def advance_period(q, v, mode, p, vtol_rel, budget, measure, acc, ts, sq, sv, harm=None):
    """March one forcing period from t = 0 to T. Returns (q, v, mode, status, work).

    ts: sorted period-local sample times, or None when not sampling (a compile-time choice: a run without
    time histories compiles no sampling); q, v there go to sq, sv.
    harm: None (left out: a compile-time choice, so a run without the output `harmonics` compiles none of
    it), or the complex accumulator of kernels/fourier.py, to which every piece adds its exact Fourier
    integrals.
    Along the way acc[ACC_JAC:ACC_JAC + 4] gets the monodromy matrix d(q, v)(T)/d(q, v)(0) and
    acc[ACC_JAC_OK] = 1 when it is valid: through reversals and sticks, not where the map is not smooth
    (a stop that neither reverses nor sticks, a stick that ends as it starts or where the force only
    touches the band edge, a slip that could not start).
    """
    A, r, bk, bs, zeta, c = p
    T = TWO_PI / r
    hmax = min(1.0, 1.0 / r)
    acc[ACC_JAC], acc[ACC_JAC + 1], acc[ACC_JAC + 2], acc[ACC_JAC + 3] = 1.0, 0.0, 0.0, 1.0
    # A period that starts stuck forgets a push dv only where kinetic friction could hold the mass too
    # (it slides dv^2/2|a| and stops); where static friction alone holds it, any push sets it sliding.
    acc[ACC_JAC_OK] = 0.0 if mode == 0 and v == 0.0 and abs(A - q) > bk else 1.0
    t = 0.0
    work = 0
    new_stop = False
    # The next slip starts from rest: after a stick's exit, or where the period starts at rest in a slip
    # mode (the force at the band edge). Where it cannot start, the mass stays stuck (without the
    # period-start case, joined r = 0.2, beta = 0.02 from q = A - bs found a stop 1e-14 later without
    # moving, again and again, and spent the whole work budget in one period).
    from_rest = v == 0.0
    j = 0
    stalled = False  # the last slip could not start from its stick exit
    while True:
        if mode == 0:
            _jac_stick(acc)
            te = stick_phase(acc, q, t, T, p, new_stop, measure, stalled)
            if stalled or te <= t:
                acc[ACC_JAC_OK] = 0.0
            new_stop = False
            stalled = False
            if ts is not None:
                j = _sample(ts, sq, sv, j, t, te if te < T else math.inf, t, q, 0.0, 0, A, r, bk, zeta)
            if harm is not None:
                fourier.add_stick(harm, q, t, min(te, T), A, r)
            if te >= T:
                return q, 0.0, 0, OK, work
            t = te
            v = 0.0
            mode = slip_direction(t, q, A, r)
            _jac_release(acc, t, mode, p)
            work += 1
            from_rest = True
        else:
            vtol = vtol_rel * max(A, math.hypot(q, v))
            s, found, w = find_stop(t, q, v, mode, A, r, bk, zeta, T - t, vtol, hmax, budget - work)
            work += w + 1
            if work > budget:
                return q, v, mode, BUDGET, work
            ca = math.cos(r * t)
            sa = math.sin(r * t)
            q1, v1 = slip_state(s, q, v, mode, A, r, bk, zeta, ca, sa)
            if found and from_rest and (s == 0.0 or q1 == q):
                # the force touched the band edge and turned back, or pushes past it by less than
                # rounding (the slip stops before the mass has moved at all): the mass stays stuck
                mode = 0
                stalled = True
                from_rest = False
                continue
            from_rest = False
            if measure:
                _measure_slip(acc, t, q, v, mode, s, q1, A, r, bk, zeta, c, ca, sa)
            if ts is not None:
                j = _sample(ts, sq, sv, j, t, t + s if found else math.inf, t, q, v, mode, A, r, bk, zeta)
            if harm is not None:
                fourier.add_slip(harm, t, q, v, mode, s, A, r, bk, zeta)
            _jac_flow(acc, s, zeta)
            t = t + s
            q = q1
            v = v1
            if not found:
                return q, v, mode, OK, work
            v = 0.0
            note_stop(acc, q)
            old = mode
            mode = decide(t, q, A, r, bs)
            if mode == -old:
                cp = math.cos(r * t)
                _jac_reversal(acc, acceleration(q, 0.0, old, A, bk, zeta, cp),
                              acceleration(q, 0.0, mode, A, bk, zeta, cp))
            elif mode != 0:
                acc[ACC_JAC_OK] = 0.0  # touched v = 0 and went on: not smooth there
            new_stop = mode == 0
            if t >= T:
                return q, v, mode, OK, work
