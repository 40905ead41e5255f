"""The energy balance per period that makes a periodic orbit a steady state, and its slack: the one
statement the kernels' acceptance (kernels/balance.py) and `fsweep check`'s rule `energy`
(friction_sweep/consistency.py) both apply.

Multiply q'' + 2 zeta q' + q + f = A cos(r t) by q' and integrate over the orbit's period: the change of
(q'^2 + q^2)/2, zero on a periodic orbit, is the forcing's work W less the friction's dissipation F and the
dashpot's V (docs/equations.md §6). Per forcing period, with Q the complex first harmonic of q against the
forcing, W = -pi A Im Q (only the first harmonic pairs with the forcing), F = kinetic friction x sliding
distance, and V >= V1 = 2 pi zeta r |Q|^2 (higher harmonics only add). So

    W = F + V1      where the motion is known in full: no damping, or no friction (a pure harmonic)
    W >= F + V1     elsewhere

An orbit accepted by a method closes to `closure` (its steady_tol plus its map's own error per period) of
its state's size Z, which changes its energy by about closure x Z^2: the balance holds to SAFETY times
that, plus RTOL of the energies for the rounding of their sums. Plain arithmetic, for floats and arrays
alike, so that the kernels jit these same functions.
"""

from __future__ import annotations

#: multiple of the closure's energy change (closure x Z^2) the balance may miss by
SAFETY = 10.0
#: relative rounding of the three energies' sums
RTOL = 1e-9


def slack(closure, size, W, F, V1):
    """How far W - F - V1 may miss the balance: SAFETY closure size^2 + RTOL (|W| + |F| + V1)."""
    return SAFETY * closure * size * size + RTOL * (abs(W) + abs(F) + V1)


def holds(residual, tol, equality):
    """Whether the residual W - F - V1 is within `tol` of the balance: of zero where `equality`, else of
    being nonnegative."""
    return (abs(residual) <= tol) if equality else (residual >= -tol)
