"""The phase resonance: for each friction level beta, every frequency ratio r where the response's first
harmonic lags the excitation by 90 degrees,

    phase(r, beta) = 90,

located on the exact solver. Each sign change of phase - 90 between neighbours of the frequency grid is
bisected on the per-point solve to `r_tol` in r. Where the phase jumps across 90 instead of passing
through it (the bracket's ends still differ by more than JUMP_DEG once narrowed), there is no crossing,
and none is reported. The response (T) and regime are those at the crossing.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from friction_sweep.design.peak import R_TOL, Response

#: degrees of phase the ends of a narrowed bracket may still differ by at a crossing (at r_tol = 1e-10
#: a slope of 1e7 degrees per unit r)
JUMP_DEG = 1e-3


@dataclass
class Crossings:
    """Every 90-degree crossing of each friction level, in increasing r, NaN-padded to `size`."""

    frequency_ratio: np.ndarray  # (levels, size)
    value: np.ndarray
    regime: np.ndarray  # (levels, size[, contacts])


def crossings(problem: Response, r: np.ndarray, beta: np.ndarray, r_tol: float = R_TOL,
              grid_phase: np.ndarray | None = None) -> Crossings:
    """The phase-resonance points over the increasing grid r for each beta (1-D); `grid_phase`: the phase on
    the grid (levels x r) where the caller has it already (peak.Peaks.grid_phase)."""
    r = np.asarray(r, dtype=float)
    beta = np.atleast_1d(np.asarray(beta, dtype=float))
    if grid_phase is None:
        R, B = np.meshgrid(r, beta)
        phase = problem.solve(R.ravel(), B.ravel())[2].reshape(R.shape)
    else:
        phase = grid_phase
    below = phase - 90.0
    change = np.isfinite(below[:, :-1]) & np.isfinite(below[:, 1:]) & ((below[:, :-1] < 0) != (below[:, 1:] < 0))
    level, i = np.nonzero(change)
    lo, hi = r[i], r[i + 1]
    lo_below = below[level, i] < 0
    f_lo, f_hi = phase[level, i], phase[level, i + 1]
    while lo.size and np.max(hi - lo) > r_tol:
        mid = 0.5 * (lo + hi)
        _, _, ph_mid = problem.solve(mid, beta[level])
        mid_below = ph_mid < 90.0
        same = mid_below == lo_below  # the crossing lies above mid
        lo, f_lo = np.where(same, mid, lo), np.where(same, ph_mid, f_lo)
        hi, f_hi = np.where(same, hi, mid), np.where(same, f_hi, ph_mid)
    x = 0.5 * (lo + hi)
    crossing = np.abs(f_hi - f_lo) <= JUMP_DEG
    value, regime, _ = problem.solve(x, beta[level]) if x.size else (x, x, x)
    rows: list[list[tuple[float, float, Any]]] = [[] for _ in beta]
    for k in np.nonzero(crossing)[0]:
        rows[level[k]].append((x[k], value[k], regime[k]))
    size = max(1, max(len(found) for found in rows))
    shape = (beta.size, size)
    extra = np.shape(regime)[1:]  # a structure's regime: one per contact
    out = Crossings(np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape + extra, np.nan))
    for j, found in enumerate(rows):
        for m, (rx, v, g) in enumerate(found):
            out.frequency_ratio[j, m], out.value[j, m], out.regime[j, m] = rx, v, g
    return out
