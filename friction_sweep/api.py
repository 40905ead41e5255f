"""The Python API: a sweep from a notebook, validated exactly as `fsweep run` validates it.

    import friction_sweep as fs
    ds = fs.sweep("configs/demo.yaml")             # a spec file
    ds = fs.sweep({"scene": {"excitation": "base"}, "grid": {...}, "method": "event"})   # a dict
    ds = fs.sweep_yaml(text)                         # YAML text
    ds = fs.open_cube("results/demo.nc")             # a cube `fsweep run` wrote

Each returns the xarray Dataset that `fsweep run` would write (the same variables, coordinates and
attributes), and writes nothing. Every refusal is a friction_sweep.FsweepError whose message is the one
the CLI prints (a spec's: one `file:line:column: key: reason` line per problem; a dict's: `<dict>: key:
reason`, as a dict has no lines): of an argument of the wrong type or out of range as well (a path that is
not a str, bytes or os.PathLike or holds a NUL; jobs not a whole number from 1 to MAX_JOBS; an unknown
executor; YAML text that is not a str), never a TypeError or ValueError from underneath.

A dict spec is held to a spec file's bounds: written as YAML it is at most MAX_SPEC_BYTES, but for the grid's
frequency_ratio and force_ratio given as numpy arrays (or long lists of numbers), which are checked as whole
arrays (spec/model.py) and may hold up to the grid's MAX_POINTS values.
"""

from __future__ import annotations

import datetime
import operator
import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from friction_sweep import packaged
from friction_sweep.batch.executors import DEFAULT_EXECUTOR, EXECUTORS, MAX_JOBS
from friction_sweep.errors import FsweepError
from friction_sweep.spec import Spec, SpecError, grid, load_spec, parse_spec_text
from friction_sweep.spec.base import show
from friction_sweep.spec.errors import SpecProblem
from friction_sweep.spec.load import MAX_DEPTH, MAX_SPEC_BYTES, KeyPath, format_key, parse_yaml
from friction_sweep.spec.parse import spec_of_document
from friction_sweep.spec.structure import StructureSpec

if TYPE_CHECKING:
    import xarray as xr

#: the source a dict spec is named by in messages
DICT_SOURCE = "<dict>"
#: where a dict may hold a numpy array (or a long list of numbers) checked as a whole
ARRAY_AXES: tuple[KeyPath, ...] = (("grid", "frequency_ratio"), ("grid", "force_ratio"))
#: the same in a structure spec (a dict with `structure:`), whose grid.frequency is dimensionless
STRUCTURE_ARRAY_AXES: tuple[KeyPath, ...] = (("grid", "frequency"), ("grid", "friction_scale"))


def sweep(spec: str | bytes | os.PathLike | Mapping[str, Any], *, jobs: int = 1,
          executor: str = DEFAULT_EXECUTOR) -> xr.Dataset:
    """Run the spec (a file path, or a dict as the YAML would hold it: numpy arrays and numbers are fine)
    and return its cube. `jobs` and `executor` as `fsweep run -j N --executor E`."""
    jobs, executor = run_options(jobs, executor)
    if isinstance(spec, Mapping):
        return run(spec_of_dict(spec), jobs=jobs, executor=executor)
    path = path_argument(spec, "spec", "a spec file's path (str, bytes or os.PathLike) or a dict")
    reason = packaged.problem(path)  # package:PATH, a spec shipped with the package
    if reason is not None:
        raise FsweepError(f"spec: {reason}")
    return run(load_spec(packaged.resolve(path)), jobs=jobs, executor=executor)


def sweep_yaml(text: str, *, jobs: int = 1, executor: str = DEFAULT_EXECUTOR) -> xr.Dataset:
    """Run the spec given as YAML text and return its cube."""
    jobs, executor = run_options(jobs, executor)
    if not isinstance(text, str):
        raise FsweepError(f"sweep_yaml: text must be the spec's YAML as a str (got {_kind(text)}); "
                          "fs.sweep(path) reads a file")
    return run(parse_spec_text(text), jobs=jobs, executor=executor)


