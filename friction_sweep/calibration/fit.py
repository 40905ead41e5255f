"""Stage one: the maximum a posteriori fit, by SciPy's least squares, with its residual table.

The likelihood is discontinuous in the natural frequency where a row's r crosses resonance
(posterior.py), and smooth in between. So the natural frequency's prior range (its central 99.9 %) is cut
at every row's crossing f_n = f_i, each interval is fitted on its own with the search bounded inside it
(a trust-region least squares cannot cross a jump), and the best interval wins. The noise levels are
profiled: least squares on the other parameters at fixed noise, then the noise levels that maximise the
posterior at those residuals, alternately until nothing moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import optimize

from .posterior import Posterior

#: central prior mass searched for the natural frequency's intervals
PRIOR_MASS = 0.999
#: least squares <-> noise profiling rounds at most
ROUNDS = 6


@dataclass
class MapFit:
    theta: np.ndarray  # (ndim,)
    log_posterior: float
    table: pd.DataFrame  # one row per measured row
    intervals: int  # natural-frequency intervals searched


def fit_map(post: Posterior) -> MapFit:
    """The MAP over every natural-frequency interval (or the one search without that parameter)."""
    model = post.model
    noise = [i for i, p in enumerate(model.parameters) if p.kind.startswith("noise_")]
    physical = [i for i in range(model.ndim) if i not in noise]
    x0 = np.array([_start(p.prior) for p in model.parameters])
    lower = np.array([p.prior.support[0] for p in model.parameters])
    upper = np.array([p.prior.support[1] for p in model.parameters])
    boxes = [(lower.copy(), upper.copy(), x0.copy())]
    fn_index = model.names.index("natural_frequency") if "natural_frequency" in model.names else None
    if fn_index is not None:
        boxes = []
        prior = model.parameters[fn_index].prior
        lo, hi = (float(q) for q in prior.quantile([(1 - PRIOR_MASS) / 2, (1 + PRIOR_MASS) / 2]))
        reference = model.spec.reference_frequency or 1.0
        crossings = np.unique(model.obs.frequency_ratio * reference)
        cuts = np.concatenate(([lo], crossings[(crossings > lo) & (crossings < hi)], [hi]))
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            box_lo, box_hi, start = lower.copy(), upper.copy(), x0.copy()
            pad = 1e-9 * (b - a)
            box_lo[fn_index], box_hi[fn_index] = a + pad, b - pad
            start[fn_index] = 0.5 * (a + b)
            boxes.append((box_lo, box_hi, start))
    best: tuple[float, np.ndarray] | None = None
    for box_lo, box_hi, start in boxes:
        theta, lp = _fit_box(post, start, box_lo, box_hi, physical, noise)
        if math.isfinite(lp) and (best is None or lp > best[0]):
            best = (lp, theta)
    if best is None:
        lp, theta = -math.inf, x0
    else:
        lp, theta = best
    return MapFit(theta, lp, residual_table(post, theta), len(boxes))


def _start(prior) -> float:
    lo, hi = prior.support
    x = float(prior.quantile(0.5))
    return min(max(x, lo), hi)


def _fit_box(post: Posterior, x: np.ndarray, lo: np.ndarray, hi: np.ndarray, physical: list[int],
             noise: list[int]) -> tuple[np.ndarray, float]:
    model = post.model
    x = np.clip(x, lo, hi)
    span = np.array([p.prior.std() for p in model.parameters])
    scale = np.where(np.isfinite(span) & (span > 0), span, 1.0)
    for _ in range(ROUNDS):
        before = x.copy()
        if physical:
            def fun(y, x=x):
                theta = x.copy()
                theta[physical] = y
                return post.residuals(theta[None, :], model.predict(theta[None, :]))

            def jac(y, x=x):
                # forward differences, every perturbed vector in one model call (one kernel call for all)
                step = np.sqrt(np.finfo(float).eps) * np.maximum(np.abs(y), scale[physical])
                step = np.where(y + step > hi[physical], -step, step)
                thetas = np.repeat(x[None, :], len(y) + 1, axis=0)
                thetas[:, physical] = y
                thetas[1:, physical] += np.diag(step)
                predicted = model.predict(thetas)
                res = np.stack([post.residuals(thetas[k:k + 1], {n: v[k:k + 1] for n, v in predicted.items()})
                                for k in range(len(y) + 1)])
                return ((res[1:] - res[0]) / step[:, None]).T

            ys = optimize.least_squares(fun, x[physical], jac=jac, bounds=(lo[physical], hi[physical]),
                                        x_scale=scale[physical], method="trf")
            x[physical] = ys.x
        if noise:
            predicted = model.predict(x[None, :])

            def neg(z, x=x, predicted=predicted):
                theta = x.copy()
                theta[noise] = np.exp(z)
                lp = post.log_prior(theta[None, :])[0]
                return -(lp + post.pointwise(theta[None, :], predicted)[0, post.rows].sum())

            z = optimize.minimize(neg, np.log(np.maximum(x[noise], 1e-6)), method="Nelder-Mead",
                                  options={"xatol": 1e-8, "fatol": 1e-10})
            x[noise] = np.exp(z.x)
        if np.allclose(x, before, rtol=1e-7, atol=1e-9 * scale):  # a parameter near 0 settles absolutely
            break
    return x, float(post(x[None, :])[0])


def residual_table(post: Posterior, theta: np.ndarray) -> pd.DataFrame:
    """Per measured row at `theta`: its line, series, r and beta as the model sees them, measured and
    predicted values, the misfit (phase wrapped into [-180, 180)) and whether it was fitted."""
    model = post.model
    obs = model.obs
    theta = np.atleast_2d(theta)
    r, beta = model.points(theta)
    predicted = model.predict(theta)
    table = pd.DataFrame({
        "line": obs.lines,
        "series": [obs.series_labels[s] for s in obs.series],
        "frequency_ratio": r[0],
        "force_ratio": beta[0],
    })
    if obs.phase is not None:
        model_phase = predicted["phase"][0] + post.offset(theta)[0]
        table["phase_measured_deg"] = obs.phase
        table["phase_predicted_deg"] = model_phase
        table["phase_residual_deg"] = np.mod(obs.phase - model_phase + 180.0, 360.0) - 180.0
        table["phase_residual_sd"] = table["phase_residual_deg"] / post.phase_sd(theta)[0]
    if obs.transmissibility is not None:
        table["transmissibility_measured"] = obs.transmissibility
        table["transmissibility_predicted"] = predicted["transmissibility"][0]
    table["fitted"] = obs.fitted
    return table
