"""The three scenes as one equation (docs/equations.md §1).

Every scene reduces to q'' + 2 zeta q' + q + beta sgn(q') = A cos(r t) for a relative displacement q,
with the response x = q + c cos(r t); b = beta / A, the friction against the force amplitude, is the
ratio Den Hartog's closed forms take:

    force    a force F cos(w t) on the mass, fixed wall:              A = 1,   c = 0  (q = x)
    base     the base moves as y = cos(r t), the rubbing wall stays:  A = 1,   c = 0
    joined   base and wall move together as y: z = x - y obeys it    A = r^2, c = 1  (x = z + y)
"""

from __future__ import annotations

import numpy as np


def forcing_amplitude(excitation: str, r):
    """A of the scene's equation at frequency ratio r (a float or an array, as r)."""
    return r * r if excitation == "joined" else 1.0


def response_offset(excitation: str) -> float:
    """c of x = q + c cos(r t)."""
    return 1.0 if excitation == "joined" else 0.0


def friction_ratio(excitation: str, r, beta):
    """b = beta / A: the friction force against the force amplitude, as Den Hartog's theory takes it."""
    return beta / (r * r) if excitation == "joined" else beta


def kernel_forcing(excitation: str, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(A, c) per point, as float arrays shaped like r, for the simulation kernels."""
    return (np.asarray(forcing_amplitude(excitation, r)) * np.ones_like(r),
            np.full_like(r, response_offset(excitation)))