def run(spec: Spec | StructureSpec, *, jobs: int = 1, executor: str = DEFAULT_EXECUTOR) -> xr.Dataset:
    """Run a validated spec (1-DoF or structure) and return its cube (FsweepError where `accuracy:` finds no
    setting)."""
    from friction_sweep.batch import pipeline, structure_sweep

    jobs, executor = run_options(jobs, executor)
    if not isinstance(spec, (Spec, StructureSpec)):
        raise FsweepError(f"run: spec must be a validated Spec (got {_kind(spec)}); fs.sweep takes a path or dict")
    flow: Any = structure_sweep if isinstance(spec, StructureSpec) else pipeline
    settings, extra = accuracy_settings(spec)
    arrays = flow.compute(spec, settings, jobs=jobs, executor=executor)
    return flow.dataset(spec, arrays, settings, f"friction_sweep.batch({spec.source_path!r})", extra)


def peak(spec: str | bytes | os.PathLike | Mapping[str, Any], *, variable: str = "transmissibility",
         r_tol: float = 1e-10) -> xr.Dataset:
    """The resonance peak of the spec's scene for each force ratio of its grid (friction_sweep.design.peak):
    the largest `variable` over frequency, refined between the frequency grid's neighbours on the exact
    solver to `r_tol` in r, with every local maximum (dim `peak`), its frequency ratio and regime; and the
    phase resonance (friction_sweep.design.phase_resonance): every r where the first harmonic lags the
    excitation by 90 degrees, bisected to `r_tol` (dim `crossing`). A structure spec's: of the mass
    `settings: {peak_dof: NAME}` (design.structure), for each friction_scale over the angular frequency
    (resonance_frequency, ...), the regime per contact."""
    from friction_sweep.design import peak as design_peak
    from friction_sweep.design import phase_resonance

    problem, r, beta, attrs, axes = _design_problem(spec, variable, r_tol)
    curve = design_peak.peaks(problem, r, beta, r_tol)
    crossings = phase_resonance.crossings(problem, r, beta, r_tol, curve.grid_phase)
    return design_peak.dataset(curve, beta, attrs, crossings, axes)


def optimize(spec: str | bytes | os.PathLike | Mapping[str, Any], *, variable: str = "transmissibility",
             beta_tol: float = 1e-8, r_tol: float = 1e-10) -> xr.Dataset:
    """The force ratio that minimises the resonance peak (friction_sweep.design.optimum), to `beta_tol`,
    searched from the spec's force-ratio grid, with the performance curve (fs.peak's Dataset) it came
    from; the optimum in optimum_force_ratio, optimum_peak, optimum_frequency_ratio, and how it was found
    in the attribute optimum_kind. A structure spec's: the friction_scale (optimum_friction_scale,
    optimum_frequency, optimum_regime per contact)."""
    from friction_sweep.design import optimum as design_optimum

    problem, r, beta, attrs, axes = _design_problem(spec, variable, r_tol)
    if beta.size < 3:
        levels = "force ratios" if axes.contacts is None else "friction scales"
        raise FsweepError(f"{attrs['spec']}: grid.{axes.friction}: the optimum is searched from at least 3 "
                          f"{levels} (got {beta.size})")
    if np.any(np.diff(beta) <= 0):
        raise FsweepError(f"{attrs['spec']}: grid.{axes.friction}: the optimum is searched from increasing "
                          "friction levels")
    if not _positive_tolerance(beta_tol):
        raise FsweepError(f"beta_tol must be a positive number (got {_shown(beta_tol)})")
    found = design_optimum.optimum(problem, r, beta, float(beta_tol), r_tol)
    return design_optimum.dataset(found, {**attrs, "beta_tol": float(beta_tol)}, axes)


