"""The three scenes as one equation (docs/equations.md §1).

Every scene reduces to q'' + 2 zeta q' + q + beta sgn(q') = A cos(r t) for a relative displacement q,
with the response x = q + c cos(r t); b = beta / A, the friction against the force amplitude, is the
ratio Den Hartog's closed forms take:

    force    a force F cos(w t) on the mass, fixed wall:              A = 1,   c = 0  (q = x)
    base     the base moves as y = cos(r t), the rubbing wall stays:  A = 1,   c = 0
    joined   base and wall move together as y: z = x - y obeys it    A = r^2, c = 1  (x = z + y)

The dashpot 2 zeta acts on q' (to the ground for force and base, on the relative velocity for joined),
except where it sits between the mass and the moving base of the base scene (`to: base`, in parallel
with the spring, docs/equations.md §6): there x'' + 2 zeta x' + x + beta sgn(x') = cos(r t) - 2 zeta r
sin(r t) = A cos(r t + lead), A = sqrt(1 + (2 zeta r)^2), lead = atan2(2 zeta r, 1). In the time
t' = t + lead / r that is the equation above with this A, so the kernels solve it unchanged, in a frame
whose forcing maximum (the section) is lead / r before the base's maximum; phases against the base then
lose `lead`.
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


def spring_parallel(excitation: str, place: str | None) -> bool:
    """Whether the dashpot sits in parallel with the spring of the base scene (its forcing then leads)."""
    return excitation == "base" and place == "base"


def forcing_lead(excitation: str, r, zeta: float = 0.0, place: str | None = None) -> np.ndarray:
    """How far (radians of forcing phase) the force on the equation's coordinate leads the excitation:
    atan2(2 zeta r, 1) for the spring-parallel dashpot, else 0; a float array shaped like r."""
    r = np.asarray(r, dtype=float)
    if not spring_parallel(excitation, place):
        return np.zeros_like(r)
    return np.arctan2(2.0 * zeta * r, 1.0)


def kernel_forcing(excitation: str, r: np.ndarray, zeta: float = 0.0,
                   place: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(A, c) per point, as float arrays shaped like r, for the simulation kernels (A = sqrt(1 + (2 zeta
    r)^2) for the spring-parallel dashpot)."""
    if spring_parallel(excitation, place):
        r = np.asarray(r, dtype=float)
        return np.hypot(1.0, 2.0 * zeta * r), np.zeros_like(r)
    return (np.asarray(forcing_amplitude(excitation, r)) * np.ones_like(r),
            np.full_like(r, response_offset(excitation)))
