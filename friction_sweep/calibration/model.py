"""The forward model of a calibration: a parameter vector -> the scene's phase and transmissibility at every
measured row, computed by the spec's method (theory or event) as `fsweep run` computes a cube's (event: the
state reached from rest, `settings: {starts: 1}`).

Parameters act on the rows as follows (docs/equations.md §1: everything depends on (r, beta) and the
effects):

    r_i    = r_data,i * f_ref / f_n                 natural_frequency f_n shifts every frequency ratio
    beta_i = beta_s(i)                              friction_ratio per series s, or friction_force_s / F_k
           = c * beta_data,i                        friction_scale c, one factor on the data's ratios
    effects: viscous_damping, static_friction_ratio (event only; the state reached from rest); a damping
           ratio drawn between 0 and catalogue.VISCOUS_DAMPING_FLOOR, below what the numerics resolve, is 0:
           no dashpot (its effect, ~14 zeta of the response, is below the rounding it would bring), so a prior
           reaching down to 0 keeps its mass there instead of losing it to points refused as unbalanced

Many parameter vectors are evaluated at once (the sampler's walkers): the points of all of them go to one
kernel call where the effects are shared, else one call per vector; `jobs` threads share the points
(the kernels release the GIL).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from friction_sweep.catalogue import VISCOUS_DAMPING_FLOOR
from friction_sweep.spec import grid
from friction_sweep.theory import den_hartog as dh

from .data import Observations
from .priors import Prior
from .spec import FRICTION_PARAMETERS, CalibrationSpec

#: the kernel outputs a calibration reads
OUTPUTS = ("transmissibility", "phase")
#: beta*(r) values kept at most (memory bound where the natural frequency moves every r)
MEMO_SIZE = 100_000
#: parameters that are effects of the scene (scene.effects of a sweep spec)
EFFECT_PARAMETERS = ("viscous_damping", "static_friction_ratio")


@dataclass(frozen=True)
class Parameter:
    """One entry of the parameter vector: its name (with the series for per-series ones), the spec's
    parameter it belongs to, its prior, and its series index (-1: not per series)."""

    name: str
    kind: str
    prior: Prior
    series: int = -1


class ForwardModel:
    """Predictions of the measured quantities for parameter vectors (rows of a 2-D array)."""

    def __init__(self, spec: CalibrationSpec, obs: Observations, jobs: int = 1):
        self.spec = spec
        self.obs = obs
        self.jobs = jobs
        self.excitation = spec.excitation
        self.method = spec.method
        self.settings = dict(spec.settings)  # without `starts` (the spec refuses it): from rest
        params: list[Parameter] = []
        for name, prior in spec.priors.items():
            if name in ("friction_ratio", "friction_force"):
                params += [Parameter(f"{name}[{label}]", name, prior, s) for s, label in enumerate(obs.series_labels)]
            else:
                params.append(Parameter(name, name, prior))
        self.parameters = tuple(params)
        self.names = tuple(p.name for p in params)
        self._index = {p.name: i for i, p in enumerate(params)}
        self._friction = next((k for k in FRICTION_PARAMETERS if k in spec.priors), None)
        self.evaluations = 0  # points computed (for the report's rate)
        self._bstar: dict[float, float] = {}  # theory: beta*(r) by r, reused while r stays (no natural_frequency)

    @property
    def ndim(self) -> int:
        return len(self.parameters)

    def too_few_rows(self) -> str | None:
        """Why the fitted rows cannot calibrate the parameters, or None. A calibration needs more measured
        values than parameters: with as many or fewer, some parameter vector passes through every value
        exactly, the residuals vanish and the noise level's estimate goes to zero (one row gave a MAP noise
        of 4e-153 degrees), the posterior then decided by the priors alone."""
        per_row = len(self.obs.measured)
        values = int(self.obs.fitted.sum()) * per_row
        if values > self.ndim:
            return None
        need = self.ndim // per_row + 1
        return (f"{self.obs.path}: {values} measured values to fit (fitted rows x quantities) for {self.ndim} "
                f"parameters ({', '.join(self.names)}): a calibration needs more values than parameters, here at "
                f"least {need} fitted rows; with fewer the fit passes through every value and the noise goes to zero")

    def column(self, theta: np.ndarray, name: str) -> np.ndarray | None:
        i = self._index.get(name)
        return None if i is None else theta[:, i]

    def points(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(r, beta) of every row for every parameter vector: arrays (n_vectors, n_rows)."""
        theta = np.atleast_2d(theta)
        n = theta.shape[0]
        r = np.broadcast_to(self.obs.frequency_ratio, (n, self.obs.size)).copy()
        f_n = self.column(theta, "natural_frequency")
        if f_n is not None:
            reference = self.spec.reference_frequency or 1.0
            r = r * (reference / f_n[:, None])
        beta = np.broadcast_to(self.obs.force_ratio, (n, self.obs.size)).copy()
        if self._friction == "friction_scale":
            beta = beta * theta[:, self._index["friction_scale"]][:, None]
        elif self._friction is not None:
            per_series = np.stack([theta[:, self._index[f"{self._friction}[{label}]"]]
                                   for label in self.obs.series_labels], axis=1)
            beta = per_series[:, self.obs.series]
            if self._friction == "friction_force":
                beta = beta / self.spec.reference_force
        return r, beta

    def effects(self, theta: np.ndarray) -> list[dict[str, float]]:
        """The scene effects of each parameter vector."""
        theta = np.atleast_2d(theta)
        cols = {name: self.column(theta, name) for name in EFFECT_PARAMETERS}
        zeta = cols["viscous_damping"]
        if zeta is not None:  # below the floor: no dashpot (the module's docstring says why)
            cols["viscous_damping"] = np.where((zeta > 0) & (zeta < VISCOUS_DAMPING_FLOOR), 0.0, zeta)
        return [{name: float(col[i]) for name, col in cols.items() if col is not None} for i in range(theta.shape[0])]

    def predict(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """{'phase': degrees, 'transmissibility'}: arrays (n_vectors, n_rows); NaN where the method gives
        none (theory off continuous motion; unbounded or unsettled points; a mass that never moves)."""
        theta = np.atleast_2d(theta)
        r, beta = self.points(theta)
        # the ranges a sweep spec accepts (spec.grid); NaN fails both comparisons
        low, high = grid.FREQUENCY_RATIO_RANGE
        ok = (r >= low) & (r <= high) & (beta >= 0.0) & (beta <= grid.FORCE_RATIO_MAX)
        out = {name: np.full(r.shape, np.nan) for name in OUTPUTS}
        if any(name in self._index for name in EFFECT_PARAMETERS):
            groups = [(effects, np.array([i])) for i, effects in enumerate(self.effects(theta))]
        else:
            groups = [({}, np.arange(theta.shape[0]))]
        tasks = []
        for effects, rows in groups:
            sel = ok[rows]
            if sel.any():
                tasks.append((effects, rows, sel, r[rows][sel], beta[rows][sel]))
        for (_, rows, sel, *_), result in zip(tasks, self._run(tasks), strict=True):
            for name in OUTPUTS:
                block = out[name][rows]
                block[sel] = result[name]
                out[name][rows] = block
        self.evaluations += int(ok.sum())
        return out

    def _run(self, tasks) -> list[dict[str, np.ndarray]]:
        """Compute each task's flat points; chunks of points go to `jobs` threads."""
        chunks = []  # (task index, slice of its points)
        for t, (*_, rr, _bb) in enumerate(tasks):
            parts = max(1, min(self.jobs, rr.size // 16)) if len(tasks) == 1 else 1
            for piece in np.array_split(np.arange(rr.size), parts):
                chunks.append((t, piece))

        def work(chunk):
            t, piece = chunk
            effects, _, _, rr, bb = tasks[t]
            return self._compute(rr[piece], bb[piece], effects)

        if self.jobs > 1 and len(chunks) > 1:
            with ThreadPoolExecutor(self.jobs) as pool:
                pieces = list(pool.map(work, chunks))
        else:
            pieces = [work(c) for c in chunks]
        results = [{name: np.empty(task[3].size) for name in OUTPUTS} for task in tasks]
        for (t, piece), values in zip(chunks, pieces, strict=True):
            for name in OUTPUTS:
                results[t][name][piece] = values[name]
        return results

    def _compute(self, r: np.ndarray, beta: np.ndarray, effects: dict[str, float]) -> dict[str, np.ndarray]:
        if self.method == "theory":
            from friction_sweep.methods import theory

            values = theory.compute_points(self.excitation, r, beta, OUTPUTS, self._continuous_limit(r))
            return {name: values[name] for name in OUTPUTS}
        from friction_sweep.kernels import steady
        from friction_sweep.methods import event

        raw = event.solve_flat(self.excitation, r, beta, effects, **self.settings)
        return {"phase": raw[:, steady.OUT_PHASE], "transmissibility": raw[:, steady.OUT_TRANSMISSIBILITY]}

    def _continuous_limit(self, r: np.ndarray) -> np.ndarray:
        """Den Hartog's beta*(r) (theory.den_hartog.continuous_limit), computed once per distinct r: the
        theory's cost (a search for the sup S(r), 0.15 ms an r) where the rows' r do not move."""
        known = {x: self._bstar.get(x) for x in np.unique(r).tolist()}  # a local view: threads share the memo
        new = [x for x, value in known.items() if value is None]
        if new:
            found = dict(zip(new, dh.continuous_limit(np.array(new)).tolist(), strict=True))
            known.update(found)
            if len(self._bstar) > MEMO_SIZE:
                self._bstar.clear()
            self._bstar.update(found)
        return np.array([known[x] for x in r.tolist()])
