"""Den Hartog's closed-form steady state for continuous (non-stop) motion.

Dimensionless problem (docs/equations.md §1): q'' + q + b sgn(q') = cos(r tau + phi), lengths in units of
the force amplitude over k, b = friction force / force amplitude. Everything here is a function of
(r, b) only and works elementwise on broadcastable numpy arrays.

The printed functions (paper Eqs. 9, 11, 12, 16)

    V(r) = 1 / (1 - r^2)
    U(r) = tan(pi / (2 r)) / r  =  sin(pi/r) / (r (1 + cos(pi/r)))      (Eq. 15 corrected)

both blow up at r = 1 and cancel in every physical quantity. We therefore carry the regularised
damping function

    Uc(r) = (1 - r) U(r) = -(2/pi) a cot(a),   a = pi (r - 1) / (2 r),

which is finite at r = 1 (Uc = -2/pi) and is computed without cancellation because r - 1 is exact.
With (1 - r) V = 1 / (1 + r) every closed form below is rewritten in terms of Uc, so nothing
divides by 1 - r^2. U itself is genuinely singular at r = 1/3, 1/5, ... (a = -k pi): there the
continuous solution does not exist for b > 0 and the continuous limit tends to 0.
"""

from __future__ import annotations

import functools

import numpy as np

from friction_sweep.ties import RESONANCE_FRICTION_LIMIT  # noqa: F401  (pi/4, part of this module's API)

PI = np.pi


