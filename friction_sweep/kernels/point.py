"""One grid point's parameters as the kernels take them: a NamedTuple of floats.

The equation of every scene, in slip direction sig = +-1 (docs/equations.md §1):

    q'' + 2 zeta q' + q + sig bk = A cos(r t),    response x = q + c cos(r t),

stuck while |A cos(r t) - q| <= bs. numba compiles a NamedTuple of floats as a plain struct passed by
value (cache=True keeps working), so the six travel together through the drivers and the period
integrators; the closed-form segments below them take just the numbers their formulas use.
"""

from __future__ import annotations

from typing import NamedTuple


class Point(NamedTuple):
    A: float  # forcing amplitude
    r: float  # frequency ratio (forcing over natural frequency)
    bk: float  # kinetic friction
    bs: float  # static friction (>= bk)
    zeta: float  # viscous damping ratio
    c: float  # the excitation's share of the response: x = q + c cos(r t) (1 joined, 0 otherwise)


class JenkinsPoint(NamedTuple):
    """A point whose contact is a Jenkins element (effect contact_stiffness, docs/equations.md §7): Point's
    parameters and the contact spring's stiffness over the main spring's, kappa. The rigid kernels never
    see it: a point without the effect stays a Point, and its code path is untouched."""

    A: float
    r: float
    bk: float
    bs: float
    zeta: float
    c: float
    kappa: float  # contact stiffness k_t / k
