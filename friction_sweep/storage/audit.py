"""Audit a result cube against the schema table: does every stored value lie where the schema says it can?

A cube whose bytes were damaged after writing (a flipped exponent bit, a bad disk block) still opens;
its numbers just become wrong. `audit` reads every variable and reports what no method can write:

* structure: variables the schema does not know, variables on other dims than the schema's, or
  stored with another dtype; a missing grid coordinate;
* coordinates (frequency_ratio, force_ratio): finite, inside their valid range, strictly increasing;
* integer flag variables (regime, steady_state, method_used, their `_moving` twins, history_regime):
  only their CF flag_values;
* float variables: NaN (no value) or finite and inside the variable's `valid_range`, and a whole
  number where the schema marks the variable `integral` (orbit periods).

The valid values live in one place, friction_sweep.storage.schema (`Variable.valid_range`,
`Variable.integral`, the flag_values); this module only applies them. It is pure: it prints nothing
and changes nothing, and returns a list of `Problem`s (empty for a sound cube).

`provenance` checks the global attributes a reader relies on (storage.attributes: excitation, method,
method_settings and the other JSON attributes) against the catalogue.

`together` checks pairs of a point's variables that every cube fsweep writes keeps: a simulation's settled
point has a transmissibility, and a transmissibility (a first harmonic) is at most 4/pi times the peak.

These are checks on single values and pairs. Whether the values fit together and fit the physics is
`fsweep check` (friction_sweep.consistency).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from friction_sweep.printable import escape
from friction_sweep.storage import attributes, schema


@dataclass(frozen=True)
class Problem:
    """One thing wrong with one variable of a cube.

    variable: the variable's name; what: what is wrong, in words (for value problems a predicate of
    "values", e.g. "are not valid regime codes"); count, total: how many values are wrong, of how many
    (None for structural problems); example: the first wrong value (C order); dims, index: the
    variable's dims and the example's position on them; where: the coordinates of that position, for
    the dims that have coordinates (frequency_ratio, force_ratio), as (dim, value) pairs.
    """

    variable: str
    what: str
    count: int | None = None
    total: int | None = None
    example: float | int | None = None
    dims: tuple[str, ...] = ()
    index: tuple[int, ...] = ()
    where: tuple[tuple[str, float], ...] = ()

    def __str__(self) -> str:
        """The problem in one line, names from the file escaped (friction_sweep.printable)."""
        if self.count is None:
            return escape(f"{self.variable}: {self.what}")
        text = f"{self.variable}: {self.count} of {self.total} values {self.what}"
        if self.example is not None:
            text += f" (e.g. {_number(self.example)}{_location(self)})"
        return escape(text)


#: every coordinate a cube may have: the grid's, the physical ones of a spec with a system, the scalar ones
#: (the scene's effects, the system's constants)
_COORDS = {**schema.COORDS, **schema.PHYSICAL_COORDS, **schema.SCALAR_COORDS, **schema.ARRAY_COORDS}


def provenance(ds: xr.Dataset) -> list[Problem]:
    """Every problem of the cube's provenance attributes (storage.attributes): an excitation or method outside
    the catalogue, a JSON attribute too large, too deep or not JSON, method settings not the method's; and an
    effect's scalar coordinate that is not the effect its method_settings record (a cube from before the
    scalar coordinates has none: nothing to compare)."""
    found = [Problem("provenance", what) for what in attributes.problems(ds.attrs)]
    if found:
        return found
    from friction_sweep import catalogue

    effects = attributes.method_settings(ds.attrs)["effects"]
    for name in catalogue.EFFECTS:
        if name in ds.coords and ds[name].ndim == 0:
            recorded = catalogue.effect_value(effects, name)
            value = ds[name].values.item()
            if value != recorded:
                found.append(Problem(name, f"is {value!r}; method_settings records the effect as {recorded!r}"))
    return found


#: methods that simulate an orbit: a settled point (stuck, stick_slip, continuous) always has its amplitude
SIMULATIONS = ("event", "rk4", "auto")
#: the first harmonic of a signal bounded by M is at most 4M/pi (the square wave's); relative slack for
#: sampled peaks (paper: the peak of 64 samples a period)
HARMONIC_SLACK = 1e-3


def together(ds: xr.Dataset) -> list[Problem]:
    """What no run writes between variables of a point, checked where the cube holds them (a cube whose
    values each lie in range can still pair them impossibly): a simulation's settled point without a
    transmissibility, and a transmissibility (x's first harmonic) above 4/pi times the peak |x|."""
    from friction_sweep.codes import Regime

    found: list[Problem] = []
    simulated = ds.attrs.get("method") in SIMULATIONS
    for suffix in ("", schema.MOVING_SUFFIX):
        T, regime, peak = (ds.get(name + suffix) for name in ("transmissibility", "regime", "peak_transmissibility"))
        if T is None or T.dtype.kind != "f":
            continue
        t = np.asarray(T.values, dtype=np.float64)
        if simulated and regime is not None and regime.shape == T.shape and regime.dtype.kind in "iu":
            settled = np.isin(regime.values, (Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS))
            bad = settled & np.isnan(t)
            if bad.any():
                found.append(_problem(ds, T.name, T, t, np.unravel_index(int(np.argmax(bad)), t.shape),
                                      int(bad.sum()), "are NaN at a settled regime (a simulated orbit has its "
                                      "amplitude)", False))
        if peak is not None and peak.shape == T.shape and peak.dtype.kind == "f":
            p = np.asarray(peak.values, dtype=np.float64)
            with np.errstate(invalid="ignore"):
                bad = t > (4.0 / np.pi) * (1.0 + HARMONIC_SLACK) * p
            if bad.any():
                found.append(_problem(ds, T.name, T, t, np.unravel_index(int(np.argmax(bad)), t.shape),
                                      int(bad.sum()), f"exceed 4/pi times {peak.name} (a first harmonic never "
                                      "does)", False))
    return found


def audit(ds: xr.Dataset) -> list[Problem]:
    """Every problem found in the cube `ds` (an empty list: none), in the order of its variables."""
    problems: list[Problem] = []
    # a structure cube has its own table (schema.STRUCTURE_VARIABLES), and its coordinates all
    structure = schema.is_structure(ds.attrs)
    coords, variables = ({**schema.STRUCTURE_COORDS, **schema.STRUCTURE_EXTRA_COORDS},
                         schema.STRUCTURE_VARIABLES) if structure else \
        (_COORDS, schema.VARIABLES)
    # a cube at constant base acceleration has the physical dims (schema.ACCELERATION_DIMS)
    physical_dims = not structure and set(schema.ACCELERATION_DIMS.values()) <= set(map(str, ds.dims))
    for name in schema.STRUCTURE_COORDS if structure else schema.COORDS:
        if name not in ds.variables:
            problems.append(Problem(name, "is missing: every result cube has this coordinate"))
    for key, var in ds.variables.items():
        name = str(key)
        spec = coords.get(name) if name in ds.coords else variables.get(name)
        if spec is None:
            where = "coordinate" if name in ds.coords else "variable"
            problems.append(Problem(name, f"is not a {where} of the result cube schema"))
            continue
        if spec.dtype is str:  # the names of masses or contacts
            problems.extend(_names(name, var))
            continue
        expected = schema.cube_dims(name, spec.dims, physical_dims)
        if tuple(var.dims) != expected:
            problems.append(Problem(name, f"has dims ({', '.join(map(str, var.dims))}); the schema says "
                                          f"({', '.join(expected)})"))
        if np.dtype(var.dtype) != np.dtype(spec.dtype):
            problems.append(Problem(name, f"is stored as {np.dtype(var.dtype)}; the schema says "
                                          f"{np.dtype(spec.dtype)}"))
        problems.extend(_values(ds, name, var, spec))
    return problems


def _names(name: str, var) -> list[Problem]:
    """A coordinate of names (a structure's masses or contacts): on its own dim, text, each name once."""
    if tuple(var.dims) != (name,):
        return [Problem(name, f"has dims ({', '.join(map(str, var.dims))}); the schema says ({name})")]
    values = np.asarray(var.values)
    if values.dtype.kind not in "UO" or not all(isinstance(v, str) and v for v in values.tolist()):
        return [Problem(name, "holds values that are not names")]
    if len(set(values.tolist())) != values.size:
        return [Problem(name, "names one entry twice")]
    return []


def _values(ds, name, var, spec) -> list[Problem]:
    """Value problems of one variable, each kind of fault reported once with its count."""
    values = np.asarray(var.values)
    if values.dtype.kind not in "biuf":  # strings, objects: nothing numeric to check
        return [Problem(name, f"holds {values.dtype} values, not numbers")]
    if values.dtype.kind == "f" and values.dtype.itemsize < 8:  # float16/32: compared with float64 ranges
        values = values.astype(np.float64)
    found = []
    is_coord = name in ds.coords  # every coordinate the schema knows (audit)

    def report(bad, what):
        n = int(np.count_nonzero(bad))
        if n:
            pos = np.unravel_index(int(np.argmax(bad)), values.shape) if values.ndim else ()
            found.append(_problem(ds, name, var, values, pos, n, what, is_coord))
        return n

    flags = spec.flag_values
    floating = values.dtype.kind == "f"
    if flags is not None:
        kind = name.removesuffix(schema.MOVING_SUFFIX).removeprefix("history_")
        report(~np.isin(values, np.asarray(flags)), f"are not valid {kind} codes")
        return found
    if floating:
        nan = np.isnan(values)
        if is_coord:
            report(nan, "are NaN (a grid coordinate is never NaN)")
        report(np.isinf(values), "are infinite (no method writes infinities; unbounded points are NaN)")
        finite = np.isfinite(values)
    else:
        finite = np.ones(values.shape, dtype=bool)
    if spec.valid_range is not None:
        lo, hi = spec.valid_range
        with np.errstate(invalid="ignore"):
            outside = finite & ((values < lo) | (values > hi))
        report(outside, f"lie outside the valid range {_range(lo, hi)}")
    else:
        outside = np.zeros(values.shape, dtype=bool)
    if spec.integral and floating:
        with np.errstate(invalid="ignore"):
            report(finite & ~outside & (values != np.round(values)), "are not whole numbers")
    if is_coord and values.ndim == 1 and values.size > 1 and spec.dims != (schema.HISTORY_DIM,):
        # (the time-history points, 1-DoF or structure, lie where the spec lists them, in its order)
        # among values that are numbers (a NaN is reported above, once)
        known = ~np.isnan(values) if floating else np.ones(values.shape, dtype=bool)
        with np.errstate(invalid="ignore"):
            step_bad = np.concatenate(([False], known[1:] & known[:-1] & ~(np.diff(values) > 0)))
        report(step_bad, "are not strictly increasing (each must exceed the one before it)")
    return found


def _problem(ds, name, var, values, pos, n, what, is_coord) -> Problem:
    pos = tuple(int(i) for i in pos)
    where = []
    if not is_coord:
        for dim, i in zip(var.dims, pos, strict=True):
            if dim in ds.coords and ds[dim].ndim == 1:
                where.append((dim, _scalar(ds[dim].values[i])))
    return Problem(name, what, n, int(values.size), _scalar(values[pos]), tuple(var.dims), pos, tuple(where))


def _scalar(x):
    return np.asarray(x).item()


def _number(x) -> str:
    if isinstance(x, float):
        return f"{x:.6g}"
    return str(x)


def _range(lo: float, hi: float) -> str:
    left = "(0" if lo == schema.POSITIVE[0] else f"[{lo:g}"
    right = f"{hi:g})" if np.isinf(hi) else f"{hi:g}]"
    return f"{left}, {right}"


def _location(p: Problem) -> str:
    """ " at frequency_ratio=..., force_ratio=..." ((r, beta), as points are named elsewhere), or
    " at history_point[i], sample[j]" on dims without coordinates."""
    named = dict(p.where)
    dims_text = []
    for dim, i in sorted(zip(p.dims, p.index, strict=True), key=lambda d: d[0] != "frequency_ratio"):
        if dim in named:
            value = named[dim]  # a number, or a structure cube's mass or contact name
            dims_text.append(f"{dim}={value}" if isinstance(value, str) else f"{dim}={value:.12g}")
        else:
            dims_text.append(f"{dim}[{i}]")
    return " at " + ", ".join(dims_text) if dims_text else ""


__all__ = ["Problem", "provenance", "together", "audit"]