def _acota(a):
    """a * cot(a), with its limit 1 at a = 0."""
    a = np.asarray(a, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = a / np.tan(a)
    return np.where(a == 0.0, 1.0, out)


def response_function(r):
    """V(r) = 1 / (1 - r^2) (paper Eq. 9); infinite at r = 1."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / ((1.0 - r) * (1.0 + r))


def damping_function(r):
    """U(r) = tan(pi/(2r)) / r (paper Eq. 9 and the corrected Eq. 15); infinite at r = 1, 1/3, ..."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return regularised_damping_function(r) / (1.0 - r)


def regularised_damping_function(r):
    """Uc(r) = (1 - r) U(r) = -(2/pi) a cot(a) with a = pi (r - 1) / (2 r); Uc(1) = -2/pi."""
    r = np.asarray(r, dtype=float)
    a = PI * (r - 1.0) / (2.0 * r)
    return -(2.0 / PI) * _acota(a)


def _g(r, tau):
    """g(tau) = sin((1 - r) tau / 2) / (1 - r), -> tau / 2 as r -> 1 (docs/equations.md §3)."""
    return 0.5 * tau * np.sinc((1.0 - r) * tau / (2.0 * PI))


def _s_ratio(r, uc, tau):
    """The bracket of paper Eq. (12): [r sin t + U r^2 (cos rt - cos t)] / sin(rt).

    cos(rt) - cos(t) = 2 (1 - r) sin((1 + r) t / 2) g(t), so U (cos rt - cos t) uses Uc only.
    """
    num = r * np.sin(tau) + 2.0 * r * r * uc * np.sin(0.5 * (1.0 + r) * tau) * _g(r, tau)
    return num / np.sin(r * tau)


def _sample_count(r, per_natural_period, minimum):
    """Samples over a half forcing period pi/r that resolve both the natural and the forcing period."""
    return int(max(minimum, np.ceil(per_natural_period * (1.0 + np.max(r)) / (2.0 * np.min(r)))))


def _golden_max(f, lo, hi, iterations=90):
    """Vectorised golden-section search for the maximum of f on [lo, hi] (unimodal near a sample max)."""
    invphi = (np.sqrt(5.0) - 1.0) / 2.0
    lo = lo.copy()
    hi = hi.copy()
    c = hi - invphi * (hi - lo)
    d = lo + invphi * (hi - lo)
    fc = f(c)
    fd = f(d)
    for _ in range(iterations):
        left = fc > fd  # keep [lo, d]
        hi = np.where(left, d, hi)
        lo = np.where(left, lo, c)
        new_c = hi - invphi * (hi - lo)
        new_d = lo + invphi * (hi - lo)
        # one new evaluation per side is enough in exact arithmetic; two keep it simple and vectorised
        c, d = new_c, new_d
        fc, fd = f(c), f(d)
    x = 0.5 * (lo + hi)
    return x, f(x)


def s_function(r, samples_per_natural_period=256, min_samples=2048):
    """S(r) = sup over 0 < tau < pi/r of the bracket of paper Eq. (12).

    The bracket is 0/0 at tau = 0 (limit 1) and at tau = pi/r (limit -1), so the sup is max(1,
    interior maximum). The interior is sampled densely, then the best sample is refined by a
    golden-section search between its neighbours.
    """
    r = np.atleast_1d(np.asarray(r, dtype=float))
    uc = regularised_damping_function(r)
    lo = np.empty_like(r)
    hi = np.empty_like(r)
    sampled = np.empty_like(r)
    for i, ri in enumerate(r):
        n = _sample_count(ri, samples_per_natural_period, min_samples)
        # stay off the 0/0 ends: near tau = pi/r the numerator cancels catastrophically
        tau = np.linspace(0.0, PI / ri, n + 2)[1:-1]
        with np.errstate(divide="ignore", invalid="ignore"):
            vals = _s_ratio(ri, uc[i], tau)
        vals = np.where(np.isfinite(vals), vals, -np.inf)
        k = int(np.argmax(vals))
        lo[i], hi[i], sampled[i] = tau[max(k - 1, 0)], tau[min(k + 1, n - 1)], vals[k]
    # one golden-section search for every r at once (a Python loop per r cost ~2 ms each)
    with np.errstate(divide="ignore", invalid="ignore"):
        _, best = _golden_max(lambda t: _s_ratio(r, uc, t), lo, hi)
    return np.fmax(1.0, np.fmax(best, sampled))  # a NaN from the search leaves the others


def continuous_limit(r, s=None):
    """beta*(r) = sqrt(V^2 / ((S/r^2)^2 + U^2)) (paper Eq. 16, corrected with (S/r^2)^2).

    Multiplying through by |1 - r|: beta* = (1/(1+r)) / sqrt((S (1-r)/r^2)^2 + Uc^2), finite at
    r = 1 where it equals pi/4. Friction ratios strictly below beta* give continuous motion.
    """
    r = np.asarray(r, dtype=float)
    if s is None:
        s = s_function(r).reshape(r.shape)
    uc = regularised_damping_function(r)
    return (1.0 / (1.0 + r)) / np.hypot(s * (1.0 - r) / (r * r), uc)


def amplitude(r, b):
    """x0 = sqrt(V^2 - b^2 U^2) (paper Eq. 11), as sqrt(1/(1+r)^2 - b^2 Uc^2) / |1 - r|.

    NaN where the radicand is negative (no continuous solution) and at r = 1.
    """
    r = np.asarray(r, dtype=float)
    b = np.asarray(b, dtype=float)
    uc = regularised_damping_function(r)
    rad = 1.0 / (1.0 + r) ** 2 - (b * uc) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        x0 = np.sqrt(np.where(rad >= 0.0, rad, np.nan)) / np.abs(1.0 - r)
    return np.where(r == 1.0, np.nan, x0)


def phase(r, b):
    """Den Hartog's phase phi between the maxima of force and displacement, radians (paper Eq. 10).

    sin phi = -b U / V = -b Uc (1 + r), cos phi = x0 / V = sign(1 - r) sqrt(1 - sin^2 phi).
    The displacement maximum follows the force maximum by phi. NaN where no continuous solution.
    """
    r = np.asarray(r, dtype=float)
    b = np.asarray(b, dtype=float)
    uc = regularised_damping_function(r)
    s = -b * uc * (1.0 + r)
    c2 = 1.0 - s * s
    c = np.sign(1.0 - r) * np.sqrt(np.where(c2 >= 0.0, c2, np.nan))
    phi = np.arctan2(s, c)
    return np.where(r == 1.0, np.nan, phi)


def waveform(r, b, tau):
    """Displacement over the half period 0 <= tau <= pi/r, from the maximum at tau = 0.

    q(tau) = -b cos tau + r V sin(phi) sin tau + V cos(r tau + phi) + b      (docs/equations.md §2)
           = x0 cos(r tau) + b [(1 - cos tau) + Uc (sin tau - 2 cos((1 + r) tau / 2) g(tau))]

    using V sin phi = -b U, V cos phi = x0 and sin(r t) - r sin t = (1 - r) sin t
    - 2 cos((1 + r) t/2) sin((1 - r) t/2). The second half period is q(tau + pi/r) = -q(tau).
    """
    r = np.asarray(r, dtype=float)
    b = np.asarray(b, dtype=float)
    x0 = amplitude(r, b)
    uc = regularised_damping_function(r)
    return x0 * np.cos(r * tau) + b * _friction_part(r, uc, tau)


def _friction_part(r, uc, tau):
    """h(tau) = (1 - cos tau) + Uc (sin tau - 2 cos((1 + r) tau/2) g(tau)): q = x0 cos(r tau) + b h."""
    return (1.0 - np.cos(tau)) + uc * (np.sin(tau) - 2.0 * np.cos(0.5 * (1.0 + r) * tau) * _g(r, tau))


def waveform_velocity(r, b, tau):
    """q'(tau) = -r x0 sin(r tau) + b [sin tau + 2 r Uc sin((1 + r) tau / 2) g(tau)]."""
    r = np.asarray(r, dtype=float)
    b = np.asarray(b, dtype=float)
    x0 = amplitude(r, b)
    uc = regularised_damping_function(r)
    return -r * x0 * np.sin(r * tau) + b * (
        np.sin(tau) + 2.0 * r * uc * np.sin(0.5 * (1.0 + r) * tau) * _g(r, tau)
    )


def periodic(fun, r, b, tau):
    """Evaluate a half-period waveform function anywhere, using q(tau + pi/r) = -q(tau)."""
    half = PI / r
    k = np.floor(tau / half)
    sign = np.where(np.mod(k, 2.0) == 0.0, 1.0, -1.0)
    return sign * fun(r, b, tau - k * half)


def section_state(r, b):
    """(q, q') of the continuous orbit at the force's maximum, tau = -phi/r (the force cos(r tau + phi)
    peaks there): the state at the simulation's period boundary, in units of the force amplitude
    over k. NaN where there is no continuous solution."""
    tau = -phase(r, b) / np.asarray(r, dtype=float)
    return periodic(waveform, r, b, tau), periodic(waveform_velocity, r, b, tau)


def gauss_legendre_nodes(r):
    """Node count for exact-to-rounding projection of the waveform over a half forcing period.

    The integrands oscillate with angular frequency at most 1 + r over a length pi/r, i.e.
    (1 + r) pi / r radians; Gauss-Legendre converges geometrically once the node count exceeds
    about half of that, so this leaves a factor of two in hand.
    """
    r = float(np.min(r))
    return int(40 + np.ceil((1.0 + r) * PI / r))


@functools.lru_cache(maxsize=64)
def _leggauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights, computed once per count (an eigenvalue problem each time
    otherwise: most of a calibration step's theory cost); read-only, as every caller shares them."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def first_harmonic(r, b, nodes=None):
    """First-harmonic coefficients (a1, b1) of q over a full period, q ~ a1 cos(r t) + b1 sin(r t).

    a1 = (2r/pi) int_0^{pi/r} q cos(r t) dt, b1 likewise with sin (the half-wave antisymmetry
    q(t + pi/r) = -q(t) doubles the half-period integral). The x0 cos(r t) part projects exactly
    onto (x0, 0); only the bounded friction part h is integrated, by Gauss-Legendre quadrature.
    """
    r = np.asarray(r, dtype=float)
    b = np.asarray(b, dtype=float)
    r, b = np.broadcast_arrays(r, b)
    n = nodes if nodes is not None else gauss_legendre_nodes(r) if r.size else 1
    x, w = _leggauss(n)
    half = PI / r[..., None]
    tau = 0.5 * half * (x + 1.0)
    weights = 0.5 * half * w
    uc = regularised_damping_function(r)[..., None]
    h = _friction_part(r[..., None], uc, tau)
    scale = 2.0 * r / PI
    ca = scale * np.sum(weights * h * np.cos(r[..., None] * tau), axis=-1)
    cb = scale * np.sum(weights * h * np.sin(r[..., None] * tau), axis=-1)
    x0 = amplitude(r, b)
    return x0 + b * ca, b * cb
