"""Event-driven advance over one forcing period of the Jenkins contact, exact between events
(docs/equations.md §7).

The contact is a spring kappa (in units of k) in series with the Coulomb slider at w, so

    q'' + 2 zeta q' + q + fc = A cos(r t),    fc = kappa (q - w),    x = q + c cos(r t)

- slider slipping in direction sig (|fc| = bk, w' = q'): today's slip, q'' + 2 zeta q' + q + sig bk = A cos(r t),
  segments.slip_state and segments.find_stop unchanged, w = q - sig bk / kappa;
- slider stuck (w' = 0) while |fc| < bs: a linear oscillator of stiffness 1 + kappa, Omega = sqrt(1 + kappa).
  In u = Omega s and p = q - K, K = kappa w / Omega^2 (its rest position), that is

      p_uu + 2 (zeta/Omega) p_u + p = (A/Omega^2) cos((r/Omega) (u0 + u)),

  a slip piece of §3 without friction, so segments.slip_state gives it exactly (cancellation-free at
  r = Omega too), and the band |fc| <= bs is |p - w/Omega^2| <= bs/kappa. The stick ends where p reaches
  an edge of that band, a root of a sum of sinusoids, found by steps that a bound on |p_uu| proves safe
  (band_exit, as segments.find_stop for the velocity); at the exit the slider slips towards that edge, w
  jumping by (bs - bk)/kappa where static friction exceeds kinetic (a massless slider: the spring
  unloads at once from bs to bk, dissipating (bs^2 - bk^2)/(2 kappa)).

Labels (they converge to the rigid model's as kappa -> oo): every slip ends at a velocity zero of the mass,
where the slider sticks. A stick during which the mass's velocity returns to zero is a stop (the contact
holds the mass, which swings on the contact spring as the rigid mass rests); a stick that ends before
(the contact spring unloading through 2 bk / kappa after a reversal, or loading further at a touch) is
part of continuous motion. While the contact holds the mass, its swing on the contact spring reaches the
band's edge again and again as the force drifts (about sqrt(kappa) times per rigid stop), and the slider
creeps a little each time. Such a creep does not end the stop: a slip begun from a held stick during
which the load on the mass, A cos(r t) - q - 2 zeta q', never exceeds the kinetic friction in the slip's
direction (sig q'' <= 0 throughout: the mass coasts on the swing's momentum against friction, which a
rigid held mass never does; `_driven`), tracked by `anchor` (the slider's position where the slip began,
NaN once the load drives it). The stick after a creep is held from its start and no new stop. A slip
the load drives is the rigid model's break-away, however short (next to r = 1 with beta close to A the
rigid slides are shorter than the band, 2 bs / kappa, at kappa = 1000). mode: +-1
slipping, 0 stuck and not (yet) a stop, STUCK_HELD stuck and a stop. The period's stuck time is the time
held (from the velocity zero that makes the stick a stop).

Measurement: slip pieces as event.py measures them; stick pieces by the same projection onto the forcing
frequency in their own variables, and their extremes by sampling and refining (q is not monotone on a
stick).

Monodromy: acc[JACC_JAC:JACC_JAC + 9] gets M = d(q, v, w)(T)/d(q, v, w)(0) (row-major) and
acc[JACC_JAC_OK] = 1 where the period map is smooth there, built piece by piece as J <- S_event Phi_piece J
(docs/equations.md §7). With a(q, v, t) = A cos(r t) - 2 zeta v - q:

- slip piece of length s, direction sig: (q, v) flows by the rigid slip flow Phi(s) of
  q'' + 2 zeta q' + q = 0 (event._jac_flow; friction and forcing do not depend on the state), and the slider
  is slaved, w = q - sig bk/kappa, so w's row is q's and the column of w at the piece's start is zero (a
  slip is defined on |fc| = bk only; where it starts the reset below, or the section's w = q - sig bk/kappa,
  has put it there):  [Phi 0; Phi_1. 0];
- stick piece of stick time u: w fixed, p = q - cK w (cK = kappa/Omega^2) obeys p_uu + 2 (zeta/Omega) p_u
  + p = 0 homogeneously, with flow Phi_u(u) in (p, p_u); in (q, v), v = Omega p_u,
      dq1 = P11 (dq0 - cK dw) + P12/Omega dv0 + cK dw,  dv1 = Omega P21 (dq0 - cK dw) + P22 dv0,  dw1 = dw;
- an event g(x) = 0 (no explicit t in either event below) with reset x+ = R(x) changes J by the
  saltation S = R_x + (f+(R(x)) - R_x f-) g_x / (g_x . f-), f-/f+ the fields before and after, f =
  (v, a - fc, w'):
  - slip -> stick at a velocity zero (g = v, no reset): there fc = sig bk on both sides and w' = v = 0, so
    f+ = f- and S = I. It needs the crossing g_x . f- = a - sig bk (the slip's acceleration) of sign
    -sig; a velocity that only touches zero is not smooth (jac_ok = 0);
  - stick -> slip at the band edge e (g = e kappa (q - w) - bs, g_x = e kappa (1, 0, -1), g_x . f- =
    e kappa v): R sets w = q - e bk/kappa (a jump by e (bs - bk)/kappa), R_x = [1 0 0; 0 1 0; 1 0 0], and
    f+ - R_x f- = (0, e (bs - bk), 0), the acceleration the unloading spring adds. So q's row stays,
    w's row becomes q's, and v's row gains g_v (q's row - w's row), g_v = e (bs - bk)/v: a later exit
    leaves the mass slower. Only a transversal exit (e v > 0) is smooth: an exit at a stick's start (a
    velocity that touched zero on the edge), a tangential exit and a stalled slip after it are not;
- the period's end is at fixed time T: no event.
Every slip resets the slider onto q, so M has rank <= 2 over a period with a slip (an eigenvalue 0; the
others are those of the map that Newton solves in (q, v) where the slider slips at the section).
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.kernels import fourier
from friction_sweep.kernels.event import EXTREME_SPACING, _measure_slip, _piece_extreme, _slip_harmonic, _slip_x
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import (
    ACC_IC,
    ACC_IS,
    ACC_JAC_OK,
    ACC_SIZE,
    ACC_STOPS,
    ACC_STUCK,
    BUDGET,
    OK,
    note_stop,
    offer_extreme,
)
from friction_sweep.kernels.segments import TWO_PI, acceleration, find_stop, slip_state
from friction_sweep.kernels.stick import TANGENT_SKIP

#: mode of a stick that has become a stop (the mass's velocity returned to zero within it)
STUCK_HELD = 2
#: golden-section iterations that refine the largest sampled sig q'' of a slip piece (_driven): a bracket
#: of two sample spacings shrinks below 1e-8 of it
DRIVEN_REFINE = 40

#: the Jenkins accumulator: the rigid record (measure.ACC_FIELDS) and these slots after it
JACC_SLIPS = ACC_SIZE  # slips begun (stick exits from which the slider moved)
JACC_JUMP = ACC_SIZE + 1  # energy dissipated by the break-away jumps, (bs^2 - bk^2)/(2 kappa) each
JACC_JAC = ACC_SIZE + 2  # the period's monodromy matrix d(q, v, w)(T)/d(q, v, w)(0), 9 slots row-major
JACC_JAC_OK = ACC_SIZE + 11  # 1 where that matrix is valid (the period map is smooth there)
JACC_SIZE = ACC_SIZE + 12


def new_jenkins_accumulator():
    """A fresh, reset Jenkins accumulator (for callers from Python: tests)."""
    from friction_sweep.kernels.measure import reset_accumulator

    acc = np.zeros(JACC_SIZE)
    reset_accumulator(acc)
    return acc


@jit
def _flow_coefficients(s, zeta):
    """Phi(s) = (p11, p12, p21, p22), the flow of q'' + 2 zeta q' + q = 0 over time s (0 <= zeta < 1)."""
    if zeta == 0.0:
        p11 = math.cos(s)
        p12 = math.sin(s)
        return p11, p12, -p12, p11
    wd = math.sqrt(1.0 - zeta * zeta)
    e = math.exp(-zeta * s)
    cw = math.cos(wd * s)
    sw = math.sin(wd * s)
    p12 = e * sw / wd
    return e * (cw + zeta / wd * sw), p12, -p12, e * (cw - zeta / wd * sw)


