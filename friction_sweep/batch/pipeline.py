"""From a validated spec to a labelled xarray Dataset: the run's settings (what `accuracy:` chooses),
the grid's tiles, the time histories, and the provenance that a cube records.

`fsweep run` calls these pieces around its checkpoint and lock; the Python API (friction_sweep.api) calls
them in a row.
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

import friction_sweep
from friction_sweep import catalogue
from friction_sweep.batch.executors import DEFAULT_EXECUTOR
from friction_sweep.spec import Spec
from friction_sweep.storage.schema import HARMONIC_DIM


def run_settings(spec: Spec, table: dict | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """The run's settings (the spec's, with the knobs `accuracy:` chooses from the benchmark's
    calibration) and the cube attributes that record that choice. LookupError where the calibration
    has no setting that meets the accuracy asked for."""
    settings = dict(spec.settings)
    if spec.accuracy is None:
        return settings, {}
    from friction_sweep.bench.workprecision import choose  # reads the calibration file

    record = catalogue.method(spec.method)
    chosen, row = choose(record.calibrated_as or record.name, spec.accuracy, table, spec.scene.effects)
    settings.update(chosen)
    return settings, {"accuracy_requested": spec.accuracy, "accuracy_choice": json.dumps(row, sort_keys=True)}


def checkpoint_key(spec: Spec, settings: dict[str, Any], extra_attrs: dict[str, Any]) -> str:
    """The fingerprint of every input that changes a number of the run, for its checkpoint: tiles of a
    run whose key differs are never joined with this one's. The spec as parsed (scene, effects, system,
    grid, method, settings, accuracy, sweep, outputs, time histories; not where the cube goes), the grid's
    values and tiles, the settings the run resolved (what `accuracy:` chose from which calibration, and
    the calibration file itself), what the cube records as method_settings, the package's version and
    the hash of its code."""
    from friction_sweep.batch import checkpoint
    from friction_sweep.batch.layout import TILE_FORCES, TILE_FREQUENCIES

    sweep = spec.sweep.direction if spec.sweep is not None else None
    calibration = b""
    if spec.accuracy is not None:
        from friction_sweep.bench.workprecision import calibration_path

        try:
            calibration = calibration_path().read_bytes()
        except OSError:
            calibration = b"unreadable"
    return checkpoint.fingerprint(
        spec=spec.model_dump(mode="json", exclude={"output"}), r=np.asarray(spec.frequency_ratio, dtype=float),
        beta=np.asarray(spec.force_ratio, dtype=float), tile=TILE_FORCES if sweep else TILE_FREQUENCIES,
        sweep=sweep, settings=settings, recorded=recorded_settings(spec, settings), accuracy=extra_attrs,
        calibration=calibration, version=friction_sweep.__version__, code=code_version())


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """A hash of the package's Python sources: a checkpoint of other code (kernels changed in a
    checkout without a new version number) is not resumed. Reading them takes milliseconds."""
    root = Path(friction_sweep.__file__).parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def tile_grids(spec: Spec) -> list[dict[str, np.ndarray]]:
    """Each tile's grid values (batch.layout, as batch.runner cuts the grid), which a checkpoint tile
    must carry to be used again."""
    from friction_sweep.batch.layout import layout

    r = np.asarray(spec.frequency_ratio, dtype=float)
    beta = np.asarray(spec.force_ratio, dtype=float)
    sweep = spec.sweep.direction if spec.sweep is not None else None
    grids = []
    for s in layout(r.size, spec.force_count, sweep):
        if sweep:
            part = {"frequency_ratio": r, "force_ratio": beta[s]}
        else:
            part = {"frequency_ratio": r[s], "force_ratio": beta if beta.ndim == 1 else beta[:, s]}
        grids.append({k: np.ascontiguousarray(v) for k, v in part.items()})
    return grids


def compute(spec: Spec, settings: dict[str, Any], *, jobs: int = 1, executor: str = DEFAULT_EXECUTOR,
            scheduler: str | None = None, done: dict | None = None,
            on_done: Callable[[int, dict], None] | None = None,
            on_tile: Callable[[int], None] | None = None) -> dict[str, np.ndarray]:
    """Every variable the spec asks for: the grid's (batch.runner.run_grid, whose done/on_done/on_tile
    serve a checkpoint and a progress bar) and the time histories of its chosen points."""
    from friction_sweep import methods
    from friction_sweep.batch.runner import run_grid

    arrays = run_grid(spec.method, spec.scene.excitation, spec.frequency_ratio, spec.force_ratio, spec.outputs,
                      effects=spec.scene.effects, settings=settings,
                      sweep=spec.sweep.direction if spec.sweep is not None else None,
                      jobs=jobs, executor=executor, scheduler=scheduler, done=done, on_done=on_done, on_tile=on_tile)
    if "harmonics" in spec.outputs:
        highest = settings.get("harmonics", catalogue.method(spec.method).defaults["harmonics"])
        arrays[HARMONIC_DIM] = np.arange(int(highest) + 1)
    if spec.time_history is not None:
        points = np.asarray(spec.time_history.points, dtype=float)
        method: Any = methods.get(spec.method)  # the catalogue vouches that it writes time histories
        arrays.update(method.time_histories(spec.scene.excitation, points, spec.time_history.samples_per_period,
                                            spec.scene.effects, settings),
                      history_frequency_ratio=points[:, 0], history_force_ratio=points[:, 1])
    return arrays


def compile_kernels(spec: Spec, settings: dict[str, Any]) -> None:
    """Have numba compile (or load from its cache) every kernel a run of `spec` calls, by computing its first
    point (and first time history) in this process: a run whose kernels are not cached says so while this
    runs, before its sweep (fsweep run), and its local workers then load them from the cache."""
    from friction_sweep import methods
    from friction_sweep.batch.runner import warm_up

    warm_up(spec.method, spec.scene.excitation, spec.frequency_ratio, spec.force_ratio, spec.outputs,
            effects=spec.scene.effects, settings=settings,
            sweep=spec.sweep.direction if spec.sweep is not None else None)
    if spec.time_history is not None:
        method: Any = methods.get(spec.method)
        method.time_histories(spec.scene.excitation, np.asarray(spec.time_history.points, dtype=float)[:1],
                              spec.time_history.samples_per_period, spec.scene.effects, settings)


def recorded_settings(spec: Spec, settings: dict[str, Any]) -> dict[str, Any]:
    """The settings the numbers came from, for the cube's method_settings attribute: the method's
    algorithm and defaults, the run's settings over them, and the effects."""
    record = catalogue.method(spec.method)
    recorded = {**record.algorithm, **record.defaults, **settings,
                "effects": catalogue.resolved_effects(spec.scene.excitation, spec.scene.effects)}
    if spec.sweep is not None:  # the sweep is the start: no second one
        recorded.pop("starts", None)
        recorded["sweep"] = spec.sweep.direction
    if "harmonics" not in spec.outputs:  # the output's size: no knob of a run without it
        recorded.pop("harmonics", None)
    return recorded


