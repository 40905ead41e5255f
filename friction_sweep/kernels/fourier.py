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
def _osc_integral(a, S):
    """J(a) = int_0^S e^{i a s} ds for real a: S e^{i a S/2} sin(a S/2)/(a S/2)."""
    h = 0.5 * a * S
    f = S * sin_over(h)
    return complex(f * math.cos(h), f * math.sin(h))


@jit
def _divided(a, b, S):
    """D(a, b) = (J(a) - J(b)) / (a - b) for real a, b (J's derivative where a = b), to rounding for all a, b:
    |D| <= S^2 / 2, and the closed form's rounding, eps S / max(|a|, |b|), stays below eps S^2 where it is used."""
    if abs(a) < abs(b):
        a, b = b, a
    if abs(a) * S >= DIVIDED_SERIES_SPAN:
        m = 0.5 * (a + b)
        d = 0.5 * (a - b)
        return (S * cmath.exp(1j * m * S) * sin_over(d * S) - _osc_integral(b, S)) / a
    # D = sum_{j>=1} i^j S^{j+1}/(j+1)! h_j, h_j = (a^j - b^j)/(a - b) = a h_{j-1} + b^{j-1}
    total = 0j
    h = 1.0
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
def add_slip(harm, t0, q0, v0, sig, S, A, r, bk, zeta):
    """Add the integrals of q e^{-i k r t} and f e^{-i k r t}, k = 0..H, over a slip piece from (q0, v0) at t0
    to t0 + S in direction sig (friction f = sig bk), exactly (module docstring)."""
    if S <= 0.0:
        return
    ca = math.cos(r * t0)
    sa = math.sin(r * t0)
    fk = sig * bk
    inv = 1.0 / (1.0 + r)
    damped = zeta != 0.0
    c1 = c2 = wd = 0.0
    H = 0j
    if damped:
        # segments.slip_state's damped form: particular Re[H e^{i r s}], H = G e^{i r t0}, G = A/(1 - r^2 + 2i zeta r)
        den = complex(1.0 - r * r, 2.0 * zeta * r)
        H = A / den * complex(ca, sa)
        wd = math.sqrt(1.0 - zeta * zeta)
        c1 = q0 + fk - H.real
        c2 = (v0 + r * H.imag + zeta * c1) / wd
    for k in range(harm.shape[1]):
        w = k * r
        rot = complex(math.cos(w * t0), -math.sin(w * t0))  # e^{-i w t0}: the piece's local time to the period's
        j0 = _osc_integral(-w, S)
        if damped:
            e1 = _exp_integral(complex(-zeta, wd - w), S)
            e2 = _exp_integral(complex(-zeta, -wd - w), S)
            iq = (-fk * j0 + 0.5 * (H * _osc_integral(r - w, S) + H.conjugate() * _osc_integral(-r - w, S))
                  + 0.5 * c1 * (e1 + e2) - 0.5j * c2 * (e1 - e2))
        else:
            jp = _osc_integral(1.0 - w, S)
            jm = _osc_integral(-1.0 - w, S)
            dp = _divided(r - w, 1.0 - w, S)
            dm = _divided(-r - w, -1.0 - w, S)
            ic = 0.5 * inv * (dm - dp)
            isn = -0.5j * inv * (jp - jm - dp - dm)
            iq = (0.5 * (q0 + fk) * (jp + jm) - 0.5j * v0 * (jp - jm) - fk * j0
                  + A * ca * ic - A * sa * isn)
        harm[0, k] += rot * iq
        harm[1, k] += rot * fk * j0


@jit
def add_stick(harm, qs, ta, tb, A, r):
    """Add the integrals over a stick at qs from ta to tb: q = qs, f = A cos(r t) - qs."""
    L = tb - ta
    if L <= 0.0:
        return
    e_p = complex(math.cos(r * ta), math.sin(r * ta))
    for k in range(harm.shape[1]):
        w = k * r
        rot = complex(math.cos(w * ta), -math.sin(w * ta))
        j0 = _osc_integral(-w, L)
        forcing = 0.5 * A * (e_p * _osc_integral(r - w, L) + e_p.conjugate() * _osc_integral(-r - w, L))
        harm[0, k] += rot * qs * j0
        harm[1, k] += rot * (forcing - qs * j0)
