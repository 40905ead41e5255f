"""A structure spec (spec.structure) from its grid to its labelled cube: the pieces batch.pipeline has for a
1-DoF spec, with the same names, for `fsweep run` (around its checkpoint and lock) and the Python API.

Tiles are fixed blocks of TILE_FREQUENCIES frequencies by every friction scale (batch.layout), each solved by
the engine (friction_sweep.structures.solve_points) as one flat batch of points, friction_scale-major; a
swept run's (`sweep:`) are blocks of TILE_FORCES friction scales by every frequency, each scale one sequential
sweep (structures.starts.solve_sweep). A
point's result depends only on its own inputs (the engine's contract), so the cube is the same bit for bit
whatever the executor, the number of workers, or which tiles a resumed run read back.
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable
from typing import Any

import numpy as np

import friction_sweep
from friction_sweep.batch.executors import DEFAULT_EXECUTOR
from friction_sweep.spec.structure import DESIGN_SETTINGS, STRUCTURE_SETTINGS, StructureSpec
from friction_sweep.storage.schema import MOVING_SUFFIX, STRUCTURE_ATTRIBUTE, STRUCTURE_VARIABLES

log = logging.getLogger("friction_sweep")


def structure_def(spec: StructureSpec):
    """The engine's description of the spec's structure (friction_sweep.structures.StructureDef): a physical
    structure's dimensionless one (spec.structure_units)."""
    from friction_sweep.structures.model import scaled

    p = spec.physical
    return si_structure_def(spec) if p is None else scaled(si_structure_def(spec), p.mass, p.stiffness, p.damping,
                                                           p.force, p.length)


def si_structure_def(spec: StructureSpec):
    """The spec's structure as it is written (SI where it is physical), as a StructureDef."""
    from friction_sweep.structures import ContactDef, StructureDef

    st = spec.structure
    contacts = tuple(ContactDef(name=c.name, between=c.between, friction=c.friction, stiffness=c.stiffness,
                                static_friction_ratio=c.static_friction_ratio) for c in st.contacts)
    return StructureDef(excitation=spec.scene.excitation, masses=dict(st.masses or {}), springs=tuple(st.springs),
                        dampers=tuple(st.dampers), contacts=contacts, forcing=dict(st.forcing or {}),
                        base_amplitude=st.base_motion, dofs=st.dofs, matrices=st.given_matrices)


