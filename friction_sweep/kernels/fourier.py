"""Exact Fourier integrals of the closed-form segments: harmonics of an orbit without sampling or FFT.

Each piece of the 1-DoF rigid-contact motion (kernels/segments.py) is a sum of exponentials and
sinusoids in its local time s = t - t0, so its integral against e^{-i w t}, w = k r (harmonic k of
the forcing), is closed form. `harm` is a complex array of shape (2, H + 1): row HARM_Q gathers
int q e^{-i k r t} dt, row HARM_F int f e^{-i k r t} dt, f the friction force on the mass in the
equation q'' + 2 zeta q' + q + f = A cos(r t): sig bk while slipping in direction sig, A cos(r t) - q
while stuck (q' = q'' = 0 there). kernels/harmonics.py turns the sums into coefficients.

Building blocks (all exact, none divides by 1 - r^2):

    E(z)    = int_0^S e^{z s} ds = S e^{z S/2} sinh(z S/2)/(z S/2)
    J(a)    = E(i a)
    D(a, b) = (J(a) - J(b)) / (a - b),  the divided difference, = [S e^{i m S} sinc(d S) - J(b)] / a
              (m = (a + b)/2, d = (a - b)/2; |a| >= |b| and |a| S >= 1), else its Taylor series

Undamped slip piece from (q0, v0), cos/sin(r t0) = ca, sa (segments.py's cancellation-free form):

    q(s) = (q0 + sig bk) cos s + v0 sin s - sig bk + A ca C(s) - A sa Sn(s)
    int C e^{-i w s}  = [D(-r-w, -1-w) - D(r-w, 1-w)] / (2 (1 + r))
    int Sn e^{-i w s} = [J(1-w) - J(-1-w) - D(r-w, 1-w) - D(-r-w, -1-w)] / (2 i (1 + r))

Damped slip piece (0 < zeta < 1): q(s) = -sig bk + Re[H e^{i r s}] + e^{-zeta s}(c1 cos wd s + c2 sin wd s)
with H, c1, c2 as in segments.slip_state, integrated term by term with E.
"""

from __future__ import annotations

import cmath
import math

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.segments import sin_over

#: the rows of the harmonic accumulator: the displacement q (relative, the equation's), the friction force
HARM_Q = 0
HARM_F = 1
#: D(a, b) by its Taylor series where max(|a|, |b|) S is below this; its terms fall like (that)^j / (j+1)!
DIVIDED_SERIES_SPAN = 1.0
DIVIDED_SERIES_TERMS = 26
#: E(x) is (e^{x S} - 1)/x, e^{x S} carried over k by multiplication, where |x| S reaches this; below, its series
RECURRENCE_SPAN = 1.0


@jit
def _exp_integral(z, S):
    """E(z) = int_0^S e^{z s} ds, without cancellation as z S -> 0."""
    w = 0.5 * z * S
    if abs(w) < 1e-3:
        w2 = w * w
        shc = 1.0 + w2 / 6.0 * (1.0 + w2 / 20.0)
    else:
        shc = cmath.sinh(w) / w
    return S * cmath.exp(w) * shc


@jit
def _integral_from(ez, x, S):
    """E(x) = int_0^S e^{x s} ds from ez = e^{x S}: (ez - 1)/x where |x| S >= RECURRENCE_SPAN (rounding at most
    eps S / RECURRENCE_SPAN), else its series (_exp_integral)."""
    if abs(x) * S >= RECURRENCE_SPAN:
        return (ez - 1.0) / x
    return _exp_integral(x, S)


@jit
def _osc_from(ez, a, S):
    """J(a) = E(i a) for real a from ez = e^{i a S}: (ez - 1)/(i a), a real division (_integral_from's rule)."""
    if abs(a) * S >= RECURRENCE_SPAN:
        d = ez - 1.0
        return complex(d.imag / a, -d.real / a)
    return _exp_integral(complex(0.0, a), S)


@jit
def _divided(a, b, S, front, ea, jb):
    """D(a, b) = (J(a) - J(b)) / (a - b) for real a, b (J's derivative where a = b), with front = S e^{i m S}
    sinc(d S) (m = (a + b)/2, d = (a - b)/2), ea = e^{i a S} and jb = J(b): [front - J(b)] / a where |a| >= |b|
    and |a| S >= DIVIDED_SERIES_SPAN, [front - J(a)] / b where the same holds with a and b exchanged (|D| <=
    S^2 / 2; this form's rounding, eps S / max(|a|, |b|), stays below eps S^2), else the Taylor series
    D = sum_{j>=1} i^j S^{j+1}/(j+1)! h_j, h_j = (a^j - b^j)/(a - b)."""
    if abs(a) >= abs(b) and abs(a) * S >= DIVIDED_SERIES_SPAN:
        return (front - jb) / a
    if abs(b) > abs(a) and abs(b) * S >= DIVIDED_SERIES_SPAN:
        return (front - _osc_from(ea, a, S)) / b
    total = 0j
    h = 1.0  # h_j = a h_{j-1} + b^{j-1}
    bp = 1.0  # b^(j-1)
    ij = 1j  # i^j
    w = S * S / 2.0  # S^(j+1)/(j+1)!
    for j in range(1, DIVIDED_SERIES_TERMS + 1):
        total += ij * w * h
        bp *= b
        h = a * h + bp
        ij *= 1j
        w *= S / (j + 2)
    return total


@jit
def _unit(phase):
    """e^{i phase}."""
    return complex(math.cos(phase), math.sin(phase))


