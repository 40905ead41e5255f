"""Values of one grid axis from its {start, stop, num} or {start, stop, step} form."""

from __future__ import annotations

import math

import numpy as np

MAX_POINTS = 10_000_000
#: the meaningful range of frequency ratios. Below it the motion is quasi-static with ever more stops
#: per period and the cost of a point grows like 1/r^2 (theory) or 1/r^1.5 (event); above it the
#: response is below 1e-4 of the excitation, where the theory's closed forms lose their digits.
FREQUENCY_RATIO_RANGE = (0.01, 100.0)
FREQUENCY_RATIO_NOTE = ("frequency ratios are computed from 0.01 to 100: below, a point's cost grows without "
                        "bound; above, the response is under 1e-4 of the excitation")
#: friction beyond this holds the mass still everywhere on the grid (joined moves only if beta < r^2)
FORCE_RATIO_MAX = 1e6
FORCE_RATIO_NOTE = "force ratios above 1e6 hold the mass still at every frequency ratio"
#: a positive force ratio below this dissipates less per period than rounding resolves: the transient
#: from rest never decays within any budget (wrong peaks, measured at 1e-16); 0 is the forced orbit
FORCE_RATIO_MIN_POSITIVE = 1e-12
#: the bounds in words, for messages about values outside them
FREQUENCY_RATIO_SPAN = f"between {FREQUENCY_RATIO_RANGE[0]:g} and {FREQUENCY_RATIO_RANGE[1]:g}"
FORCE_RATIO_SPAN = f"0 or between {FORCE_RATIO_MIN_POSITIVE:g} and {FORCE_RATIO_MAX:g}"


def frequency_ratio_ok(r):
    """Whether r is in the meaningful range: a bool for a number, elementwise for an array (NaN is not)."""
    return (FREQUENCY_RATIO_RANGE[0] <= r) & (r <= FREQUENCY_RATIO_RANGE[1])


def force_ratio_ok(beta):
    """Whether beta is 0 or in the resolved range: a bool for a number, elementwise for an array."""
    return (beta == 0) | ((FORCE_RATIO_MIN_POSITIVE <= beta) & (beta <= FORCE_RATIO_MAX))
SIGNIFICANT_DIGITS = 12
LATTICE_RTOL = 1e-9


def round_significant(values: np.ndarray) -> np.ndarray:
    """Round to 12 significant digits, so decimal steps land on decimals (0.05 + 95*0.01 == 1.0)."""
    # Formatting is the exact, documented rule; a vectorised scale-and-round differs in the last ulp.
    return np.array([float(f"{v:.{SIGNIFICANT_DIGITS}g}") for v in values.tolist()], dtype=np.float64)


def step_count(start: float, stop: float, step: float) -> tuple[int, bool]:
    """(number of points, whether stop is on the step lattice); the count may exceed MAX_POINTS."""
    q = (stop - start) / step
    if not math.isfinite(q) or q >= MAX_POINTS:
        return MAX_POINTS + 1, False
    k = round(q)
    if abs(q - k) <= LATTICE_RTOL * max(1.0, abs(q)):
        return k + 1, True
    return math.floor(q) + 1, False


def linspace_values(start: float, stop: float, num: int) -> np.ndarray:
    """Inclusive linspace, rounded, with the exact ends kept."""
    values = round_significant(np.linspace(start, stop, num))
    values[0], values[-1] = start, stop
    return values


def step_values(start: float, stop: float, step: float) -> np.ndarray:
    """start + i*step up to stop (inclusive when stop is on the lattice), rounded, exact ends kept."""
    n, on_lattice = step_count(start, stop, step)
    values = round_significant(start + np.arange(n, dtype=np.float64) * step)
    values[0] = start
    if on_lattice:
        values[-1] = stop
    return values


def first_not_increasing(values: np.ndarray) -> int | None:
    """Index of the first value not greater than its predecessor, or None."""
    bad = np.flatnonzero(np.diff(values) <= 0)
    return int(bad[0]) + 1 if bad.size else None
