"""The force transmitted to the supports, from the response's first harmonic (docs/equations.md §6,
"Transmitted force"). Shared by every method that writes `transmitted_force`; numba-free.

The spring, the friction and the dashpot are the only forces on the mass besides a force applied to
it, so together they act on the supports (ground, base, wall) with

    base, joined:  m x''                  (units of kY: first harmonic r^2 X1)
    force:         F0 cos(w t) - m x''    (units of F0: first harmonic 1 + r^2 X1)

where X1 = T e^{-i phase} is the response's first harmonic against the excitation's (transmissibility T,
`phase` the lag of the response, so x ~ T cos(r t - phase)). Exact wherever the first harmonic is.
"""

from __future__ import annotations

import numpy as np


def transmitted_force(excitation: str, r, transmissibility, phase_degrees):
    """First-harmonic amplitude of the force the spring, friction and dashpot exert on the supports:
    r^2 T for base and joined (units of kY), |1 + r^2 T e^{-i phase}| for force (units of F0).

    NaN where T is NaN (no steady state). Where T = 0 (no motion) the phase is undefined (NaN) and
    not needed: base 0, force 1 (the wall holds the whole force).
    """
    r = np.asarray(r, dtype=float)
    t = np.asarray(transmissibility, dtype=float)
    if excitation != "force":
        return r * r * t
    lag = np.radians(np.where(t == 0.0, 0.0, np.asarray(phase_degrees, dtype=float)))
    rt = r * r * t
    return np.hypot(1.0 + rt * np.cos(lag), rt * np.sin(lag))
