"""Motion regimes: small integer codes shared by every method and stored as CF flags."""

from __future__ import annotations

import numpy as np

STUCK = np.int8(0)  # the mass never moves relative to its wall
STICK_SLIP = np.int8(1)  # the mass stops (sticks) at least once per forcing period
CONTINUOUS = np.int8(2)  # one velocity reversal per half period, no stops (Den Hartog's regime)
UNBOUNDED = np.int8(3)  # the amplitude grows without bound (resonance with friction ratio < pi/4)
UNSETTLED = np.int8(4)  # no periodic steady state was found within the method's budget

#: code -> name, in code order; the names are the CF flag_meanings.
NAMES = ("stuck", "stick_slip", "continuous", "unbounded", "unsettled")
FLAG_VALUES = np.arange(len(NAMES), dtype=np.int8)
FLAG_MEANINGS = " ".join(NAMES)


def counts(codes) -> dict[str, int]:
    """Number of grid points in each regime, by name (every regime listed, zeros included)."""
    codes = np.asarray(codes).ravel()
    return {name: int(np.count_nonzero(codes == value)) for value, name in zip(FLAG_VALUES, NAMES)}


# Why the steady-state search of a simulation method stopped (variable `steady_state`).
CONVERGED = np.int8(0)  # the stroboscopic map repeated (period 1 or k) within tolerance
PERIOD_CAP = np.int8(1)  # no periodic state within the cap on forcing periods
EVENT_BUDGET = np.int8(2)  # the per-point work budget (events or steps) ran out
NONFINITE = np.int8(3)  # a state became NaN or infinite
GROWING = np.int8(4)  # the amplitude kept growing at a steady rate (reported as `unbounded`)
NOT_SIMULATED = np.int8(5)  # the point was not simulated (e.g. `auto` used the theory)
FAMILY = np.int8(6)  # r = 1/(2n), no damping: a continuum of stick-free orbits; first-harmonic outputs are
#                      the family's, peak outputs those of its half-wave symmetric (Den Hartog) member

APERIODIC = np.int8(7)  # no period-k orbit (k <= max_orbit_period) and nearby states do not draw together
#                         (Lyapunov exponent of the stroboscopic map > -1/max_orbit_period): chaotic,
#                         quasi-periodic or a longer period; outputs are averages over 256 forcing periods

STEADY_NAMES = ("converged", "period_cap", "event_budget", "nonfinite", "growing", "not_simulated", "family",
                "aperiodic")
STEADY_FLAG_VALUES = np.arange(len(STEADY_NAMES), dtype=np.int8)
STEADY_FLAG_MEANINGS = " ".join(STEADY_NAMES)
