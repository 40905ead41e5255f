"""The energy balance of a measured orbit (friction_sweep.theory.energy): what makes a converged orbit a
steady state (issue 28).

Per forcing period, from the measurement's accumulator (measure.py) over the orbit's k periods:

    W  = A r IS / k                     the forcing's work (by parts; the boundary term A (q(kT) - q(0))
                                        is the orbit's closure, inside the slack)
    F  = bk slide / k                   kinetic friction times the distance q slides
    V1 = 2 pi zeta r |Q|^2, |Q| = (r / pi) |(IC, IS)| / k

An orbit that the period map repeats only because it cannot resolve the dynamics breaks the balance
(rounding swallowing the dashpot: a damping ratio below 2e-17 gave T = 68 at r = 1 for the exact 5e17).
The state's size Z is max(1, r) times the orbit's (the velocity ~ r q).
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import ACC_IC, ACC_IS, ACC_QMAX, ACC_SLIDE
from friction_sweep.kernels.period_map import map_error
from friction_sweep.kernels.settings import SET_STEADY_TOL
from friction_sweep.theory import energy

#: the balance's slack and test, compiled
slack = jit_inline(energy.slack)
holds = jit_inline(energy.holds)


@jit
def balanced(acc, orbit, p, settings, q, v):
    """Whether the orbit measured in `acc` over `orbit` periods from the state (q, v) balances its energy
    per period (theory.energy, with the terms of the module docstring)."""
    r = p.r
    W = p.A * r * acc[ACC_IS] / orbit
    F = p.bk * acc[ACC_SLIDE] / orbit
    Q = r / math.pi * math.hypot(acc[ACC_IC], acc[ACC_IS]) / orbit
    V1 = 2.0 * math.pi * p.zeta * r * Q * Q
    residual = W - F - V1
    size = max(1.0, r) * max(math.hypot(q, v), acc[ACC_QMAX], Q, p.A)
    tol = slack(settings[SET_STEADY_TOL] + map_error(r, settings), size, W, F, V1)
    return holds(residual, tol, p.zeta == 0.0 or (p.bk == 0.0 and p.bs == 0.0))
