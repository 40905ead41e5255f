"""Public entry points: YAML text or file -> validated Spec, or SpecError listing every problem."""

from __future__ import annotations

import os

from pydantic import BaseModel, ValidationError
from pydantic_core import ErrorDetails

from friction_sweep.catalogue import number_text

from .errors import SpecError, SpecProblem
from .grid import FORCE_RATIO_NOTE, FREQUENCY_RATIO_NOTE, MAX_POINTS
from .load import Document, KeyPath, format_key, parse_yaml, read_text
from .model import AXIS_TAGS, ForceRange, FrequencyRange, Grid, Scene, Spec, TimeHistory, show
from .structure import (
    KEY_PROBLEM,
    Contact,
    Matrices,
    Modes,
    ScaleRange,
    Structure,
    StructureGrid,
    StructureScene,
    StructureSpec,
)
from .structure import FrequencyRange as StructureFrequencyRange
from .system import System

# Which model a mapping at a given key path is validated by, to list the keys it allows.
_MODELS: dict[KeyPath, type[BaseModel]] = {
    (): Spec,
    ("scene",): Scene,
    ("time_history",): TimeHistory,
    ("grid",): Grid,
    ("system",): System,
    ("grid", "frequency_ratio"): FrequencyRange,
    ("grid", "force_ratio"): ForceRange,
}
#: the same for a structure spec (a spec with `structure:`)
_STRUCTURE_MODELS: dict[KeyPath, type[BaseModel]] = {
    (): StructureSpec,
    ("scene",): StructureScene,
    ("structure",): Structure,
    ("structure", "contacts", "*"): Contact,
    ("structure", "matrices"): Matrices,
    ("structure", "modes"): Modes,
    ("grid",): StructureGrid,
    ("grid", "frequency"): StructureFrequencyRange,
    ("grid", "friction_scale"): ScaleRange,
}
#: the grid axes whose union tags (model.AXIS_TAGS) pydantic puts in an error's location
_TAGGED_AXES = ("frequency_ratio", "force_ratio", "frequency", "friction_scale")


def load_spec(path: str | os.PathLike[str]) -> Spec | StructureSpec:
    """Read and validate the spec file at `path`."""
    return parse_spec_text(read_text(path), source=os.fspath(path))


def parse_spec_text(text: str, source: str = "<string>") -> Spec | StructureSpec:
    """Validate spec YAML `text`; `source` names it in error messages and `spec.source_path`."""
    return spec_of_document(parse_yaml(text, source), text)


def spec_of_document(doc: Document, text: str) -> Spec | StructureSpec:
    """Validate a parsed spec; `text` is what the spec records as its own (spec.text). A spec with a
    `structure:` key is a structure spec (spec.structure), any other a 1-DoF one."""
    if not isinstance(doc.data, dict):
        got = "an empty document" if doc.data is None else f"a {type(doc.data).__name__}"
        reason = f"the spec must be a mapping of keys (got {got})"
        raise SpecError.single(doc.source, reason, line=1, column=1)
    model, models = (StructureSpec, _STRUCTURE_MODELS) if "structure" in doc.data else (Spec, _MODELS)
    try:
        spec = model.model_validate(doc.data, context={"source": doc.source})  # relative files: its folder
    except ValidationError as e:
        raise SpecError(problems_of(e, doc, models)) from None
    assert isinstance(spec, (Spec, StructureSpec))
    spec._source_path = doc.source
    spec._text = text
    return spec


def problems_of(exc: ValidationError, doc: Document,
                models: dict[KeyPath, type[BaseModel]] | None = None) -> list[SpecProblem]:
    """Each problem pydantic found in the document, located at its key (file:line:column); `models`: which
    model validates the mapping at each key path, to list the keys it allows (default: a sweep spec's)."""
    models = _MODELS if models is None else models
    problems = []
    for err in exc.errors():
        loc = err["loc"]
        # a union tag follows the axis it belongs to; a key the user named "<range>" stays a key
        path = tuple(p for i, p in enumerate(loc)
                     if not (p in AXIS_TAGS and i and loc[i - 1] in _TAGGED_AXES))
        path += tuple((err.get("ctx") or {}).get("at", ()))
        line, column = doc.locate(path, key=err["type"] in ("extra_forbidden", "unknown_key", KEY_PROBLEM))
        problems.append(SpecProblem(doc.source, line, column, format_key(path), _reason(err, path, models)))
    # File order reads best; problems without a line (missing top-level keys) go last.
    return sorted(problems, key=lambda p: (p.line is None, p.line or 0, p.column or 0))


def _reason(err: ErrorDetails, path: KeyPath, models: dict[KeyPath, type[BaseModel]]) -> str:
    kind, value, ctx = err["type"], err.get("input"), err.get("ctx") or {}
    got = f" (got {show(value)})"
    if kind == "extra_forbidden":
        model = models.get(path[:-1]) or models.get(tuple("*" if isinstance(p, int) else p for p in path[:-1]))
        allowed = f" (allowed: {', '.join(model.model_fields)})" if model else ""
        return f"unknown key {show(path[-1])}{allowed}"
    if kind == "missing":
        return f"required key {show(path[-1])} is missing"
    if kind in ("float_type", "float_parsing"):
        if isinstance(value, int) and not isinstance(value, bool):  # beyond a double's range
            return f"is too large: {show(value)} (a number holds at most about 1.8e308)"
        if isinstance(value, bool):
            return f"must be a number, not a boolean{got}"
        if isinstance(value, str):
            return f"must be a number, not a string{got}"
        return f"must be a number{got}"
    if kind in ("int_type", "int_from_float", "int_parsing"):
        if isinstance(value, bool):
            return f"must be an integer, not a boolean{got}"
        return f"must be an integer{got}"
    if kind == "finite_number":
        return f"must be a finite number{got}"
    for kind_, op, limit in (
        ("greater_than", ">", "gt"),
        ("greater_than_equal", ">=", "ge"),
        ("less_than", "<", "lt"),
        ("less_than_equal", "<=", "le"),
    ):
        if kind == kind_:
            return f"must be {op} {number_text(ctx[limit])}{got}{_range_note(path, limit)}"
    if kind == "too_short":
        return "must not be empty"
    if kind == "list_type":
        return f"must be a list{got}"
    if kind in ("dict_type", "model_type", "model_attributes_type"):
        return f"must be a mapping{got}"
    if kind == "grid_axis":
        return err["msg"] + got
    if "at" in ctx:  # our own PydanticCustomError: the message is complete
        return err["msg"]
    return f"{err['msg']}{got}"


def _range_note(path: KeyPath, limit: str) -> str:
    """Why a grid value has the bounds it has (a negative force ratio needs no explanation); an axis's
    num is a count of points, not a ratio."""
    if path and path[-1] in ("num", "step"):
        return f": an axis has at most {MAX_POINTS} points" if path[-1] == "num" and limit == "le" else ""
    if "frequency_ratio" in path:
        return f": {FREQUENCY_RATIO_NOTE}"
    if "force_ratio" in path and limit == "le":
        return f": {FORCE_RATIO_NOTE}"
    return ""
