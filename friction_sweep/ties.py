"""The documented ties of the (r, beta) plane and the tolerance that decides them, for every method.

On a decimal grid two numbers that are equal on paper can differ by an ulp or two in binary: 0.2 * 0.2
is one ulp above 0.04, so a point on the joined no-motion boundary beta = r^2 would otherwise be
decided by rounding (and a motion of size 1e-17 would be simulated for the whole budget). Each tie is
therefore decided as if the two numbers were equal whenever they agree to TIE_RTOL, relative. The
tolerance is wider than rounding alone needs, so that it also covers what no method resolves: a force
that leaves the band by a fraction e of itself moves the mass by ~e^1.5 (below 1e-18 of the
excitation here, under the simulation's rounding), and within 1e-12 of r = 1 the resonant amplitude
(~1/(2|1 - r|) > 5e11) is beyond what the stroboscopic map can pin down (see kernels/shoot.py
RESOLVABLE), so the simulation reports `unbounded` there too.

    no motion from rest   A <= bs (1 + TIE_RTOL): the whole swing of the force stays inside the static
                          band (A = 1 for force/base, r*r for joined; bs = static friction ratio * beta),
                          the mass never moves (paper Eqs. 24, 41-42). The kernels apply the same test
                          to every stick: a stick at q whose band holds A + |q| never ends.
    resonance             |r - 1| <= TIE_RTOL counts as r = 1 (no damping: unbounded for b <= pi/4).
    resonance friction    at r = 1, b <= (pi/4) (1 + TIE_RTOL) is unbounded (Eqs. 14-15).
    subharmonic family    |2 n r - 1| <= TIE_RTOL counts as r = 1/(2n) (docs/equations.md §6).

The continuous limit beta*(r) keeps its own band: a stick shorter than 1e-10 of a period is a grazing
contact (kernels/stick.py GRAZING_STICK), so within ~1e-10 of beta* rounding of the simulation decides.
"""

from __future__ import annotations

import numpy as np

#: lim_{r -> 1} (-V/U): the friction ratio (against the force amplitude) up to which the resonance
#: grows without bound (paper Eqs. 14-15)
RESONANCE_FRICTION_LIMIT = float(np.pi / 4.0)

#: relative tolerance of every documented tie (products of decimal grid values differ by 1-2 ulps)
TIE_RTOL = 1e-12


def at_resonance(r):
    """r = 1 to within the tie tolerance (elementwise)."""
    return np.abs(np.asarray(r, dtype=float) - 1.0) <= TIE_RTOL


def never_moves(force_amplitude, static_friction):
    """The force's whole swing stays inside the static band, to within the tie tolerance (elementwise)."""
    return np.asarray(force_amplitude) <= np.asarray(static_friction) * (1.0 + TIE_RTOL)


def subharmonic_order(r):
    """n where r = 1/(2n) to within the tie tolerance, else 0 (elementwise)."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore"):
        n = np.rint(0.5 / r)
    ok = (n >= 1) & (np.abs(2.0 * n * r - 1.0) <= TIE_RTOL)
    return np.where(ok, n, 0).astype(np.int64)