def run_settings(spec: StructureSpec, table: dict | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """The run's settings (the spec's, with the knobs `accuracy:` chooses from the benchmark's structure rows in
    the calibration, `table` or the file's; not the design's peak_dof, which no number of the cube depends on)
    and the cube attributes that record that choice (batch.pipeline.run_settings's). LookupError where no
    calibrated setting meets the accuracy."""
    settings = {k: v for k, v in spec.settings.items() if k not in DESIGN_SETTINGS}
    if spec.accuracy is None:
        return settings, {}
    from friction_sweep.bench.workprecision import choose  # reads the calibration file

    chosen, row = choose(spec.method, spec.accuracy, table, structure=True)
    settings.update(chosen)
    return settings, {"accuracy_requested": spec.accuracy, "accuracy_choice": json.dumps(row, sort_keys=True)}


def recorded_settings(spec: StructureSpec, settings: dict[str, Any]) -> dict[str, Any]:
    """The settings the numbers came from, for the cube's method_settings: the method's defaults (catalogue)
    with the run's over them."""
    from friction_sweep.catalogue import METHODS

    defaults = METHODS[spec.method].defaults
    recorded = {**{k: defaults[k] for k in STRUCTURE_SETTINGS[spec.method]}, **settings}
    if "harmonics" not in spec.outputs:  # the output's size: no knob of a run without it
        recorded.pop("harmonics", None)
    if spec.sweep is not None:  # the sweep is the start: no second one (batch.pipeline's rule)
        recorded.pop("starts", None)
        recorded["sweep"] = spec.sweep.direction
    return recorded


def checkpoint_key(spec: StructureSpec, settings: dict[str, Any], extra_attrs: dict[str, Any]) -> str:
    """The fingerprint of every input that changes a number of the run (batch.pipeline.checkpoint_key's
    rule): the spec as parsed, the grid's values and tiles, the settings, the version and the code."""
    from friction_sweep.batch import checkpoint
    from friction_sweep.batch.layout import TILE_FORCES, TILE_FREQUENCIES
    from friction_sweep.batch.pipeline import code_version

    return checkpoint.fingerprint(
        spec=spec.model_dump(mode="json", exclude={"output"}), frequency=np.asarray(spec.frequency, dtype=float),
        friction_scale=np.asarray(spec.friction_scale, dtype=float),
        tile=TILE_FORCES if spec.sweep else TILE_FREQUENCIES, sweep=_direction(spec), settings=settings,
        recorded=recorded_settings(spec, settings), accuracy=extra_attrs, version=friction_sweep.__version__,
        code=code_version(), model=_model_digest(spec))


def tile_grids(spec: StructureSpec) -> list[dict[str, np.ndarray]]:
    """Each tile's grid values, which a checkpoint tile must carry to be used again."""
    frequency, scale = spec.frequency, spec.friction_scale
    if spec.sweep is not None:
        return [{"frequency": np.ascontiguousarray(frequency), "friction_scale": np.ascontiguousarray(scale[s])}
                for s in _parts(spec)]
    return [{"frequency": np.ascontiguousarray(frequency[s]), "friction_scale": np.ascontiguousarray(scale)}
            for s in _parts(spec)]


def _direction(spec: StructureSpec) -> str | None:
    return spec.sweep.direction if spec.sweep is not None else None


def _parts(spec: StructureSpec) -> list[slice]:
    """The run's tiles (batch.layout): slices of the frequencies, or of the friction scales for a swept run."""
    from friction_sweep.batch.layout import layout

    return layout(spec.frequency.size, spec.friction_scale.size, _direction(spec))


def compute_tile(args) -> dict[str, np.ndarray]:
    """One tile: a pure function of its arguments (picklable for processes and Dask). Each variable comes
    back as (friction_scale, frequency[, dof or contact]) arrays in the schema's dtype."""
    from friction_sweep.structures import assemble, solve_points, starts

    definition, frequency, scale, variables, outputs, settings, direction, method = args
    n_s, n_f = scale.size, frequency.size
    if direction is not None:  # a stepped-sine sweep along frequency at each friction scale
        a = assemble(definition)
        swept = [starts.solve_sweep(a, frequency, float(v), direction, settings, outputs, method) for v in scale]
        return {name: np.stack([np.asarray(one[name], dtype=STRUCTURE_VARIABLES[name].dtype) for one in swept])
                for name in variables}
    f = np.tile(frequency, n_s)  # friction_scale-major: point k is (scale[k // n_f], frequency[k % n_f])
    s = np.repeat(scale, n_f)
    a = assemble(definition)
    solved = solve_points(a, f, s, settings, outputs, method)
    if "harmonics" in outputs:
        solved.update(_harmonics(a, f, s, settings, solved))
    if any(name.endswith(MOVING_SUFFIX) for name in variables):  # the spec's two_starts
        moving = starts.solve_moving(a, f, s, settings, outputs, method)
        if "harmonics" in outputs:
            moving.update(_harmonics(a, f, s, settings, moving))
        solved.update({name + MOVING_SUFFIX: values for name, values in moving.items()})
        solved["steady_states"] = starts.count_states(solved, moving)
    return {name: np.asarray(solved[name], dtype=STRUCTURE_VARIABLES[name].dtype).reshape(
        (n_s, n_f, *np.shape(solved[name])[1:])) for name in variables}


def highest_harmonic(settings: dict[str, Any]) -> int:
    """H of the output harmonics: the setting, else the event method's default (catalogue)."""
    from friction_sweep.catalogue import METHODS

    return int(settings.get("harmonics", METHODS["event"].defaults["harmonics"]))


def _harmonics(a, f, s, settings: dict[str, Any], solved: dict) -> dict[str, np.ndarray]:
    """The output harmonics' variables of a solve's points (structures.harmonics), each (points, dof or
    contact, harmonic)."""
    from friction_sweep.structures.harmonics import orbit_harmonics

    h = orbit_harmonics(a, f, s, highest_harmonic(settings), settings, solved)
    out = {}
    for row, values in (("response", h["displacement"]), ("friction", h["contact_force"])):
        along = np.swapaxes(values, 1, 2)  # the harmonic last (schema.STRUCTURE_VARIABLES)
        out[f"{row}_harmonic_real"], out[f"{row}_harmonic_imag"] = along.real, along.imag
    return out


def compile_kernels(spec: StructureSpec, settings: dict[str, Any]) -> None:
    """Have numba compile (or load from its cache) the structure engine, by solving the spec's first point in
    this process (as batch.pipeline.compile_kernels does for a 1-DoF spec): fsweep run says so meanwhile."""
    frequency, scale = spec.frequency[:1], spec.friction_scale[:1]
    compute_tile((structure_def(spec), frequency, scale, spec.variables, spec.outputs, dict(settings), None,
                  spec.method))
    if spec.time_history is not None:  # the sampler's kernel, on the first point
        histories(spec, settings, slice(0, 1))


def compute(spec: StructureSpec, settings: dict[str, Any], *, jobs: int = 1, executor: str = DEFAULT_EXECUTOR,
            scheduler: str | None = None, done: dict | None = None,
            on_done: Callable[[int, dict], None] | None = None,
            on_tile: Callable[[int], None] | None = None) -> dict[str, np.ndarray]:
    """Every variable of the spec's cube on the whole plane (done/on_done/on_tile as batch.runner.run_grid:
    a checkpoint's tiles, saving each new one, progress in points)."""
    from friction_sweep.batch.runner import run_tiles

    frequency, scale = spec.frequency, spec.friction_scale
    definition = structure_def(spec)
    sizes = {"dof": len(spec.structure.dofs), "contact": len(spec.structure.contacts),
             "harmonic": highest_harmonic(settings) + 1}
    parts = _parts(spec)
    direction = _direction(spec)
    # a swept run's tile: some friction scales by every frequency; else some frequencies by every scale
    cuts = [(slice(None), p) if direction is None else (p, slice(None)) for p in parts]
    work = [(definition, frequency[f], scale[s], spec.variables, spec.outputs, dict(settings), direction, spec.method)
            for s, f in cuts]
    points = [scale[s].size * frequency[f].size for s, f in cuts]
    results: dict[str, np.ndarray] = {
        name: np.empty((scale.size, frequency.size, *[sizes[d] for d in STRUCTURE_VARIABLES[name].dims[2:]]),
                       dtype=STRUCTURE_VARIABLES[name].dtype) for name in spec.variables}

    def fits(i: int, tile: dict) -> bool:
        """A checkpoint's tile holding exactly this run's variables, each of its place's shape and dtype."""
        return set(tile) == set(results) and all(
            np.asarray(v).dtype == results[k].dtype and np.shape(v) == results[k][cuts[i]].shape
            for k, v in tile.items())

    def place(i: int, tile: dict) -> None:
        for name, values in tile.items():
            results[name][cuts[i]] = values
        if on_tile is not None:
            on_tile(points[i])

    done = {i: t for i, t in (done or {}).items() if fits(i, t)}
    todo = [i for i in range(len(parts)) if i not in done]
    log.info("computing %d tiles (%d points) with %s, %d worker(s)", len(todo),
             sum(points[i] for i in todo), executor, jobs)
    run_tiles(compute_tile, work, place, done=done, executor=executor, jobs=jobs, scheduler=scheduler,
              on_done=on_done)
    if spec.time_history is not None:
        results.update(histories(spec, settings))
    return results


def histories(spec: StructureSpec, settings: dict[str, Any], points: slice = slice(None)) -> dict[str, np.ndarray]:
    """The time-history variables of the spec's chosen points (outputs: time_history; schema's history_*): each
    orbit from rest sampled by the engine's flow (structures.time_histories), and each contact's relative
    displacement u = w . x - ey cos(w t) beside its force."""
    from friction_sweep.kernels.structure.flow import CP_EY
    from friction_sweep.structures import assemble, time_histories
    from friction_sweep.structures.solve import contact_parameters

    assert spec.time_history is not None
    a = assemble(structure_def(spec))
    pts = spec.history_points[points]
    h = time_histories(a, pts, spec.time_history.samples_per_period, settings)
    m = len(a.contact_names)
    W = np.asarray(a.W, dtype=float).reshape(m, -1)
    ey = contact_parameters(a)[:, CP_EY]
    u = h["displacement"] @ W.T - ey * np.cos(2.0 * np.pi * h["time"])[..., None]
    orbit = np.where(np.isfinite(h["time"][:, 0]), np.nan_to_num(h["orbit_period"]), 0.0)
    return {"history_orbit_period": orbit, "history_time": h["time"],
            "history_displacement": h["displacement"] / a.amplitude_unit, "history_contact_force": h["contact_force"],
            "history_relative_displacement": u / a.amplitude_unit}


def physical_coordinates(spec: StructureSpec) -> dict[str, Any]:
    """The frequency over the first natural frequency with every contact stuck and free, and a physical
    structure's physical coordinates and scales (storage.schema.STRUCTURE_PHYSICAL_COORDS)."""
    from friction_sweep.spec.structure_units import first_frequency
    from friction_sweep.structures import assemble, natural_frequencies

    si = assemble(si_structure_def(spec))
    phys = spec.physical
    # the grid's angular frequencies in the structure's units as written (rad/s where physical)
    omega = spec.frequency if phys is None else spec.frequency * phys.omega
    out: dict[str, Any] = {}
    for reference in ("stuck", "free"):
        if phys is not None and reference == phys.reference:
            out[f"frequency_ratio_{reference}"] = spec.frequency  # as solved, bit for bit
            continue
        first = first_frequency(natural_frequencies(si, reference))
        if np.isfinite(first):  # none free where a mass is held only by a contact: a grid coordinate is never NaN
            out[f"frequency_ratio_{reference}"] = omega / first
    if phys is None:
        return out
    friction = np.array([c.friction for c in spec.structure.contacts])
    return {**out, "frequency_hz": omega / (2.0 * np.pi), "friction_force": np.outer(spec.friction_scale, friction),
            "reference_frequency": np.float64(phys.omega), "mass_scale": np.float64(phys.mass),
            "stiffness_scale": np.float64(phys.stiffness), "force_scale": np.float64(phys.force),
            "length_scale": np.float64(phys.length)}


def structure_attribute(spec: StructureSpec) -> str:
    """The solved structure as the cube's `structure` attribute (JSON)."""
    st = spec.structure
    if st.matrices is not None:  # the file's name and digest, and the matrices it held (the file may be gone)
        model: dict[str, Any] = {"matrices": {**st.matrices.model_dump(mode="json"), "sha256": _model_digest(spec)}}
    elif st.modes is not None:
        model = {"modes": st.modes.model_dump(mode="json")}
    else:
        model = {"masses": st.masses}
    if st.given_matrices is not None:  # what the engine solved (as written, SI where physical): `recorded` reads it
        model["dofs"] = list(st.dofs)
        model["solved_matrices"] = {name: values.tolist()
                                    for name, values in zip("MKC", st.given_matrices, strict=True)}
    return json.dumps({
        **model, "springs": [list(e) for e in st.springs], "dampers": [list(e) for e in st.dampers],
        "contacts": [c.model_dump(mode="json") for c in st.contacts], "forcing": st.forcing or {},
        **({"base_amplitude": st.base_motion} if spec.scene.excitation == "base" else {}),
    })


def _model_digest(spec: StructureSpec) -> str:
    """The reduced model's digest (a file's matrices are no part of the spec's text), or "" without one."""
    given = spec.structure.given_matrices
    return "" if given is None else _digest(given)


def _digest(matrices) -> str:
    """SHA-256 of the model's M, K and C as solved (float64, C order): which model a cube came from."""
    import hashlib

    h = hashlib.sha256()
    for a in matrices:
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    return h.hexdigest()


def cube(spec: StructureSpec, arrays: dict[str, np.ndarray], settings: dict[str, Any], command: str,
         extra_attrs: dict[str, Any] | None = None):
    """The parts of the labelled cube of a run's arrays (storage.cube.CubeParts), with its provenance (as a
    1-DoF cube's) and the structure it solved."""
    from friction_sweep.storage import cube as cubes
    from friction_sweep.storage import provenance

    excitation = spec.scene.excitation
    coords = {"friction_scale": spec.friction_scale, "frequency": spec.frequency,
              "dof": np.array(list(spec.structure.dofs), dtype=str),
              "contact": np.array([c.name for c in spec.structure.contacts], dtype=str),
              **physical_coordinates(spec)}
    if "harmonics" in spec.outputs:
        coords["harmonic"] = np.arange(highest_harmonic(settings) + 1)
    if spec.time_history is not None:
        points = spec.history_points
        coords.update(history_frequency=points[:, 0], history_friction_scale=points[:, 1])
        if spec.physical is not None:
            coords["history_frequency_hz"] = points[:, 0] * spec.physical.omega / (2.0 * np.pi)
    n, m = len(spec.structure.dofs), len(spec.structure.contacts)
    return cubes.structure_cube_parts(
        arrays, coords=coords, excitation=excitation,
        title=f"friction_sweep: structure of {n} masses and {m} contacts, {excitation} excitation, "
              f"method {spec.method}",
        history=provenance.history_line(command),
        attrs={**provenance.attributes(spec_text=spec.text, spec_path=spec.source_path, excitation=excitation,
                                       method=spec.method, settings=recorded_settings(spec, settings)),
               STRUCTURE_ATTRIBUTE: structure_attribute(spec), **(extra_attrs or {})},
    )


def dataset(spec: StructureSpec, arrays: dict[str, np.ndarray], settings: dict[str, Any], command: str,
            extra_attrs: dict[str, Any] | None = None):
    """The labelled cube of a run's arrays as an xarray Dataset."""
    from friction_sweep.storage.cube import as_dataset

    return as_dataset(cube(spec, arrays, settings, command, extra_attrs))