@jit
def _mono_slip(acc, s, zeta):
    """J <- L J over a slip piece of length s: L = [Phi 0; Phi_1. 0] (w slaved to q, its start column zero)."""
    p11, p12, p21, p22 = _flow_coefficients(s, zeta)
    j = JACC_JAC
    for col in range(3):
        a = acc[j + col]
        b = acc[j + 3 + col]
        acc[j + col] = p11 * a + p12 * b
        acc[j + 3 + col] = p21 * a + p22 * b
        acc[j + 6 + col] = acc[j + col]


@jit
def _mono_stick(acc, u, zp, om, kappa):
    """J <- G J over a stick piece of stick time u (w fixed, q about its rest cK w, cK = kappa/Omega^2):
    G = [P11, P12/Omega, cK (1 - P11); Omega P21, P22, -cK Omega P21; 0, 0, 1], Phi_u(u) at damping zeta/Omega."""
    p11, p12, p21, p22 = _flow_coefficients(u, zp)
    ck = kappa / (om * om)
    g12 = p12 / om
    g13 = ck * (1.0 - p11)
    g21 = om * p21
    g23 = -ck * g21
    j = JACC_JAC
    for col in range(3):
        a = acc[j + col]
        b = acc[j + 3 + col]
        c = acc[j + 6 + col]
        acc[j + col] = p11 * a + g12 * b + g13 * c
        acc[j + 3 + col] = g21 * a + p22 * b + g23 * c
        # w's row is unchanged


