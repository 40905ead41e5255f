"""Run a validated spec: cut the grid into tiles, compute them (in processes if asked), assemble.

Tiles are fixed blocks of frequency ratios (all force ratios each), independent of the number of
workers, so the cube is the same whatever `jobs` is.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from typing import Callable

import numpy as np

from friction_sweep import methods

GRID_OUTPUTS = ("transmissibility", "phase", "regime")

#: frequency ratios per tile; fixed so results never depend on how tiles are scheduled
TILE_FREQUENCIES = 32


def tiles(n_frequencies: int, size: int = TILE_FREQUENCIES) -> list[slice]:
    return [slice(i, min(i + size, n_frequencies)) for i in range(0, n_frequencies, size)]


def _compute(args):
    method_name, excitation, r, beta, outputs, effects, settings = args
    return methods.get(method_name).compute_tile(excitation, r, beta, outputs, effects=effects, settings=settings)


def run_grid(method_name: str, excitation: str, frequency_ratio, force_ratio, outputs, *, effects=None,
             settings=None, jobs: int = 1, on_tile: Callable[[int], None] | None = None) -> dict[str, np.ndarray]:
    """Compute every requested variable on the full grid; `on_tile(points)` reports progress."""
    r = np.asarray(frequency_ratio, dtype=float)
    beta = np.asarray(force_ratio, dtype=float)
    parts = tiles(r.size)
    grid_outputs = tuple(o for o in outputs if o in GRID_OUTPUTS)  # time histories are not per grid point
    work = [(method_name, excitation, r[s], beta, grid_outputs, dict(effects or {}), dict(settings or {}))
            for s in parts]
    results: dict[str, np.ndarray] = {}

    def place(s: slice, tile: dict) -> None:
        for name, values in tile.items():
            if name not in results:
                shape = (r.size,) if values.ndim == 1 else (beta.size, r.size)
                results[name] = np.empty(shape, dtype=values.dtype)
            results[name][..., s] = values
        if on_tile is not None:
            on_tile(beta.size * (s.stop - s.start))

    if jobs <= 1 or len(parts) == 1:
        for s, args in zip(parts, work):
            place(s, _compute(args))
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for s, tile in zip(parts, pool.map(_compute, work)):
                place(s, tile)
    return results
