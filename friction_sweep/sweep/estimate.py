"""What a run will cost before it starts: wall time and memory, from a measured cost model.

Per method, the wall time of a tile on one core is modelled as

    tile + sum over its frequency ratios r of [ frequency(r) + (force ratios) * point(r) ]
    point(r) = point * max(1, (knee / r)^slope) * (settings factor)

`frequency(r)` is work done once per r (the theory's continuity limit); `point(r)` grows at low r,
where the motion stops ever more often per period. The constants are upper bounds of measurements
on 2 cores (make bench; README "What a run costs"), so the estimate errs high. `worst` bounds what a
point can cost when it uses its whole budget (max_periods periods), which no typical grid does.
Numba-free: `fsweep validate` prints the estimate without loading any kernel.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from friction_sweep.sweep.layout import TILE_FORCES, TILE_FREQUENCIES

#: a grid is "huge" (run only with --yes) past either: the refusal says how much
HUGE_SECONDS = 1800.0
HUGE_BYTES = 4 * 2**30
#: a run's process before its grid: Python with numba, xarray and h5py loaded (peak RSS of a 1-point run)
BASE_BYTES = 300 * 2**20


@dataclass(frozen=True)
class CostModel:
    """Seconds on one core; see the module docstring. `period`: one forcing period of one point,
    at most, for the worst-case bound; `point_bytes`: memory per grid point while a run holds it."""

    tile: float
    point: float
    knee: float = 0.0
    slope: float = 0.0
    frequency: float = 0.0
    frequency_knee: float = 0.0
    frequency_slope: float = 0.0
    period: float = 0.0
    point_bytes: int = 1000


#: measured on 2 cores (see the module docstring), rounded up
COSTS = {
    "theory": CostModel(tile=2e-3, point=2e-5, frequency=2.5e-3, frequency_knee=0.05, frequency_slope=2.2,
                        point_bytes=600),
    "event": CostModel(tile=3e-3, point=2e-4, knee=0.1, slope=1.5, period=2e-5),
    "auto": CostModel(tile=5e-3, point=2e-4, knee=0.1, slope=1.5, frequency=2.5e-3, frequency_knee=0.05,
                      frequency_slope=2.2, period=2e-5),
    "rk4": CostModel(tile=3e-3, point=2e-3, knee=0.1, slope=1.0, period=3e-5),
    "paper": CostModel(tile=1e-2, point=5.0, knee=0.1, slope=1.0, period=0.05),
}


@dataclass(frozen=True)
class Estimate:
    points: int
    seconds: float  # wall time, typical
    worst: float  # wall time if every point ran its whole budget
    bytes: int
    workers: int

    def describe(self) -> str:
        text = f"about {duration(self.seconds)} with {self.workers} worker(s)"
        if self.worst > 2 * self.seconds:
            text += f" (at most {duration(self.worst)} if every point used its whole budget)"
        return text + f" and {self.bytes / 2**30:.2g} GiB of memory"


def estimate(spec, *, jobs: int, executor: str) -> Estimate:
    """The cost of running `spec` with `jobs` workers on `executor`."""
    model = COSTS[spec.method]
    r, n_beta = spec.frequency_ratio, spec.force_ratio.size
    settings = spec.settings
    factor = _settings_factor(spec.method, settings)
    starts = 2 if _two_starts(spec) else 1
    point = model.point * np.maximum(1.0, (model.knee / r) ** model.slope) * factor * starts
    frequency = model.frequency * np.maximum(1.0, (model.frequency_knee / r) ** model.frequency_slope) \
        if model.frequency else np.zeros_like(r)
    sweep = spec.sweep is not None
    n_tiles = -(-n_beta // TILE_FORCES) if sweep else -(-r.size // TILE_FREQUENCIES)
    serial = float(n_tiles * model.tile + frequency.sum() * (n_tiles if sweep else 1) + n_beta * point.sum())
    worst_point = _worst_point(spec.method, model, settings) * starts
    worst = serial + r.size * n_beta * max(0.0, worst_point - float(point.max()))
    workers = _workers(executor, jobs, n_tiles)
    points = r.size * n_beta
    history = 0
    if spec.time_history is not None:
        history = len(spec.time_history.points) * spec.time_history.samples_per_period * 8 * 4
        serial += len(spec.time_history.points) * float(point.max()) * 4
    return Estimate(points=points, seconds=serial / workers, worst=worst / workers,
                    bytes=BASE_BYTES + points * model.point_bytes * starts + history, workers=workers)


def _two_starts(spec) -> bool:
    effects = spec.scene.effects.declared()
    return (effects.get("static_friction_ratio", 1.0) > 1.0 and spec.sweep is None
            and spec.settings.get("starts", 2) == 2 and spec.method in ("event", "rk4"))


def _settings_factor(method: str, settings: dict) -> float:
    """How the knobs that set the work per point scale the typical cost."""
    if method == "rk4":
        return settings.get("steps_per_period", 256) / 256
    if method == "paper":
        return settings.get("periods", 200) / 200 * max(1.0, settings.get("samples_per_period", 64) / 256)
    return 1.0


def _worst_point(method: str, model: CostModel, settings: dict) -> float:
    """A point that marches its whole budget: max_periods periods (paper: its periods)."""
    if method == "theory":
        return 0.0
    if method == "paper":
        return model.period * settings.get("periods", 200)
    periods = settings.get("max_periods", 2000)
    per_period = model.period * (_settings_factor(method, settings) if method == "rk4" else 1.0)
    return periods * per_period


def _workers(executor: str, jobs: int, n_tiles: int) -> int:
    """Workers that can run at once: one for serial; never more than tiles, nor (locally) cores."""
    if executor == "serial" or jobs <= 1:
        return 1
    if executor == "dask":  # a remote cluster's size is unknown here: -j is the user's word for it
        return max(1, min(jobs, n_tiles))
    return max(1, min(jobs, n_tiles, os.cpu_count() or 1))


def duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s" if seconds >= 1 else f"{seconds:.1g} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 172800:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"