@jit
def _mono_exit(acc, edge, v, bs, bk):
    """J <- S J at a stick's exit through edge e at velocity v (e v > 0): S = [1 0 0; g_v 1 -g_v; 1 0 0],
    g_v = e (bs - bk)/v: the exit time moves by -(dq - dw)/v, and a later exit starts the slip with the
    spring unloaded from bs to bk that much later."""
    gv = edge * (bs - bk) / v
    j = JACC_JAC
    for col in range(3):
        a = acc[j + col]
        acc[j + 3 + col] += gv * (a - acc[j + 6 + col])
        acc[j + 6 + col] = a


@jit
def stick_scales(r, zeta, kappa):
    """(Omega, r/Omega, zeta/Omega): the stuck oscillator's natural frequency and the ratios in its time u."""
    om = math.sqrt(1.0 + kappa)
    return om, r / om, zeta / om


@jit
def stick_state(s, t0, q0, v0, w, A, r, zeta, kappa):
    """(q, v) at local time s of a stick that starts at (q0, v0) at t0 with the slider at w."""
    om, rho, zp = stick_scales(r, zeta, kappa)
    m = w / (om * om)
    p0 = (q0 - w) + m
    p, pu = slip_state(om * s, p0, v0 / om, 1, A / (om * om), rho, 0.0, zp, math.cos(r * t0), math.sin(r * t0))
    return p + (w - m), om * pu