def backbone(spec: str | bytes | os.PathLike | Mapping[str, Any], *, r_tol: float = 1e-10) -> xr.Dataset:
    """The backbone of the spec's scene (friction_sweep.design.backbone): at every phase-resonance point of
    each force ratio (bisected on the exact solver to `r_tol` in r from the frequency grid), the first-
    harmonic amplitude, the energy dissipated per period, the springs' potential energy at the largest
    displacement and the equivalent damping ratio zeta_eq = E_d / (4 pi E_p), along dims (force_ratio,
    crossing). Scenes force, and base with the dashpot (if any) to the ground. A structure spec's (force
    excitation): along the phase resonance of the mass `settings: {peak_dof: NAME}`, E_p the largest
    elastic energy of the first-harmonic motion (friction_sweep.design.structure), dims (friction_scale,
    crossing[, contact])."""
    from friction_sweep.design import backbone as design_backbone
    from friction_sweep.design import structure as design_structure

    problem, r, beta, attrs, axes = _design_problem(spec, "transmissibility", r_tol)
    attrs.pop("variable")
    if isinstance(problem, design_structure.StructureProblem):
        reason = design_structure.backbone_refusal(problem)
        if reason is not None:
            raise FsweepError(f"{attrs['spec']}: scene: {reason} (got {problem.assembled.excitation!r})")
        found = design_structure.backbone(problem, r, beta, r_tol)
        return design_backbone.dataset(found, beta, attrs, axes, design_structure.POTENTIAL)
    reason = design_backbone.refusal(problem)
    if reason is not None:
        raise FsweepError(f"{attrs['spec']}: scene: {reason} (got {problem.excitation!r})")
    found = design_backbone.backbone(problem, r, beta, r_tol)
    return design_backbone.dataset(found, beta, attrs)


def _positive_tolerance(value: Any) -> bool:
    return bool(isinstance(value, (int, float, np.floating, np.integer))
                and not isinstance(value, (bool, np.bool_)) and np.isfinite(value) and value > 0)


def _design_problem(spec: Any, variable: Any, r_tol: Any):
    """The peak's Problem, frequency and force grids and Dataset attributes from a spec, or FsweepError
    where the spec is not one the peak is built for."""
    from friction_sweep.design.peak import METHODS, ONE_DOF, PEAK_VARIABLES, Problem

    if isinstance(spec, Mapping):
        parsed = spec_of_dict(spec)
    else:
        parsed = load_spec(path_argument(spec, "spec", "a spec file's path (str, bytes or os.PathLike) or a dict"))
    where = parsed.source_path
    if isinstance(parsed, StructureSpec):
        return _structure_design_problem(parsed, variable, r_tol)
    if parsed.method not in METHODS:
        raise FsweepError(f"{where}: method: the resonance peak is built on methods {', '.join(METHODS)} "
                          f"(got {parsed.method!r})")
    if parsed.sweep is not None:
        raise FsweepError(f"{where}: sweep: the resonance peak solves each point on its own; drop `sweep:`")
    if not isinstance(variable, str) or variable not in PEAK_VARIABLES:
        raise FsweepError(f"variable must be one of: {', '.join(PEAK_VARIABLES)} (got {_shown(variable)})")
    if not _positive_tolerance(r_tol):
        raise FsweepError(f"r_tol must be a positive number (got {_shown(r_tol)})")
    r = np.array(parsed.frequency_ratio, dtype=float)
    beta = np.array(parsed.force_ratio, dtype=float)
    if beta.ndim != 1:
        raise FsweepError(f"{where}: grid: the resonance peak needs one force ratio per friction level "
                          "(not one per point, as at constant base acceleration)")
    if r.size < 3:
        raise FsweepError(f"{where}: grid.frequency_ratio: the peak is searched from at least 3 frequency "
                          f"ratios (got {r.size})")
    settings, _ = accuracy_settings(parsed)
    problem = Problem(parsed.method, parsed.scene.excitation, parsed.scene.effects or None, settings, variable)
    attrs = {"spec": str(where), "method": parsed.method, "excitation": parsed.scene.excitation,
             "variable": variable, "r_tol": float(r_tol),
             "frequency_ratio_range": np.array([r.min(), r.max()])}
    physical = parsed.physical
    if physical is not None and physical.reference_force is not None and physical.length_scale is not None:
        # the scales of (beta, T) where the spec has a system: friction force beta F_k (N), amplitude T L (m)
        attrs["reference_force"] = float(physical.reference_force)
        attrs["length_scale"] = float(physical.length_scale)
    return problem, r, beta, attrs, ONE_DOF


