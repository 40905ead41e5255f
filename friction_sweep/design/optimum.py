"""The optimum friction: the friction level beta that minimises the resonance peak P(beta) (peak.py), found
on the exact peak, with the performance curve P over the friction grid it came from.

The curve's smallest value on the grid, P[j], decides the search:

    interior   P[j] below both neighbours: a golden-section search for min P in [beta[j-1], beta[j+1]],
               to `beta_tol`; the optimum is the best level evaluated (never above the grid's P[j]).
    plateau    P[j] equal (to PLATEAU_RTOL) to P[j+1]: the peak no longer falls with more friction (the
               mass stays stuck where it would peak: T = 0 for base and force, the wall's own motion
               T = 1 for joined). The optimum is the least friction that reaches the plateau, bisected
               in [beta[j-1], beta[j]] on P(beta) <= P[j] (1 + PLATEAU_RTOL), to `beta_tol`.
    edge       P smallest at the grid's first or last level (and no plateau): not refined, the grid
               does not bracket a minimum.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from friction_sweep.design.peak import INV_PHI, Peaks, Response, peaks

#: default width, in beta, of the bracket the optimum is refined to
BETA_TOL = 1e-8
#: two peaks within this relative difference (or both zero) are one plateau
PLATEAU_RTOL = 1e-9


@dataclass
class Optimum:
    """The optimum friction level, its peak and where that peak lies, how it was found (`kind`), and
    the performance curve (`curve`, over the friction grid `beta`)."""

    force_ratio: float
    peak: float
    frequency_ratio: float
    regime: Any  # a float, or an array of one code per contact (a structure)
    kind: str
    beta: np.ndarray
    curve: Peaks


def _scalar(v: Any) -> Any:
    """A level's entry: a float, or (a structure's regime per contact) an array."""
    return float(v) if np.ndim(v) == 0 else np.asarray(v, dtype=float)


def _same(a: float, b: float) -> bool:
    return bool(a == b or abs(a - b) <= PLATEAU_RTOL * max(abs(a), abs(b)))


def optimum(problem: Response, r: np.ndarray, beta: np.ndarray, beta_tol: float = BETA_TOL,
            r_tol: float | None = None) -> Optimum:
    """The optimum over the increasing friction grid `beta` (at least 3 values), each level's peak over the
    frequency grid `r` (peak.peaks): see the module docstring."""
    beta = np.asarray(beta, dtype=float)
    if beta.ndim != 1 or beta.size < 3 or np.any(np.diff(beta) <= 0):
        raise ValueError("the friction grid must be at least 3 increasing values")
    kw = {} if r_tol is None else {"r_tol": r_tol}
    curve = peaks(problem, r, beta, **kw)
    best = curve.best()
    p = np.where(np.isnan(best["value"]), np.inf, best["value"])
    j = int(np.argmin(p))

    def at(b: float) -> dict[str, Any]:
        one = peaks(problem, r, np.array([b]), **kw).best()
        return {k: _scalar(v[0]) for k, v in one.items()}

    found = {k: _scalar(v[j]) for k, v in best.items()}
    b_opt = float(beta[j])
    if j + 1 < beta.size and _same(p[j], p[j + 1]):
        kind = "plateau"
        if j > 0:  # the least friction on the plateau: bisection between the last level above it and j
            lo, hi = float(beta[j - 1]), b_opt
            while hi - lo > beta_tol:
                mid = 0.5 * (lo + hi)
                trial = at(mid)
                if trial["value"] <= p[j] * (1.0 + PLATEAU_RTOL) or trial["value"] == p[j]:
                    hi, found = mid, trial
                else:
                    lo = mid
            b_opt = hi
        else:
            kind = "edge"
    elif j == 0 or j == beta.size - 1:
        kind = "edge"
    else:
        kind = "interior"
        lo, hi = float(beta[j - 1]), float(beta[j + 1])
        c, d = hi - INV_PHI * (hi - lo), lo + INV_PHI * (hi - lo)
        fc, fd = at(c), at(d)
        while hi - lo > beta_tol:
            for x, fx in ((c, fc), (d, fd)):
                if fx["value"] < found["value"]:
                    b_opt, found = x, fx
            if fc["value"] < fd["value"]:  # the minimum lies in [lo, d]
                hi, d, fd = d, c, fc
                c = hi - INV_PHI * (hi - lo)
                fc = at(c)
            else:
                lo, c, fc = c, d, fd
                d = lo + INV_PHI * (hi - lo)
                fd = at(d)
        for x, fx in ((c, fc), (d, fd)):
            if fx["value"] < found["value"]:
                b_opt, found = x, fx
    return Optimum(b_opt, found["value"], found["frequency_ratio"], found["regime"], kind, beta, curve)


def dataset(found: Optimum, attrs: dict, axes=None):
    """The performance curve (peak.dataset) with the optimum as scalars: optimum_force_ratio, optimum_peak,
    optimum_frequency_ratio, optimum_regime (named after `axes`, peak.Axes: a structure's optimum_friction_scale,
    optimum_frequency, optimum_regime per contact), and attribute optimum_kind (interior, plateau or edge)."""
    from friction_sweep.design import peak

    axes = peak.ONE_DOF if axes is None else axes
    ds = peak.dataset(found.curve, found.beta, {**attrs, "optimum_kind": found.kind}, axes=axes)
    ds[f"optimum_{axes.friction}"] = found.force_ratio
    ds["optimum_peak"] = found.peak
    ds[f"optimum_{axes.frequency}"] = found.frequency_ratio
    ds["optimum_regime"] = ((), found.regime) if axes.contacts is None else (("contact",), found.regime)
    return ds