@jit
def _driven(t0, q0, v0, sig, s_end, A, r, bk, zeta, ca, sa):
    """Whether the load drives the slip piece from (q0, v0) at t0 in direction sig (cos/sin(r t0) = ca, sa)
    somewhere in [0, s_end]: sig q'' > 0, i.e. A cos(r t) - q - 2 zeta q' beyond the kinetic friction.

    q'' moves at the frequencies 1 and r, so samples EXTREME_SPACING/(1 + r) apart (as for the extremes of
    x) cannot step over a hump of it; the best sample's bracket is refined by golden section."""
    n = max(2, int(math.ceil(s_end * (1.0 + r) / EXTREME_SPACING)))
    h = s_end / n
    best = -math.inf
    jbest = 0
    for j in range(n + 1):
        q, v = slip_state(j * h, q0, v0, sig, A, r, bk, zeta, ca, sa)
        f = sig * acceleration(q, v, sig, A, bk, zeta, math.cos(r * (t0 + j * h)))
        if f > 0.0:
            return True
        if f > best:
            best, jbest = f, j
    a = max(0.0, (jbest - 1) * h)
    b = min(s_end, (jbest + 1) * h)
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(DRIVEN_REFINE):
        x1 = b - g * (b - a)
        x2 = a + g * (b - a)
        q, v = slip_state(x1, q0, v0, sig, A, r, bk, zeta, ca, sa)
        f1 = sig * acceleration(q, v, sig, A, bk, zeta, math.cos(r * (t0 + x1)))
        q, v = slip_state(x2, q0, v0, sig, A, r, bk, zeta, ca, sa)
        f2 = sig * acceleration(q, v, sig, A, bk, zeta, math.cos(r * (t0 + x2)))
        if f1 > 0.0 or f2 > 0.0:
            return True
        if f1 >= f2:
            b = x2
        else:
            a = x1
    return False


@jit
def band_exit(u0, p0, pu0, m, hb, Ap, rho, zp, u_end, htol, hmax, budget, u_start):
    """First u in (u_start, u_end] at which p leaves the band |p - m| <= hb outwards, in the stick's time u
    (forcing phase rho (u0 + u)). Returns (u, found, edge, work), edge the side (+1: fc = +bs) it leaves by.

    From a sample inside with h = hb - e (p - m) > 0 for edge e and h' = -e p_u, |h''| <= a_max (the
    bound on |p_uu| over the next hmax: in the stick d|(p, p_u)|/du <= Ap), the band holds for d <
    (h' + sqrt(h'^2 + 2 a_max h)) / a_max: no exit is skipped, near a simple root this is a guarded Newton
    step, at a grazing one the steps shrink until h <= htol. A start on an edge (a stick that begins
    where the slip ended, fc = bk = bs) that the force turns inwards (h'' > 0) skips that zero as
    find_stop does: h >= -|h'| u + h'' u^2/2 - M3 u^3/6; one it turns outwards (or a tie) exits at once.
    That skip is cut to the safe step of the other edge (2 hb away), which it could otherwise step over.
    """
    ca = math.cos(rho * u0)
    sa = math.sin(rho * u0)
    u = u_start
    if u == 0.0:
        a0 = Ap * ca - p0 - 2.0 * zp * pu0
        rho_max = math.hypot(p0, pu0) + Ap * hmax
        m3 = Ap * rho + rho_max + 2.0 * zp * (Ap + rho_max * (1.0 + 2.0 * zp))  # >= |p_uuu|
        for e in (1.0, -1.0):
            h = hb - e * (p0 - m)
            if h <= htol:
                hd = -e * pu0
                hdd = -e * a0
                if hd > htol:
                    continue  # moving inwards: the safe steps below leave the edge
                if hd < -htol or hdd <= 0.0:
                    return 0.0, True, int(e), 0  # moving (or curving) outwards, or a tie: leave now
                s_tie = 1.5 * hdd / m3
                if hd < 0.0 and s_tie <= 4.0 * (-hd) / hdd:
                    return 0.0, True, int(e), 0
                u = max(u, s_tie)
        if u > 0.0:
            # the skip leaves one edge; it must not step over the other, 2 hb away (the swing of a short
            # stick at a reversal crosses the band within the skip): the safe step below, from u = 0
            a_max = Ap + rho_max * (1.0 + 2.0 * zp)
            for e in (1.0, -1.0):
                h = hb - e * (p0 - m)
                if h > htol:
                    hd = -e * pu0
                    disc = math.sqrt(hd * hd + 2.0 * a_max * h)
                    u = min(u, (hd + disc) / a_max if hd >= 0.0 else 2.0 * h / (disc - hd))
        u = min(u, hmax, u_end)
    work = 0
    while True:
        p, pu = slip_state(u, p0, pu0, 1, Ap, rho, 0.0, zp, ca, sa)
        if u > u_start:
            for e in (1.0, -1.0):
                h = hb - e * (p - m)
                if h <= 0.0 or (h <= htol and -e * pu <= 0.0):
                    return u, True, int(e), work
        if u >= u_end:
            return u_end, False, 0, work
        work += 1
        if work > budget:
            return u, False, 0, work
        rho_max = math.hypot(p, pu) + Ap * hmax
        a_max = Ap + rho_max * (1.0 + 2.0 * zp)
        d = hmax
        for e in (1.0, -1.0):
            h = max(hb - e * (p - m), 0.0)
            hd = -e * pu
            disc = math.sqrt(hd * hd + 2.0 * a_max * h)
            de = (hd + disc) / a_max if hd >= 0.0 else 2.0 * h / (disc - hd)
            d = min(d, de)
        u = min(u + d, u_end)


