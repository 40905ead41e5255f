"""What a run will cost before it starts: wall time and memory, from a measured cost model.

Seconds on one core, summed over the run's tiles (fixed blocks of frequency ratios, batch.layout):

    every method    0.3 ms x max(1, 0.07/r) per frequency ratio (the theory's continuity limit S(r),
                    which the simulations write beside their results)
    theory, auto    per tile: 0.6 ms + 6e-11 n^3 (Gauss-Legendre nodes, n = 40 + pi (1 + r_min)/r_min);
                    per point: 2 us + 0.03 us n, and for joined 1 us per peak sample
                    (64 + 16 (1 + r)/r of them)
    event, auto     per point: base/force 8 us x max(1, (0.66/r)^1.5), joined 6 us x max(1, (0.035/r)^0.6);
                    x3 with static above kinetic friction and two starts (three solves)
    rk4             per point: 1.2 us x steps_per_period
    paper           per point: 5.7 us per right-hand side, up to max_evaluations, + 0.2 us a sample

Measured on 2 cores, each column's mean over 151 force ratios (the event rows again after issue 16's
shooting, which made them 10-30x cheaper), and checked on the paper plane (74,896 points, serial).
Single points vary more than column means (at r < 0.1 a small force ratio can cost 3-5x its
column's mean), so a grid of only such points can take longer than `seconds`. `worst` bounds a grid
whose every point runs into its budget: work_budget events at 0.3 us, or max_periods periods at
21 us + 13 ns x max_orbit_period, whichever comes first.
Numba-free: `fsweep validate` prints the estimate without loading any kernel.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from friction_sweep.batch.layout import layout
from friction_sweep.catalogue import METHODS, effect_value

#: a grid is "huge" (run only with --yes) past either: the refusal says how much
HUGE_SECONDS = 1800.0
HUGE_BYTES = 4 * 2**30
#: a run's process before its grid: Python with numba, xarray and h5py loaded (peak RSS of a 1-point run)
BASE_BYTES = 300 * 2**20
#: memory per grid point while a run holds its outputs and the cube's serialised copy
POINT_BYTES = 1000
#: loading the compiled kernels from numba's cache, once per run (the simulation methods; make bench:
#: numba's first call of any cached kernel alone costs ~0.4 s)
KERNEL_LOAD_SECONDS = 0.4


def _frequency_seconds(r: np.ndarray) -> np.ndarray:
    return 3e-4 * np.maximum(1.0, 0.07 / r)


def _theory_seconds(r: np.ndarray, n_beta: int, joined: bool) -> float:
    n = 40 + math.ceil((1.0 + r.min()) * math.pi / r.min())
    per_point = 2e-6 + 3e-8 * n + (1e-6 * (64 + 16 * (1.0 + r) / r) if joined else 0.0)
    return 6e-4 + 6e-11 * n**3 + float(np.sum(np.broadcast_to(per_point, r.shape))) * n_beta


def _event_point_seconds(r: np.ndarray, joined: bool) -> np.ndarray:
    if joined:
        return 6e-6 * np.maximum(1.0, (0.035 / r) ** 0.6)
    return 8e-6 * np.maximum(1.0, (0.66 / r) ** 1.5)


def _tile_seconds(method: str, r: np.ndarray, n_beta: int, joined: bool, solves: int, knobs: dict) -> float:
    """Typical seconds for one tile of frequency ratios `r` by all `n_beta` force ratios."""
    seconds = float(_frequency_seconds(r).sum())
    if method in ("theory", "auto"):
        seconds += _theory_seconds(r, n_beta, joined)
    if method in ("event", "auto"):
        seconds += float(_event_point_seconds(r, joined).sum()) * n_beta * solves
    if method == "rk4":
        seconds += 1.2e-6 * knobs["steps_per_period"] * r.size * n_beta * solves
    if method == "paper":  # a smooth point; stick-slip runs into max_evaluations (`worst`)
        seconds += (5.7e-6 * 2e4 + 0.2e-6 * knobs["periods"] * knobs["samples_per_period"]) * r.size * n_beta
    return seconds


def _worst_point_seconds(method: str, knobs: dict, solves: int) -> float:
    """A point that runs into its budget."""
    if method == "theory":
        return 0.0
    if method == "paper":
        return 5.7e-6 * knobs["max_evaluations"] + 0.2e-6 * knobs["periods"] * knobs["samples_per_period"]
    per_period = 21e-6 + 13e-9 * knobs["max_orbit_period"]
    if method == "rk4":
        per_period += 1.2e-6 * knobs["steps_per_period"]
    return solves * min(0.3e-6 * knobs["work_budget"], knobs["max_periods"] * per_period)


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


def estimate(spec, settings: dict | None = None, *, jobs: int, executor: str) -> Estimate:
    """The cost of running `spec` with `jobs` workers on `executor`, with the run's `settings` (those
    `accuracy:` chose included; default: the spec's)."""
    r, n_beta = spec.frequency_ratio, spec.force_count
    knobs = {**METHODS[spec.method].defaults, **(spec.settings if settings is None else settings)}
    joined = spec.scene.excitation == "joined"
    solves = 3 if _two_starts(spec, knobs) else 1
    sweep = spec.sweep.direction if spec.sweep is not None else None
    parts = layout(r.size, n_beta, sweep)
    if sweep:  # tiles of force ratios, each over every frequency ratio
        serial = sum(_tile_seconds(spec.method, r, p.stop - p.start, joined, solves, knobs) for p in parts)
    else:
        serial = sum(_tile_seconds(spec.method, r[p], n_beta, joined, solves, knobs) for p in parts)
    if spec.method != "theory":
        serial += KERNEL_LOAD_SECONDS
    points = r.size * n_beta
    history = 0
    if spec.time_history is not None:
        n = len(spec.time_history.points)
        history = n * spec.time_history.samples_per_period * 8 * 8  # eight float64 variables
        serial += n * _worst_point_seconds(spec.method, knobs, solves)
    worst = serial + points * _worst_point_seconds(spec.method, knobs, solves)
    workers = _workers(executor, jobs, len(parts))
    return Estimate(points=points, seconds=serial / workers, worst=worst / workers,
                    bytes=BASE_BYTES + points * POINT_BYTES * solves + history, workers=workers)


def _two_starts(spec, knobs: dict) -> bool:
    """Whether each point is solved from a moving start too (methods.event.two_starts)."""
    return (effect_value(spec.scene.effects, "static_friction_ratio") > 1.0 and spec.sweep is None
            and knobs.get("starts", 1) == 2)


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