def _structure_design_problem(parsed: StructureSpec, variable: Any, r_tol: Any):
    """_design_problem's answer for a structure spec: the chosen mass's response (design.structure), the
    angular frequency and friction_scale grids, and the Dataset's attributes and axes."""
    from friction_sweep.batch import structure_sweep
    from friction_sweep.design import structure as design_structure
    from friction_sweep.structures import assemble

    where = parsed.source_path
    if not isinstance(variable, str) or variable not in design_structure.VARIABLES:
        raise FsweepError(f"variable must be one of: {', '.join(design_structure.VARIABLES)} (got {_shown(variable)})")
    if not _positive_tolerance(r_tol):
        raise FsweepError(f"r_tol must be a positive number (got {_shown(r_tol)})")
    w = np.array(parsed.frequency, dtype=float)
    s = np.array(parsed.friction_scale, dtype=float)
    if w.size < 3 or np.any(np.diff(w) <= 0):
        raise FsweepError(f"{where}: grid.frequency: the peak is searched from at least 3 increasing frequencies "
                          f"(got {w.size})")
    a = assemble(structure_sweep.structure_def(parsed))
    settings, _ = accuracy_settings(parsed)
    dof = parsed.settings.get(design_structure.DOF_SETTING) or design_structure.default_dof(a)
    problem = design_structure.StructureProblem(a, dof, settings, variable)
    attrs: dict[str, Any] = {"spec": str(where), "method": parsed.method, "excitation": parsed.scene.excitation,
                             "variable": variable, "dof": dof, "r_tol": float(r_tol),
                             "frequency_range": np.array([w.min(), w.max()])}
    if parsed.physical is not None:  # the angular frequency over omega_0 (spec.structure_units)
        attrs["reference_frequency"] = float(parsed.physical.omega)
    return problem, w, s, attrs, design_structure.axes(a)


def run_options(jobs: Any, executor: Any) -> tuple[int, str]:
    """`jobs` as an int from 1 to MAX_JOBS (numpy integers too; not a bool or float) and `executor` one of
    the executors (Dask only where it is installed), or FsweepError."""
    try:
        n = None if isinstance(jobs, (bool, np.bool_)) else operator.index(jobs)
    except TypeError:
        n = None
    if n is None or not 1 <= n <= MAX_JOBS:
        raise FsweepError(f"jobs must be a whole number from 1 to {MAX_JOBS} (got {_shown(jobs)})")
    if not isinstance(executor, str) or executor not in EXECUTORS:
        raise FsweepError(f"executor must be one of: {', '.join(EXECUTORS)} (got {_shown(executor)})")
    if executor == "dask":
        from friction_sweep.batch.executors import DaskUnavailable, check_dask

        try:
            check_dask(None)
        except DaskUnavailable as err:
            raise FsweepError(str(err)) from None
    return int(n), executor


def path_argument(value: Any, name: str, expected: str) -> str:
    """A path argument as str: a str, bytes (decoded as the file system does) or os.PathLike; FsweepError
    for anything else or a path holding a NUL (which no file name can)."""
    try:
        path = os.fsdecode(value) if isinstance(value, (str, bytes, os.PathLike)) else None
    except Exception:  # an os.PathLike whose __fspath__ fails or returns neither str nor bytes
        path = None
    if path is None:
        raise FsweepError(f"{name} must be {expected} (got {_kind(value)})")
    if not path:
        raise FsweepError(f"{name}: the path is empty")
    if "\0" in path:
        raise FsweepError(f"{name}: {_shown(path)} holds a NUL character, which no file name can")
    return path


def _kind(value: Any) -> str:
    return f"{type(value).__name__} {_shown(value)}"


def _shown(value: Any) -> str:
    try:
        return show(value)
    except Exception:  # an object whose repr fails
        return f"a {type(value).__name__}"


def accuracy_settings(spec: Spec | StructureSpec) -> tuple[dict[str, Any], dict[str, Any]]:
    """The run's settings and the attributes recording what `accuracy:` chose; FsweepError if nothing can."""
    from friction_sweep.batch import structure_sweep
    from friction_sweep.batch.pipeline import run_settings

    try:
        return structure_sweep.run_settings(spec) if isinstance(spec, StructureSpec) else run_settings(spec)
    except LookupError as err:
        raise FsweepError(f"{spec.source_path}: accuracy: {err}") from None


