"""The energy balance of a measured orbit: what makes a converged orbit a steady state (issue 28).

Multiply q'' + 2 zeta q' + q + f = A cos(r t) by q' and integrate over the orbit's k measured periods: the
forcing's work equals the friction's dissipation plus the dashpot's, plus the change of (q^2 + q'^2)/2,
which is zero on a periodic orbit. Per forcing period, from the measurement's accumulator (measure.py):

    W  = A r IS / k                     the forcing's work (by parts: only q's first harmonic pairs with
                                        it; the boundary term A (q(kT) - q(0)) is the orbit's closure)
    F  = bk slide / k                   kinetic friction times the distance q slides
    V1 = 2 pi zeta r |Q|^2, |Q| = (r / pi) |(IC, IS)| / k
                                        the dashpot's loss by q's first harmonic alone; higher harmonics
                                        only add to it

so W = F + V1 where the motion is known in full (no damping; or no friction, a pure harmonic) and
W >= F + V1 elsewhere. An orbit that the period map repeats only because it cannot resolve the
dynamics (rounding swallowing the dashpot: a damping ratio below 2e-17 gave T = 68 at r = 1 for the
exact 5e17) breaks it. The slack is what the acceptance itself allows: an orbit closed to
(steady_tol + the map's own error) of its state's size Z changes its energy by about that times Z^2
(Z = max(1, r) times the orbit's size: the velocity ~ r q), plus BALANCE_RTOL of the energies for the
rounding of their sums. friction_sweep.consistency's rule `energy` states the same on a cube's outputs.
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import ACC_IC, ACC_IS, ACC_QMAX, ACC_SLIDE
from friction_sweep.kernels.period_map import map_error
from friction_sweep.kernels.settings import SET_STEADY_TOL

#: multiple of the closure's energy (steady_tol + map error) x Z^2 the balance may miss by
BALANCE_SAFETY = 10.0
#: relative rounding of the three energies' sums
BALANCE_RTOL = 1e-9


@jit
def balanced(acc, orbit, p, settings, q, v):
    """Whether the orbit measured in `acc` over `orbit` periods from the state (q, v) balances its energy
    per period (module docstring)."""
    r = p.r
    W = p.A * r * acc[ACC_IS] / orbit
    F = p.bk * acc[ACC_SLIDE] / orbit
    Q = r / math.pi * math.hypot(acc[ACC_IC], acc[ACC_IS]) / orbit
    V1 = 2.0 * math.pi * p.zeta * r * Q * Q
    residual = W - F - V1
    size = max(1.0, r) * max(math.hypot(q, v), acc[ACC_QMAX], Q, p.A)
    tol = (BALANCE_SAFETY * (settings[SET_STEADY_TOL] + map_error(r, settings)) * size * size
           + BALANCE_RTOL * (abs(W) + F + V1))
    if p.zeta == 0.0 or (p.bk == 0.0 and p.bs == 0.0):
        return abs(residual) <= tol
    return residual >= -tol