@jit
def add_slip(harm, t0, q0, v0, sig, S, A, r, bk, zeta):
    """Add the integrals of q e^{-i k r t} and f e^{-i k r t}, k = 0..H, over a slip piece from (q0, v0) at t0
    to t0 + S in direction sig (friction f = sig bk), exactly (module docstring).

    The exponentials at harmonic k are those at k = 0 times e^{-i k r S} (and e^{-i k r t0} from the piece's
    local time to the period's), carried from one k to the next by a multiplication: no trig call per harmonic."""
    if S <= 0.0:
        return
    ca = math.cos(r * t0)
    sa = math.sin(r * t0)
    fk = sig * bk
    inv = 1.0 / (1.0 + r)
    step = _unit(-r * S)  # e^{-i r S}
    turn = _unit(-r * t0)  # e^{-i r t0}
    zk = 1.0 + 0j  # e^{-i k r S}
    rot = 1.0 + 0j  # e^{-i k r t0}
    e_r = _unit(r * S)
    e_1 = _unit(S)
    damped = zeta != 0.0
    c1 = c2 = wd = 0.0
    G = ed_p = ed_m = f_p = f_m = 0j
    if damped:
        # segments.slip_state's damped form: particular Re[G e^{i r s}], G = A e^{i r t0} / (1 - r^2 + 2i zeta r)
        G = A / complex(1.0 - r * r, 2.0 * zeta * r) * complex(ca, sa)
        wd = math.sqrt(1.0 - zeta * zeta)
        c1 = q0 + fk - G.real
        c2 = (v0 + r * G.imag + zeta * c1) / wd
        decay = math.exp(-zeta * S)
        ed_p = decay * _unit(wd * S)
        ed_m = decay * _unit(-wd * S)
    else:
        # D's fronts S e^{i m S} sinc(d S) at k = 0: (a, b) = (r, 1) and (-r, -1), d = +-(r - 1)/2
        sinc = S * sin_over(0.5 * (r - 1.0) * S)
        f_p = sinc * _unit(0.5 * (1.0 + r) * S)
        f_m = sinc * _unit(-0.5 * (1.0 + r) * S)
    for k in range(harm.shape[1]):
        w = k * r
        j0 = _osc_from(zk, -w, S)
        er_p = e_r * zk
        er_m = e_r.conjugate() * zk
        if damped:
            e1 = _integral_from(ed_p * zk, complex(-zeta, wd - w), S)
            e2 = _integral_from(ed_m * zk, complex(-zeta, -wd - w), S)
            iq = (-fk * j0 + 0.5 * (G * _osc_from(er_p, r - w, S) + G.conjugate() * _osc_from(er_m, -r - w, S))
                  + 0.5 * c1 * (e1 + e2) - 0.5j * c2 * (e1 - e2))
        else:
            jp = _osc_from(e_1 * zk, 1.0 - w, S)
            jm = _osc_from(e_1.conjugate() * zk, -1.0 - w, S)
            dp = _divided(r - w, 1.0 - w, S, f_p * zk, er_p, jp)
            dm = _divided(-r - w, -1.0 - w, S, f_m * zk, er_m, jm)
            ic = 0.5 * inv * (dm - dp)
            isn = -0.5j * inv * (jp - jm - dp - dm)
            iq = (0.5 * (q0 + fk) * (jp + jm) - 0.5j * v0 * (jp - jm) - fk * j0
                  + A * ca * ic - A * sa * isn)
        harm[0, k] += rot * iq
        harm[1, k] += rot * fk * j0
        zk *= step
        rot *= turn


@jit
def add_stick(harm, qs, ta, tb, A, r):
    """Add the integrals over a stick at qs from ta to tb: q = qs, f = A cos(r t) - qs (exponentials carried
    over k as in add_slip)."""
    L = tb - ta
    if L <= 0.0:
        return
    e_p = _unit(r * ta)
    step = _unit(-r * L)
    turn = e_p.conjugate()
    e_r = _unit(r * L)
    zk = 1.0 + 0j
    rot = 1.0 + 0j
    for k in range(harm.shape[1]):
        w = k * r
        j0 = _osc_from(zk, -w, L)
        forcing = 0.5 * A * (e_p * _osc_from(e_r * zk, r - w, L) + turn * _osc_from(e_r.conjugate() * zk, -r - w, L))
        harm[0, k] += rot * qs * j0
        harm[1, k] += rot * (forcing - qs * j0)
        zk *= step
        rot *= turn


@jit
def add_stuck_slider(harm, scratch, t0, U, p0, pu0, K, m, kappa, Ap, r, rho, zp, om):
    """Add the integrals over a stick of the Jenkins contact's slider (kernels/jenkins.py) from t0, U long in its
    time u = om (t - t0): q = p + K, f = kappa (q - w) = kappa (p - m), where p obeys p_uu + 2 zp p_u + p =
    Ap cos(rho (om t0 + u)), a slip piece without friction in time u, which add_slip integrates against
    e^{-i k rho u} = e^{-i k r (t - t0)}; dt = du / om. scratch: a work array of harm's shape."""
    if U <= 0.0:
        return
    scratch[:, :] = 0.0
    add_slip(scratch, om * t0, p0, pu0, 1, U, Ap, rho, 0.0, zp)
    L = U / om
    step = _unit(-r * L)
    turn = _unit(-r * t0)
    zk = 1.0 + 0j
    rot = 1.0 + 0j
    for k in range(harm.shape[1]):
        const = rot * _osc_from(zk, -k * r, L)  # int e^{-i k r t} dt over the stick
        ip = scratch[0, k] / om
        harm[0, k] += ip + K * const
        harm[1, k] += kappa * (ip - m * const)
        zk *= step
        rot *= turn