def cube(spec: Spec, arrays: dict[str, np.ndarray], settings: dict[str, Any], command: str,
         extra_attrs: dict[str, Any] | None = None):
    """The parts of the labelled cube of a run's arrays (storage.cube.CubeParts), with its provenance
    (`command` opens its history)."""
    from friction_sweep.storage import cube as cubes
    from friction_sweep.storage import physical, provenance

    coords, attrs = None, dict(extra_attrs or {})
    # the declared effects and the system's constants as scalar coordinates: a family of cubes stacks on them
    scalars = {name: catalogue.effect_value(spec.scene.effects, name) for name in spec.scene.effects or {}}
    if spec.physical is not None:
        scalars.update(physical.constants(spec.physical))
        coords = physical.coordinates(spec.physical)
        arrays = {**arrays, **physical.variables(spec.physical, arrays)}
        attrs[physical.ATTRIBUTE] = physical.attribute(spec.physical)
    return cubes.cube_parts(
        arrays,
        frequency_ratio=spec.frequency_ratio,
        force_ratio=spec.force_ratio,
        excitation=spec.scene.excitation,
        title=f"friction_sweep: {spec.scene.excitation} excitation, method {spec.method}",
        history=provenance.history_line(command),
        attrs={**provenance.attributes(spec_text=spec.text, spec_path=spec.source_path,
                                       excitation=spec.scene.excitation, method=spec.method,
                                       settings=recorded_settings(spec, settings)),
               **_effects_attribute(spec), **attrs},
        physical=coords,
        physical_dims=spec.physical is not None and spec.physical.physical_dims,
        scalars=scalars,
    )


def _effects_attribute(spec: Spec) -> dict[str, str]:
    """The scene's effects in words (where a dashpot sits, too), as the cube's `effects` attribute; none
    without effects."""
    lines = catalogue.effect_lines(spec.scene.excitation, spec.scene.effects)
    return {"effects": "; ".join(lines)} if lines else {}


def dataset(spec: Spec, arrays: dict[str, np.ndarray], settings: dict[str, Any], command: str,
            extra_attrs: dict[str, Any] | None = None) -> xr.Dataset:
    """The labelled cube of a run's arrays as a Dataset (cube)."""
    from friction_sweep.storage.cube import as_dataset

    return as_dataset(cube(spec, arrays, settings, command, extra_attrs))