@jit
def _measure_stick_piece(acc, scratch, t0, u_end, p0, pu0, K, Ap, rho, zp, om, r, c):
    """Measure a stick piece of length u_end (stick time) from p0, pu0 at t0: the integrals of
    q cos(r t), q sin(r t) (q = p + K; dt = du / Omega) and the extremes of x = q + c cos(r t), which a
    stick need not hold at its ends (the mass swings on the contact spring): sampled at spacing
    EXTREME_SPACING/(1 + rho) and the best samples refined (event._piece_extreme)."""
    if u_end <= 0.0:
        return
    u0 = om * t0
    ca = math.cos(r * t0)
    sa = math.sin(r * t0)
    t1 = t0 + u_end / om
    scratch[ACC_IC] = 0.0
    scratch[ACC_IS] = 0.0
    _slip_harmonic(scratch, u0, p0, pu0, 1, u_end, Ap, rho, 0.0, zp, ca, sa)
    acc[ACC_IC] += scratch[ACC_IC] / om + K * (math.sin(r * t1) - math.sin(r * t0)) / r
    acc[ACC_IS] += scratch[ACC_IS] / om + K * (math.cos(r * t0) - math.cos(r * t1)) / r
    n = max(2, int(math.ceil(u_end * (1.0 + rho) / EXTREME_SPACING)))
    h = u_end / n
    xmax = -math.inf
    xmin = math.inf
    jmax = jmin = 0
    for j in range(n + 1):
        x = _slip_x(j * h, u0, p0, pu0, 1, Ap, rho, 0.0, zp, c, ca, sa)[0]
        if x > xmax:
            xmax, jmax = x, j
        if x < xmin:
            xmin, jmin = x, j
    offer_extreme(acc, xmax + K, t0 + jmax * h / om)
    offer_extreme(acc, xmin + K, t0 + jmin * h / om)
    for j, sign in ((jmax, 1.0), (jmin, -1.0)):
        a = max(0.0, (j - 1) * h)
        b = min(u_end, (j + 1) * h)
        y, x = _piece_extreme(sign, a, b, j * h, u0, p0, pu0, 1, Ap, rho, 0.0, zp, c, ca, sa)
        if a <= y <= b:
            offer_extreme(acc, x + K, t0 + y / om)


@jit
def _sample(ts, sq, sv, i, ta, tb, stuck, t0, q0, v0, w, sig, p, sw=None):
    """Fill the samples with ta <= ts[i] < tb from the piece that starts at (q0, v0) at t0: a stick with the
    slider at w, or a slip in direction sig. Returns the next i. sw: None (left out: not compiled), or where the
    slider's position goes (w on a stick; q - sig bk / kappa, where the contact spring holds bk, on a slip)."""
    A, r, bk, bs, zeta, c, kappa = p
    while i < ts.size and ts[i] < tb:
        if ts[i] >= ta:
            if stuck:
                sq[i], sv[i] = stick_state(ts[i] - t0, t0, q0, v0, w, A, r, zeta, kappa)
            else:
                sq[i], sv[i] = slip_state(ts[i] - t0, q0, v0, sig, A, r, bk, zeta, math.cos(r * t0), math.sin(r * t0))
            if sw is not None:
                sw[i] = w if stuck else sq[i] - sig * bk / kappa
        i += 1
    return i


