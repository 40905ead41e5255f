"""Prior distributions of the calibrated parameters, as a spec writes them and as the sampler uses them.

A spec gives a prior as a one-key mapping, its values in the parameter's unit (spec.quantities):

    {normal: [mu, sigma]}          Gaussian
    {uniform: [low, high]}         flat on [low, high]
    {log_normal: [median, s]}      log(theta) ~ N(log median, s): a positive scale known to a factor e^s
    {half_normal: scale}           |N(0, scale)|: a noise level or a discrepancy's size, most likely small

Each is scipy.stats' distribution of that name, frozen; `support` bounds the least-squares search and
`residual` is the prior's term in it (sum of squares = -2 log prior + const inside the support).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy import stats

KINDS = ("normal", "uniform", "log_normal", "half_normal")
#: how many numbers each kind takes
ARITY = {"normal": 2, "uniform": 2, "log_normal": 2, "half_normal": 1}


@dataclass(frozen=True)
class Prior:
    """One parameter's prior: its kind and its numbers, in the parameter's SI (or dimensionless) unit."""

    kind: str
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        reason = self.problem()
        if reason:
            raise ValueError(reason)

    def problem(self) -> str | None:
        """Why these numbers make no distribution, or None."""
        if self.kind not in KINDS:
            return f"unknown prior {self.kind!r} (known: {', '.join(KINDS)})"
        if len(self.values) != ARITY[self.kind]:
            return f"{self.kind} takes {ARITY[self.kind]} number(s) (got {len(self.values)})"
        if not all(math.isfinite(v) for v in self.values):
            return f"{self.kind}: its numbers must be finite"
        if self.kind == "uniform" and not self.values[0] < self.values[1]:
            return f"uniform: needs low < high (got {self.values[0]:g}, {self.values[1]:g})"
        if self.kind in ("normal", "log_normal") and self.values[1] <= 0:
            return f"{self.kind}: its spread must be positive (got {self.values[1]:g})"
        if self.kind == "log_normal" and self.values[0] <= 0:
            return f"log_normal: its median must be positive (got {self.values[0]:g})"
        if self.kind == "half_normal" and self.values[0] <= 0:
            return f"half_normal: its scale must be positive (got {self.values[0]:g})"
        return None

    @cached_property
    def dist(self):
        """The frozen scipy.stats distribution (sampling, quantiles, sd)."""
        a, *rest = self.values
        if self.kind == "normal":
            return stats.norm(a, rest[0])
        if self.kind == "uniform":
            return stats.uniform(a, rest[0] - a)
        if self.kind == "log_normal":
            return stats.lognorm(rest[0], scale=a)
        return stats.halfnorm(scale=a)

    @property
    def support(self) -> tuple[float, float]:
        if self.kind == "uniform":
            return self.values[0], self.values[1]
        if self.kind == "normal":
            return -math.inf, math.inf
        return 0.0, math.inf

    def logpdf(self, x: np.ndarray) -> np.ndarray:
        """log density, written out (the sampler asks for it every step; scipy.stats' generic checks cost
        more than the model's points): the same as self.dist.logpdf (tests/test_calibration.py)."""
        x = np.asarray(x, dtype=float)
        a, *rest = self.values
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.kind == "normal":
                return -0.5 * ((x - a) / rest[0]) ** 2 - math.log(rest[0] * math.sqrt(2.0 * math.pi))
            if self.kind == "uniform":
                inside = (x >= a) & (x <= rest[0])
                return np.where(inside, -math.log(rest[0] - a), -np.inf)
            if self.kind == "log_normal":
                z = (np.log(np.where(x > 0, x, np.nan)) - math.log(a)) / rest[0]
                out = -0.5 * z**2 - np.log(x * rest[0] * math.sqrt(2.0 * math.pi))
                return np.where(x > 0, out, -np.inf)
            out = -0.5 * (x / a) ** 2 + math.log(math.sqrt(2.0 / math.pi) / a)
            return np.where(x >= 0, out, -np.inf)

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return self.dist.rvs(size=n, random_state=rng)

    def quantile(self, p):
        return self.dist.ppf(p)

    def std(self) -> float:
        return float(self.dist.std())

    def residual(self, x: float) -> float:
        """The prior's least-squares residual: its square is -2 log prior up to a constant (0 for the
        flat prior, whose support bounds the search instead; the half normal's mode sits on its bound).
        log_normal: -2 log p = z^2 + 2 log x + const with z = log(x/a)/s, and since log(x/a) = s z that
        is (z + s)^2 + const: the residual z + s, whose zero is the density's mode a e^(-s^2)."""
        a, *rest = self.values
        if self.kind == "normal":
            return (x - a) / rest[0]
        if self.kind == "log_normal":
            return math.log(max(x, 1e-300) / a) / rest[0] + rest[0]
        if self.kind == "half_normal":
            return x / a
        return 0.0

    def describe(self, unit: str = "") -> str:
        shown = ", ".join(f"{v:.6g}" for v in self.values)
        return f"{self.kind}({shown}){' ' + unit if unit else ''}"