def spec_of_dict(data: Mapping[str, Any]) -> Spec | StructureSpec:
    """A spec given as a dict: written as YAML (the cube records that text) and validated as a file is;
    problems carry the dict's keys, not the lines of that text. numpy values become plain numbers; a grid
    axis given as an array (or a long list of numbers) is written into the text as a flow list but
    validated as a whole array (spec/model.py), never through a YAML parser or number by number."""
    arrays: dict[str, np.ndarray] = {}
    budget = [MAX_SPEC_BYTES]
    axes = STRUCTURE_ARRAY_AXES if "structure" in data else ARRAY_AXES
    plain = _plain(data, (), arrays, budget, axes)
    text = _dump(plain)
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > MAX_SPEC_BYTES:
        raise SpecError.single(DICT_SOURCE, _too_large(size))
    try:
        doc = parse_yaml(text, DICT_SOURCE)
        if isinstance(doc.data, dict):
            _put_arrays(doc.data, arrays)
        spec = spec_of_document(doc, text)
    except SpecError as err:
        raise SpecError([SpecProblem(p.path, None, None, p.key, p.reason) for p in err.errors]) from None
    for mark, values in arrays.items():  # the text the cube records: the arrays (valid now) written out
        text = text.replace(mark, _flow_list(values), 1)
    spec._text = text
    return spec


def _too_large(size: int | None) -> str:
    """`size`: the YAML's bytes, None where counting stopped at the bound."""
    what = f"{size} bytes" if size is not None else f"more than {MAX_SPEC_BYTES} bytes"
    return (f"written as YAML the spec is {what}; a spec is at most {MAX_SPEC_BYTES} (give long grid axes "
            "as numpy arrays at grid.frequency_ratio / grid.force_ratio, or as {start, stop, num})")