@jit
def advance_period_jenkins(q, v, w, mode, anchor, p, vtol_rel, budget, measure, acc, ts, sq, sv, harm=None,
                           sw=None):
    """March one forcing period of the Jenkins contact from t = 0 to T. Returns (q, v, w, mode, anchor,
    status, work); acc (JACC_SIZE slots) gathers what measure.py describes plus the slips and the jumps'
    energy, and the period's monodromy matrix (JACC_JAC, JACC_JAC_OK; the module's docstring). anchor: where
    the slider was when the current slip began from a held stick (NaN otherwise). ts: sorted period-local
    sample times, or None when not sampling (compiled without sampling then); q, v there go to sq, sv
    (event.advance_period's contract). harm: None (left out: nothing compiled for it) or the complex accumulator
    of kernels/fourier.py, to which every piece adds its exact Fourier integrals. sw: None (left out: not
    compiled), or where the slider's position at the sample times goes (_sample)."""
    A, r, bk, bs, zeta, c, kappa = p
    T = TWO_PI / r
    hmax = min(1.0, 1.0 / r)
    om, rho, zp = stick_scales(r, zeta, kappa)
    Ap = A / (om * om)
    hb = bs / kappa
    hmax_u = min(1.0, 1.0 / rho)
    acc[ACC_JAC_OK] = 0.0
    j = JACC_JAC
    for i in range(9):
        acc[j + i] = 1.0 if i % 4 == 0 else 0.0
    acc[JACC_JAC_OK] = 1.0
    scratch = np.empty(2)
    if harm is not None:
        harm_scratch = np.empty_like(harm)
    t = 0.0
    work = 0
    i_sample = 0
    stalled = False  # the last slip could not start from its stick exit (a tangential exit)
    while True:
        if mode == 0 or mode == STUCK_HELD:
            m = w / (om * om)
            K = w - m
            p0 = (q - w) + m
            pu0 = v / om
            u0 = om * t
            u_end = om * (T - t)
            htol = vtol_rel * max(Ap, math.hypot(p0, pu0), hb)
            u_start = min(TANGENT_SKIP * T * om, u_end) if stalled else 0.0
            ub, found, edge, wk = band_exit(u0, p0, pu0, m, hb, Ap, rho, zp, u_end, htol, hmax_u, budget - work,
                                            u_start)
            work += wk + 1
            if work > budget:
                acc[JACC_JAC_OK] = 0.0  # a budget stop: no period map to differentiate
                return q, v, w, mode, anchor, BUDGET, work
            held_from = 0.0
            if mode == 0 and ub > 0.0:
                # a stop once the mass's velocity returns to zero within the stick
                a0 = Ap * math.cos(r * t) - p0 - 2.0 * zp * pu0
                sig_v = 0
                if abs(pu0) > htol:
                    sig_v = 1 if pu0 > 0.0 else -1
                elif a0 != 0.0:
                    sig_v = 1 if a0 > 0.0 else -1
                if sig_v != 0:
                    us, hit, wk = find_stop(u0, p0, pu0, sig_v, Ap, rho, 0.0, zp, ub, htol, hmax_u, budget - work)
                    work += wk
                    if work > budget:
                        acc[JACC_JAC_OK] = 0.0  # a budget stop: no period map to differentiate
                        return q, v, w, mode, anchor, BUDGET, work
                    if hit and 0.0 < us < ub:
                        mode = STUCK_HELD
                        held_from = us
                        acc[ACC_STOPS] += 1.0
            if mode == STUCK_HELD:
                acc[ACC_STUCK] += (ub - held_from) / om
            if measure:
                _measure_stick_piece(acc, scratch, t, ub, p0, pu0, K, Ap, rho, zp, om, r, c)
            _mono_stick(acc, ub, zp, om, kappa)
            if harm is not None:
                fourier.add_stuck_slider(harm, harm_scratch, t, ub, p0, pu0, K, m, kappa, Ap, r, rho, zp, om)
            if ts is not None:
                i_sample = _sample(ts, sq, sv, i_sample, t, t + ub / om if found else math.inf, True, t, q, v, w,
                                   0, p, sw)
            if not found:
                p1, pu1 = slip_state(u_end, p0, pu0, 1, Ap, rho, 0.0, zp, math.cos(r * t), math.sin(r * t))
                return p1 + K, om * pu1, w, mode, anchor, OK, work
            p1, pu1 = slip_state(ub, p0, pu0, 1, Ap, rho, 0.0, zp, math.cos(r * t), math.sin(r * t))
            q_exit = p1 + K
            v_exit = om * pu1
            if ub > 0.0 and edge * v_exit > 0.0:
                _mono_exit(acc, edge, v_exit, bs, bk)
            else:
                # an exit where the stick began (the velocity touched zero on the edge) or a tangential one:
                # the exit time is not smooth in the state
                acc[JACC_JAC_OK] = 0.0
            t_exit = t + ub / om
            # the slider slips towards the edge it reached; try the slip before committing to it
            vtol = vtol_rel * max(A, math.hypot(q_exit, v_exit))
            s, hit, wk = find_stop(t_exit, q_exit, v_exit, edge, A, r, bk, zeta, T - t_exit, vtol, hmax,
                                   budget - work)
            work += wk + 1
            if work > budget:
                acc[JACC_JAC_OK] = 0.0  # a budget stop: no period map to differentiate
                return q_exit, v_exit, w, mode, anchor, BUDGET, work
            ca = math.cos(r * t_exit)
            sa = math.sin(r * t_exit)
            q1, v1 = slip_state(s, q_exit, v_exit, edge, A, r, bk, zeta, ca, sa)
            t, q, v = t_exit, q_exit, v_exit
            if hit and (s == 0.0 or q1 == q_exit):
                # the force on the slider left the band tangentially and turned back: it stays stuck
                stalled = True
                acc[JACC_JAC_OK] = 0.0
                continue
            stalled = False
            anchor = w if mode == STUCK_HELD else math.nan
            mode = edge
            acc[JACC_SLIPS] += 1.0
            acc[JACC_JUMP] += 0.5 * (bs - bk) * (bs + bk) / kappa
        else:
            vtol = vtol_rel * max(A, math.hypot(q, v))
            s, hit, wk = find_stop(t, q, v, mode, A, r, bk, zeta, T - t, vtol, hmax, budget - work)
            work += wk + 1
            if work > budget:
                acc[JACC_JAC_OK] = 0.0  # a budget stop: no period map to differentiate
                return q, v, w, mode, anchor, BUDGET, work
            ca = math.cos(r * t)
            sa = math.sin(r * t)
            q1, v1 = slip_state(s, q, v, mode, A, r, bk, zeta, ca, sa)
        # a slip piece from (q, v) at t, direction mode, of length s, ending at (q1, v1); one the load drives
        # is no creep
        if not math.isnan(anchor) and _driven(t, q, v, mode, s, A, r, bk, zeta, ca, sa):
            anchor = math.nan
        if measure:
            _measure_slip(acc, t, q, v, mode, s, q1, A, r, bk, zeta, c, ca, sa)
        _mono_slip(acc, s, zeta)
        if harm is not None:
            fourier.add_slip(harm, t, q, v, mode, s, A, r, bk, zeta)
        if ts is not None:
            i_sample = _sample(ts, sq, sv, i_sample, t, t + s if hit else math.inf, False, t, q, v, w, mode, p, sw)
        t = t + s
        q = q1
        v = v1
        w = q - mode * bk / kappa
        if not hit:
            return q, v, w, mode, anchor, OK, work
        # the velocity zero is smooth (saltation I) where the slip's acceleration crosses it, against mode
        if s == 0.0 or mode * (A * math.cos(r * t) - q - mode * bk) >= 0.0:
            acc[JACC_JAC_OK] = 0.0
        v = 0.0
        note_stop(acc, q)
        # a creep within a stop leaves the mass held
        mode = 0 if math.isnan(anchor) else STUCK_HELD
        anchor = math.nan
        if t >= T:
            return q, v, w, mode, anchor, OK, work
