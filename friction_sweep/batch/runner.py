"""Run a validated spec: cut the grid into tiles, compute them where asked, assemble.

Tiles are fixed blocks of frequency ratios (all force ratios each), independent of the number of
workers and of the executor, so the cube is the same bit for bit however it was scheduled. A swept run
(`sweep:` in the spec) is sequential along the frequency ratio, so its tiles are fixed blocks of force
ratios instead (all frequency ratios each, in sweep order).
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from friction_sweep import methods
from friction_sweep.batch.executors import DEFAULT_EXECUTOR, execute
from friction_sweep.batch.layout import TILE_FORCES, TILE_FREQUENCIES, layout, tiles
from friction_sweep.catalogue import GRID_OUTPUTS
from friction_sweep.storage.schema import VARIABLES

log = logging.getLogger("friction_sweep")

__all__ = ["TILE_FORCES", "TILE_FREQUENCIES", "compute_tile", "layout", "run_grid", "run_tiles", "tiles", "warm_up"]


def compute_tile(args):
    """One tile: a pure function of its arguments (picklable for processes and Dask). `beta` is one force
    ratio per force-axis value, or (constant base acceleration) a column of them per frequency ratio."""
    method_name, excitation, r, beta, outputs, effects, settings, sweep = args
    method = methods.get(method_name)
    if sweep:
        return method.compute_sweep_tile(excitation, r, beta, outputs, effects=effects, settings=settings,
                                         direction=sweep)
    if np.ndim(beta) == 1:
        return method.compute_tile(excitation, r, beta, outputs, effects=effects, settings=settings)
    # each point is computed alone, so a column of its own force ratios gives what a plane would
    columns = [method.compute_tile(excitation, r[i:i + 1], beta[:, i], outputs, effects=effects, settings=settings)
               for i in range(r.size)]
    return {name: np.concatenate([c[name] for c in columns], axis=-1) for name in columns[0]}


def warm_up(method_name: str, excitation: str, frequency_ratio, force_ratio, outputs, *, effects=None,
            settings=None, sweep: str | None = None) -> None:
    """Compute the grid's first point as run_grid would compute its tiles: numba compiles every kernel the
    run calls (or loads it from its cache) and caches it for the run's workers on this machine."""
    r = np.asarray(frequency_ratio, dtype=float)
    beta = np.asarray(force_ratio, dtype=float)
    grid_outputs = tuple(o for o in outputs if o in GRID_OUTPUTS)
    compute_tile((method_name, excitation, r[:1], beta[:1] if beta.ndim == 1 else beta[:1, :1], grid_outputs,
                  dict(effects or {}), dict(settings or {}), sweep))


def run_grid(method_name: str, excitation: str, frequency_ratio, force_ratio, outputs, *, effects=None,
             settings=None, sweep: str | None = None, jobs: int = 1, executor: str = DEFAULT_EXECUTOR,
             scheduler: str | None = None,
             done: dict | None = None, on_done: Callable[[int, dict], None] | None = None,
             on_tile: Callable[[int], None] | None = None) -> dict[str, np.ndarray]:
    """Compute every requested variable on the full grid.

    done: tiles already computed (index -> arrays, from a checkpoint); on_done(index, arrays) is
    called for each newly computed tile (to checkpoint it); on_tile(points) reports progress.
    sweep: "up" or "down" for a stepped-sine sweep along the frequency ratio (tiles of force ratios).
    """
    r = np.asarray(frequency_ratio, dtype=float)
    beta = np.asarray(force_ratio, dtype=float)  # (n_beta,), or (n_beta, n_r) at constant acceleration
    n_beta = beta.shape[0]
    parts = layout(r.size, n_beta, sweep)
    grid_outputs = tuple(o for o in outputs if o in GRID_OUTPUTS)  # time histories are not per grid point
    common = (grid_outputs, dict(effects or {}), dict(settings or {}), sweep)
    if sweep:
        work = [(method_name, excitation, r, beta[s], *common) for s in parts]
    else:
        work = [(method_name, excitation, r[s], beta if beta.ndim == 1 else beta[:, s], *common) for s in parts]
    results: dict[str, np.ndarray] = {}

    def place(s: slice, tile: dict) -> None:
        for name, values in tile.items():
            values = np.asarray(values)
            if name not in results:
                # a plane, or planes along a leading dim of their own (the harmonics)
                shape = (r.size,) if values.ndim == 1 else (*values.shape[:-2], n_beta, r.size)
                results[name] = np.empty(shape, dtype=values.dtype)
            if sweep and values.ndim == 1:
                results[name][:] = values  # along frequency_ratio: every tile has all of it
            elif sweep:
                results[name][s, :] = values
            else:
                results[name][..., s] = values
        if on_tile is not None:
            on_tile((s.stop - s.start) * (r.size if sweep else n_beta))

    done = {i: tile for i, tile in (done or {}).items() if _fits(tile, parts[i], r.size, n_beta, sweep)}
    todo = [i for i in range(len(parts)) if i not in done]
    if todo and executor in ("processes", "threads") and jobs > 1:
        # compile (or load from the cache) once here, before workers start: no compile storm
        warm_up(method_name, excitation, r, beta, outputs, effects=effects, settings=settings, sweep=sweep)
    log.info("computing %d tiles (%d points) with %s, %d worker(s)", len(todo),
             sum((r.size if sweep else n_beta) * (parts[i].stop - parts[i].start) for i in todo), executor, jobs)
    run_tiles(compute_tile, work, lambda i, tile: place(parts[i], tile), done=done, executor=executor, jobs=jobs,
              scheduler=scheduler, on_done=on_done)
    return results


