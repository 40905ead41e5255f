"""Absolute motion of the mass when the wall moves with the base (paper Sect. 4, Eqs. 36-44).

The relative motion z = x - y obeys the force problem with force amplitude k Y r^2, so in units of
Y: z(tau) = r^2 q(tau; b = beta / r^2) and, with the base y(tau) = cos(r tau + phi_yz) in the time
frame where z is maximal at tau = 0,

    x(tau) = r^2 q(tau) + cos(r tau + phi_yz)                       (paper Eq. 39)

|X|/|Y| = max |x| over a half period (Eq. 37) is found numerically: dense samples, then bisection
on d|x|/dtau between the neighbours of the best sample.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.theory import den_hartog as dh


def absolute_displacement(r, b, phi, tau):
    """x(tau) of Eq. (39), any tau; b is the friction ratio against the apparent force (beta/r^2)."""
    return r * r * dh.periodic(dh.waveform, r, b, tau) + np.cos(r * tau + phi)


def absolute_velocity(r, b, phi, tau):
    """x'(tau) = r^2 q'(tau) - r sin(r tau + phi)."""
    return r * r * dh.periodic(dh.waveform_velocity, r, b, tau) - r * np.sin(r * tau + phi)


def peak_of_absolute(r, b, phi, samples=None, iterations=64):
    """max |x| over a period and the time tau_x of the positive maximum of x, in [0, 2 pi / r).

    Arrays r, b, phi of one shape (the continuous points). |x| has period pi/r, so the samples
    wrap around and the refinement bracket never hits an end.
    """
    r, b, phi = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (r, b, phi)))
    if r.size == 0:
        return np.empty(r.shape), np.empty(r.shape)
    half = (np.pi / r)[..., None]
    m = samples or int(64 + np.ceil(16.0 * (1.0 + np.max(r)) / np.min(r)))
    tau = half * (np.arange(m) / m)
    rr, bb, pp = r[..., None], b[..., None], phi[..., None]
    x = absolute_displacement(rr, bb, pp, tau)
    k = np.argmax(np.abs(x), axis=-1)[..., None]
    t0 = np.take_along_axis(tau, k, axis=-1)
    sgn = np.sign(np.take_along_axis(x, k, axis=-1))
    h = half / m
    lo, hi = t0 - h, t0 + h
    # bisection on sgn * x' (decreasing through the maximum of |x|): exact to rounding in tau
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        rising = sgn * absolute_velocity(rr, bb, pp, mid) > 0.0
        lo = np.where(rising, mid, lo)
        hi = np.where(rising, hi, mid)
    t = 0.5 * (lo + hi)
    xt = absolute_displacement(rr, bb, pp, t)
    # guard: keep the best sample if refinement wandered (never larger than the true maximum)
    better = np.abs(xt) >= np.take_along_axis(np.abs(x), k, axis=-1)
    t = np.where(better, t, t0)
    xt = np.where(better, xt, np.take_along_axis(x, k, axis=-1))
    t_pos = np.where(xt >= 0.0, t, t + half)
    period = 2.0 * half
    return np.abs(xt)[..., 0], np.mod(t_pos, period)[..., 0]