def _plain(value: Any, path: KeyPath, arrays: dict[str, np.ndarray], budget: list[int],
           axes: tuple[KeyPath, ...] = ARRAY_AXES) -> Any:
    """numpy arrays and scalars as lists and numbers, tuples as lists, keys as they are; an array of numbers
    at a grid axis (ARRAY_AXES) replaced by a marker string (its float64 values in `arrays`). SpecError
    where the dict nests deeper than a spec may (a dict holding itself does) or holds more than a spec
    file may (`budget`: bytes left, counted roughly as the YAML will hold them)."""
    if len(path) > MAX_DEPTH:
        raise SpecError.single(DICT_SOURCE, f"nested deeper than {MAX_DEPTH} levels (a spec nests 4; does the dict "
                               "hold itself?)", key=format_key(path[:MAX_DEPTH]))
    if isinstance(value, np.ma.MaskedArray):  # np.asarray would drop the mask: a masked value would be run
        value = _unmasked(value, path)
    if path in axes and (array := _number_array(value)) is not None:
        mark = f"fsweep-array-{len(arrays)}-{id(value):x}"
        arrays[mark] = array
        return mark
    if isinstance(value, np.ndarray) and value.ndim == 0 or isinstance(value, np.generic):
        return _scalar(np.asarray(value))
    budget[0] -= len(value) + 2 if isinstance(value, (str, bytes)) else 8
    if budget[0] < 0:
        raise SpecError.single(DICT_SOURCE, _too_large(None))
    if isinstance(value, Mapping):
        return {k: _plain(v, (*path, str(k)), arrays, budget, axes) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        if 2 * value.size > budget[0]:  # each value at least two bytes of YAML; refused before listing it
            raise SpecError.single(DICT_SOURCE, _too_large(None))
        value = list(value)  # each element a numpy scalar, read as one below
    if isinstance(value, (list, tuple)):
        return [_plain(v, (*path, i), arrays, budget, axes) for i, v in enumerate(value)]
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > _MAX_INTEGER_BITS:
        raise SpecError.single(DICT_SOURCE, f"{show(value)} is beyond any number a spec holds (a double holds at "
                               "most 1.8e308)", key=format_key(path))
    if not isinstance(value, _YAML_SCALARS):
        raise SpecError.single(DICT_SOURCE, f"cannot be written as YAML (got {show(value)})", key=format_key(path))
    return value


#: what YAML holds, as the safe loader reads it back (a spec key refuses the ones it does not take, by name)
_YAML_SCALARS = (str, bytes, int, float, type(None), datetime.date, set, frozenset)
#: an integer beyond a double's range holds no number fsweep computes with (and beyond 4300 digits Python
#: cannot even write it as YAML)
_MAX_INTEGER_BITS = 1024


def _unmasked(value: np.ma.MaskedArray, path: KeyPath) -> np.ndarray:
    """A numpy masked array's values, where none is masked; SpecError naming the key where one is (a masked
    value means "no value here", which fsweep cannot compute, and np.asarray would turn into a number)."""
    masked = int(np.ma.count_masked(value))
    if masked:
        raise SpecError.single(DICT_SOURCE, f"a numpy masked array with {masked} masked value(s) of {value.size}: "
                               "fsweep computes every value it is given; pass only the values to compute "
                               "(e.g. values.compressed())", key=format_key(path))
    return np.ma.getdata(value)


def _number_array(value: Any) -> np.ndarray | None:
    """`value` as an array checked whole by the grid model: a numpy array (any shape or dtype: the model
    says what is wrong) or what numpy reads as one (a pandas Series, an xarray coordinate), or a list of
    more than a few plain numbers; None for anything else."""
    if isinstance(value, np.ndarray):
        return value
    if hasattr(value, "__array__") and not isinstance(value, (str, bytes, Mapping, list, tuple, np.generic)):
        try:
            return np.asarray(value)
        except Exception:  # an __array__ that fails: the value goes the way of any other
            return None
    if isinstance(value, (list, tuple)) and len(value) > 16 and \
            all(type(x) in (int, float) for x in value):
        try:
            return np.array(value, dtype=np.float64)
        except OverflowError:  # an integer beyond a double: the list's own validation says so
            return None
    return None


def _scalar(value: np.ndarray) -> Any:
    """A numpy scalar (0-d) as the plain number, bool or str it holds; float64 for every float type
    (a longdouble beyond a double's range becomes infinite, which validation refuses)."""
    if value.dtype.kind == "f":
        with np.errstate(over="ignore"):
            return float(value.astype(np.float64))
    return value.item() if value.dtype.kind in "biuUS" else value.tolist()


def _dump(plain: Any) -> str:
    import io

    from ruamel.yaml import YAML

    yaml = YAML(typ="safe")
    yaml.default_flow_style = None
    buffer = io.StringIO()
    try:
        yaml.dump(plain, buffer)
    except Exception:  # a key or a set's member YAML cannot hold: _plain refuses every other value, by its key
        raise SpecError.single(DICT_SOURCE, "cannot be written as YAML (a key, or a member of a set, is no "
                               "YAML value)") from None
    return buffer.getvalue()


def _put_arrays(data: dict, arrays: dict[str, np.ndarray]) -> None:
    """The marker strings at the grid axes replaced by their arrays."""
    for parent, name in (*ARRAY_AXES, *STRUCTURE_ARRAY_AXES):
        holder = data.get(parent)
        if isinstance(holder, dict) and isinstance(holder.get(name), str) and holder[name] in arrays:
            holder[name] = arrays[holder[name]]


def _on_lattice(values: np.ndarray) -> bool:
    """Whether `values` are exactly {start, stop, num}'s values (grid.linspace_values). The rounding is a
    formatting per value (seconds for 10^7): a sample of 64 is tried first."""
    n = values.size
    if n < 3:
        return False
    sample = np.unique(np.linspace(0, n - 1, 64).astype(np.int64))
    raw = np.linspace(values[0], values[-1], n)
    if not np.array_equal(grid.round_significant(raw[sample[1:-1]]), values[sample[1:-1]]):
        return False
    return bool(np.array_equal(grid.linspace_values(float(values[0]), float(values[-1]), n), values))


def _flow_list(values: np.ndarray) -> str:
    """A validated axis array (1-D, numbers) as YAML that reads back to the same values: {start, stop, num}
    where it is that range's lattice (np.linspace rounded to the grid's digits), else a flow list."""
    integers = values.dtype.kind in "iu"
    values = values if integers else values.astype(np.float64)  # a longdouble's repr is not YAML
    if not integers and _on_lattice(values):
        return f"{{start: {float(values[0])!r}, stop: {float(values[-1])!r}, num: {values.size}}}"
    # in chunks: one list of 10^7 Python floats and their texts would hold a gigabyte at once
    return "[" + ", ".join(", ".join(map(str if integers else repr, values[i:i + 65536].tolist()))
                           for i in range(0, values.size, 65536)) + "]"


def open_cube(path: str | os.PathLike[str]) -> xr.Dataset:
    """The cube at `path`, loaded into memory and checked as `fsweep info` checks it
    (friction_sweep.storage.cube.open_cube); FsweepError where it is not a regular file, not readable, not
    a friction_sweep cube, or holds values no run writes."""
    from friction_sweep.storage import cube

    return cube.open_cube(path_argument(path, "path", "a cube's path (str, bytes or os.PathLike)"))
