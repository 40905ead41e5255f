"""Every integer code the cube stores, once: the kernels, the schema's CF flags and the CLI read them here.

Each is an IntEnum whose member names, lower-cased, are the CF `flag_meanings` and whose values are the
`flag_values`. numba reads IntEnum members as integer constants, so the kernels use them directly.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np


class Regime(IntEnum):
    """Motion regime (variable `regime`)."""

    STUCK = 0  # the mass never moves relative to its wall
    STICK_SLIP = 1  # the mass stops (sticks) at least once per forcing period
    CONTINUOUS = 2  # one velocity reversal per half period, no stops (Den Hartog's regime)
    UNBOUNDED = 3  # the amplitude grows without bound (resonance with friction ratio < pi/4)
    UNSETTLED = 4  # no periodic steady state was found within the method's budget


class SteadyState(IntEnum):
    """Why the steady-state search of a simulation method stopped (variable `steady_state`)."""

    CONVERGED = 0  # the stroboscopic map repeated (period 1 or k) within tolerance
    PERIOD_CAP = 1  # no periodic state within the cap on forcing periods
    EVENT_BUDGET = 2  # the per-point work budget (events or steps) ran out
    NONFINITE = 3  # a state became NaN or infinite
    GROWING = 4  # the amplitude kept growing at a steady rate (reported as `unbounded`)
    NOT_SIMULATED = 5  # the point was not simulated (e.g. `auto` used the theory)
    # r = 1/(2n), no damping: a continuum of stick-free orbits; first-harmonic outputs are the family's,
    # peak outputs those of its half-wave symmetric (Den Hartog) member
    FAMILY = 6
    # no period-k orbit (k <= max_orbit_period) and nearby states do not draw together (Lyapunov exponent
    # of the stroboscopic map > -1/max_orbit_period): chaotic, quasi-periodic or a longer period; outputs
    # are averages over 256 forcing periods
    APERIODIC = 7
    # the orbit found does not balance its energy per period (kernels/balance.py: the forcing's work against
    # friction and viscous dissipation): the period map repeated it without resolving the dynamics (a
    # damping ratio far below rounding); reported as `unsettled`, without numbers
    UNBALANCED = 8


class MethodUsed(IntEnum):
    """Which way method `auto` computed a point (variable `method_used`)."""

    THEORY = 0
    EVENT = 1


def meanings(codes: type[IntEnum]) -> tuple[str, ...]:
    """The codes' names in code order (values run 0, 1, 2, ...): the CF flag_meanings."""
    return tuple(member.name.lower() for member in codes)


def flags(codes: type[IntEnum]) -> dict[str, object]:
    """The CF attributes of a variable holding these codes."""
    return {"flag_values": np.array([int(m) for m in codes], dtype=np.int8),
            "flag_meanings": " ".join(meanings(codes))}


def name_of(codes: type[IntEnum], code: int) -> str:
    """A code's name, or 'code N' for a value that is none of them."""
    try:
        return codes(int(code)).name.lower()
    except ValueError:
        return f"code {int(code)}"


def counts(values, codes: type[IntEnum] = Regime) -> dict[str, int]:
    """Number of grid points holding each code, by name (every code listed, zeros included)."""
    values = np.asarray(values).ravel()
    return {member.name.lower(): int(np.count_nonzero(values == member)) for member in codes}
