"""The Python API: a sweep from a notebook, validated exactly as `fsweep run` validates it.

    import friction_sweep as fs
    ds = fs.sweep("configs/demo.yaml")             # a spec file
    ds = fs.sweep({"scene": {"excitation": "base"}, "grid": {...}, "method": "event"})   # a dict
    ds = fs.sweep_yaml(text)                         # YAML text
    ds = fs.open_cube("results/demo.h5")             # a cube `fsweep run` wrote

Each returns the xarray Dataset that `fsweep run` would write (the same variables, coordinates and
attributes), and writes nothing. Every refusal is a friction_sweep.FsweepError whose message is the one
the CLI prints (a spec's: one `file:line:column: key: reason` line per problem; a dict's: `<dict>: key:
reason`, as a dict has no lines).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from friction_sweep.errors import FsweepError
from friction_sweep.spec import Spec, SpecError, load_spec, parse_spec_text
from friction_sweep.spec.errors import SpecProblem

if TYPE_CHECKING:
    import xarray as xr

#: the source a dict spec is named by in messages
DICT_SOURCE = "<dict>"


def sweep(spec: str | os.PathLike[str] | Mapping[str, Any], *, jobs: int = 1, executor: str = "threads") -> xr.Dataset:
    """Run the spec (a file path, or a dict as the YAML would hold it: numpy arrays and numbers are fine)
    and return its cube. `jobs` and `executor` as `fsweep run -j N --executor E`."""
    if isinstance(spec, Mapping):
        return run(spec_of_dict(spec), jobs=jobs, executor=executor)
    return run(load_spec(spec), jobs=jobs, executor=executor)


def sweep_yaml(text: str, *, jobs: int = 1, executor: str = "threads") -> xr.Dataset:
    """Run the spec given as YAML text and return its cube."""
    return run(parse_spec_text(text), jobs=jobs, executor=executor)


def run(spec: Spec, *, jobs: int = 1, executor: str = "threads") -> xr.Dataset:
    """Run a validated spec and return its cube (FsweepError where `accuracy:` finds no setting)."""
    from friction_sweep.batch import pipeline

    settings, extra = accuracy_settings(spec)
    arrays = pipeline.compute(spec, settings, jobs=jobs, executor=executor)
    return pipeline.dataset(spec, arrays, settings, f"friction_sweep.batch({spec.source_path!r})", extra)


def accuracy_settings(spec: Spec) -> tuple[dict[str, Any], dict[str, Any]]:
    """The run's settings and the attributes recording what `accuracy:` chose; FsweepError if nothing can."""
    from friction_sweep.batch.pipeline import run_settings

    try:
        return run_settings(spec)
    except LookupError as err:
        raise FsweepError(f"{spec.source_path}: accuracy: {err}") from None


def spec_of_dict(data: Mapping[str, Any]) -> Spec:
    """A spec given as a dict: written as YAML (the cube records that text) and validated as a file is;
    problems carry the dict's keys, not the lines of that text."""
    import io

    from ruamel.yaml import YAML

    yaml = YAML(typ="safe")
    yaml.default_flow_style = None
    buffer = io.StringIO()
    try:
        yaml.dump(_plain(data), buffer)
    except Exception as err:  # a value YAML cannot hold (an object, a function)
        raise SpecError.single(DICT_SOURCE, f"cannot be written as YAML: {' '.join(str(err).split())}") from None
    try:
        return parse_spec_text(buffer.getvalue(), source=DICT_SOURCE)
    except SpecError as err:
        raise SpecError([SpecProblem(p.path, None, None, p.key, p.reason) for p in err.errors]) from None


def _plain(value: Any) -> Any:
    """numpy arrays and scalars as lists and numbers, tuples as lists, keys as they are."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    tolist = getattr(value, "tolist", None)  # numpy arrays and scalars
    if callable(tolist) and type(value).__module__ == "numpy":
        return _plain(tolist())
    return value


def open_cube(path: str | os.PathLike[str]) -> xr.Dataset:
    """The cube at `path`, loaded into memory and checked as `fsweep info` checks it
    (friction_sweep.storage.cube.open_cube); FsweepError where it is not a regular file, not readable, not
    a friction_sweep cube, or holds values no run writes."""
    from friction_sweep.storage import cube

    return cube.open_cube(path)