def run_tiles(fn: Callable, work: list, place: Callable[[int, dict], None], *, done: dict[int, dict],
              executor: str, jobs: int, scheduler: str | None, on_done: Callable[[int, dict], None] | None) -> None:
    """Place every tile: those `done` (read back from a checkpoint, already judged to fit), then each of the
    others as `fn(work[i])` finishes on `executor` (handed to on_done first, to checkpoint it). Stopped
    (Ctrl-C, SIGTERM, a lost cluster), every finished tile is still handed to on_done before the error goes
    on. ValueError where the tiles hold different variables (a checkpoint of another run's outputs)."""
    for i, tile in done.items():
        place(i, tile)
    todo = [i for i in range(len(work)) if i not in done]
    if done:
        log.info("resuming: %d of %d tiles already done", len(done), len(work))
    with execute(fn, [work[i] for i in todo], executor, jobs, scheduler) as running:
        saving = None
        try:
            for k, tile in running:
                saving = (k, tile)
                if on_done is not None:
                    on_done(todo[k], tile)
                saving = None
                place(todo[k], tile)
        except BaseException as err:
            # stopped (Ctrl-C, SIGTERM, a lost cluster): keep every tile that was finished, the one
            # being saved when a signal came too; not where the save itself failed (it would again).
            # A second signal, or a save that fails, ends this at once
            if on_done is not None and (saving is None or isinstance(err, KeyboardInterrupt)):
                for k, tile in ([saving] if saving else []) + running.finished():
                    try:
                        on_done(todo[k], tile)
                    except Exception:
                        break
            raise
    if len({frozenset(t) for t in done.values()} | ({frozenset(tile)} if todo else set())) > 1:
        raise ValueError("the checkpoint's tiles hold other variables than this run computes: clear the "
                         "checkpoint folder and run again")


def _fits(tile: dict, part: slice, n_r: int, n_beta: int, sweep: str | None) -> bool:
    """Whether a tile read back from a checkpoint has, for every variable, the shape of its place in the
    grid (a plane, or a line along the frequency ratio for a variable of that dim alone, as the schema
    says) and the schema's exact dtype (a damaged, cast or foreign one is computed again)."""
    n = part.stop - part.start
    grid = (n, n_r) if sweep else (n_beta, n)
    line = (n_r,) if sweep else (n,)
    return all(_kind_fits(k, v) and np.shape(v)[-len(grid):] == (line if VARIABLES[k].dims == ("frequency_ratio",)
                                                                  else grid)
               and np.ndim(v) == len(VARIABLES[k].dims) for k, v in tile.items())


def _kind_fits(name: str, values) -> bool:
    """A schema variable stored with exactly the schema's dtype: a tile cast to float16 (or int64 codes)
    would give the whole cube its precision, since tiles are placed into one array."""
    var = VARIABLES.get(name)
    return var is not None and np.asarray(values).dtype == np.dtype(var.dtype)
