"""Pydantic models of a sweep spec; grid values are computed, never stored as fields."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    Discriminator,
    Field,
    PlainSerializer,
    PlainValidator,
    PrivateAttr,
    Strict,
    Tag,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from friction_sweep.catalogue import (
    DEFAULT_OUTPUTS,
    EFFECTS,
    EXCITATIONS,
    METHODS,
    OUTPUTS,
    PLACED_KEYS,
    Bounded,
    Effect,
    able,
    number_text,
)
from friction_sweep.printable import name_problem

from . import grid as g
from .base import Model as _Model
from .base import Sourced as _Sourced
from .base import problem as _error
from .base import raise_all as _raise_all
from .base import show
from .quantities import FORCE, FREQUENCY
from .system import PhysicalMap, System, physical_axis, range_problem, ratios


def _bound_problem(kind: str, bounds: Bounded, value: Any) -> str | None:
    """Why `value` is refused for a catalogued number (a setting or an effect), or None."""
    integer = isinstance(value, int) and not isinstance(value, bool)
    if isinstance(value, bool) or not (integer or (kind == "float" and isinstance(value, float))):
        return f"must be {'an integer' if kind == 'int' else 'a number'} (got {show(value)})"
    if not integer and not math.isfinite(value):
        return f"must be a finite number (got {show(value)})"
    if not bounds.contains(value):
        high = f"{number_text(bounds.high)} ({number_text(bounds.high)} excluded)" if bounds.high_open else \
            number_text(bounds.high)
        if 0.0 < value < bounds.floor:
            return f"must be 0 or at least {number_text(bounds.floor)} (got {show(value)}): {bounds.why}"
        return f"must be between {number_text(bounds.low)} and {high} (got {show(value)}): {bounds.why}"
    return None


#: stored time-history samples per variable at most (16 MB of float64 each, 8 variables)
MAX_HISTORY_SAMPLES = 2_000_000

# Union tags appear in pydantic's error locations; the angle brackets keep them apart from YAML keys.
AXIS_TAGS = frozenset({"<number>", "<list>", "<range>", "<array>"})

Finite = Annotated[float, Strict(), Field(allow_inf_nan=False)]
Positive = Annotated[float, Strict(), Field(allow_inf_nan=False, gt=0)]
NonNegative = Annotated[float, Strict(), Field(allow_inf_nan=False, ge=0)]
FrequencyRatio = Annotated[float, Strict(), Field(allow_inf_nan=False, ge=g.FREQUENCY_RATIO_RANGE[0],
                                                  le=g.FREQUENCY_RATIO_RANGE[1])]


def _zero_or_resolved(beta: float) -> float:
    if 0 < beta < g.FORCE_RATIO_MIN_POSITIVE:
        raise _error("force_ratio_tiny", f"must be 0 or at least {g.FORCE_RATIO_MIN_POSITIVE:g} (got {show(beta)}): "
                     "so little friction dissipates below rounding, and the motion from rest never settles")
    return beta


ForceRatio = Annotated[float, Strict(), Field(allow_inf_nan=False, ge=0, le=g.FORCE_RATIO_MAX),
                       AfterValidator(_zero_or_resolved)]


class _Range(_Model):
    start: Finite
    stop: Finite
    num: Annotated[int, Strict(), Field(ge=1, le=g.MAX_POINTS)] | None = None
    step: Positive | None = None

    @field_validator("stop")
    @classmethod
    def _stop_not_below_start(cls, stop: float, info: ValidationInfo) -> float:
        start = info.data.get("start")
        if start is not None and stop < start:
            raise _error("stop_below_start", f"must be >= start ({show(start)}) (got {show(stop)})")
        return stop

    @model_validator(mode="after")
    def _one_of_num_step(self):
        if (self.num is None) == (self.step is None):
            given = "both" if self.num is not None else "neither"
            raise _error("num_or_step", f"give exactly one of 'num' or 'step' (got {given})")
        if self.num == 1 and self.start != self.stop:
            raise _error(
                "num_one",
                f"num = 1 needs start == stop (got start {show(self.start)}, stop {show(self.stop)})",
                ("num",),
            )
        if self.step is not None and self.size > g.MAX_POINTS:
            raise _error("too_many_points", f"step gives more than {g.MAX_POINTS} points", ("step",))
        return self

    @property
    def size(self) -> int:
        if self.num is not None:
            return self.num
        assert self.step is not None  # _one_of_num_step
        return g.step_count(self.start, self.stop, self.step)[0]

    def values(self) -> np.ndarray:
        if self.num is not None:
            return g.linspace_values(self.start, self.stop, self.num)
        assert self.step is not None  # _one_of_num_step
        return g.step_values(self.start, self.stop, self.step)


class FrequencyRange(_Range):
    start: FrequencyRatio
    stop: FrequencyRatio


class ForceRange(_Range):
    start: ForceRatio
    stop: ForceRatio


def _increasing(values: list[float]) -> list[float]:
    for i in range(1, len(values)):
        if values[i] <= values[i - 1]:
            what = "duplicate value" if values[i] == values[i - 1] else "not sorted"
            raise _error(
                "not_increasing",
                f"values must be strictly increasing: {what} "
                f"{show(values[i])} after {show(values[i - 1])}",
                (i,),
            )
    return values


def _axis_kind(v: Any) -> str | None:
    if isinstance(v, np.ndarray):  # the Python API's arrays (api.spec_of_dict), checked as a whole
        return "<array>"
    if isinstance(v, (dict, _Range)):  # a model instance when serialising
        return "<range>"
    if isinstance(v, list):
        return "<list>"
    if isinstance(v, (int, float, str)):  # strings and booleans get a "must be a number" error
        return "<number>"
    return None


def _array_axis(ok: Callable[[np.ndarray], np.ndarray], span: str, note: str) -> Callable[[np.ndarray], np.ndarray]:
    """The validator of an axis given as a numpy array: the rules of a list of numbers (finite, within
    `span`, strictly increasing), applied to the whole array at once, the first offending item reported
    with how many more; the values as float64 (a longdouble beyond a double's range is infinite)."""

    def check(v: np.ndarray) -> np.ndarray:
        if v.dtype.kind not in "iuf":
            raise _error("array_dtype", f"must be an array of numbers (got an array of dtype {v.dtype})")
        if v.ndim != 1:
            raise _error("array_shape", f"must be a 1-D array of numbers (got shape {v.shape})")
        if v.size == 0:
            raise _error("array_empty", "must not be empty")
        with np.errstate(over="ignore", invalid="ignore"):
            values = v.astype(np.float64)
        bad = np.flatnonzero(~(np.isfinite(values) & ok(values)))
        if bad.size:
            i, more = int(bad[0]), f" ({bad.size - 1} more)" if bad.size > 1 else ""
            got = f"(got {show(values[i].item())})"
            raise _error("array_range", f"must be a finite number {got}" if not np.isfinite(values[i]) else
                         f"must be {span} {got}{more}: {note}", (i,))
        j = g.first_not_increasing(values)
        if j is not None:
            what = "duplicate value" if values[j] == values[j - 1] else "not sorted"
            raise _error("not_increasing", f"values must be strictly increasing: {what} {show(values[j].item())} "
                         f"after {show(values[j - 1].item())}", (j,))
        values.flags.writeable = False
        return values

    return check


def _axis(element: Any, range_model: type[_Range], array: Callable[[np.ndarray], np.ndarray]) -> Any:
    return Annotated[
        Annotated[element, Tag("<number>")]
        | Annotated[list[element], Field(min_length=1), AfterValidator(_increasing), Tag("<list>")]
        | Annotated[range_model, Tag("<range>")]
        | Annotated[Any, PlainValidator(array), PlainSerializer(lambda a: a.tolist()), Tag("<array>")],
        Discriminator(
            _axis_kind,
            custom_error_type="grid_axis",
            custom_error_message="must be a number, a list of numbers, "
            "or a mapping with start, stop and one of num or step",
        ),
    ]


if TYPE_CHECKING:  # what pydantic builds from _axis, as a type checker can read it
    FrequencyAxis = float | list[float] | np.ndarray | FrequencyRange
    ForceAxis = float | list[float] | np.ndarray | ForceRange
else:
    FrequencyAxis = _axis(FrequencyRatio, FrequencyRange,
                          _array_axis(g.frequency_ratio_ok, g.FREQUENCY_RATIO_SPAN, g.FREQUENCY_RATIO_NOTE))
    ForceAxis = _axis(ForceRatio, ForceRange, _array_axis(g.force_ratio_ok, g.FORCE_RATIO_SPAN, g.FORCE_RATIO_NOTE))


def _axis_size(axis: float | list[float] | np.ndarray | _Range) -> int:
    if isinstance(axis, _Range):
        return axis.size
    return len(axis) if isinstance(axis, (list, np.ndarray)) else 1


def _axis_values(axis: float | list[float] | np.ndarray | _Range) -> np.ndarray:
    if isinstance(axis, _Range):
        return axis.values()
    return np.atleast_1d(np.asarray(axis, dtype=np.float64)).copy()


class Grid(_Model):
    """The grid: one frequency axis (frequency_ratio, or frequency in a unit of frequency) and at most one
    force axis (force_ratio, or friction_force in a unit of force; absent: the system's one friction)."""

    frequency_ratio: FrequencyAxis | None = None
    force_ratio: ForceAxis | None = None
    #: physical axes, in Hz and N (spec.system.physical_axis); the spec maps them onto (r, beta)
    frequency: tuple[float, ...] | None = None
    friction_force: tuple[float, ...] | None = None
    _values: dict[str, np.ndarray] = PrivateAttr(default_factory=dict)

    @model_validator(mode="before")
    @classmethod
    def _no_null_axis(cls, data: Any) -> Any:
        # `frequency_ratio:` left empty, with no other axis of its kind, is a mistake, not an axis left out
        if isinstance(data, dict):
            _raise_all("grid", [_error("grid_axis", "must be a number, a list of numbers, or a mapping with start, "
                                       "stop and one of num or step (got null)", (name,))
                                for name, other in (("frequency_ratio", "frequency"), ("force_ratio", "friction_force"))
                                if name in data and data[name] is None and data.get(other) is None])
        return data

    @field_validator("frequency", mode="before")
    @classmethod
    def _frequency_axis(cls, v: Any) -> Any:
        return v if v is None else physical_axis(v, FREQUENCY)

    @field_validator("friction_force", mode="before")
    @classmethod
    def _friction_axis(cls, v: Any) -> Any:
        return v if v is None else physical_axis(v, FORCE)

    @model_validator(mode="after")
    def _build(self):
        problems = []
        if (self.frequency_ratio is None) == (self.frequency is None):
            both = self.frequency is not None
            problems.append(_error("frequency_axis", "give one frequency axis: frequency_ratio, or frequency "
                                   f"with the system's natural frequency (got {'both' if both else 'neither'})",
                                   ("frequency" if both else "frequency_ratio",)))
        if self.force_ratio is not None and self.friction_force is not None:
            problems.append(_error("force_axis", "give one force axis: force_ratio or friction_force (got both)",
                                   ("friction_force",)))
        _raise_all("grid", problems)
        nf = _axis_size(self.frequency_ratio) if self.frequency is None else len(self.frequency)
        nb = (_axis_size(self.force_ratio) if self.force_ratio is not None else
              len(self.friction_force) if self.friction_force is not None else 1)
        if nf * nb > g.MAX_POINTS:
            raise _error(
                "too_many_points",
                f"grid has {nf * nb} points ({nf} x {nb}); at most {g.MAX_POINTS} are allowed",
            )
        for name in ("frequency_ratio", "force_ratio"):
            axis = getattr(self, name)
            if axis is None:
                continue
            values = _axis_values(axis)
            if isinstance(axis, _Range) and (
                g.first_not_increasing(values) is not None or values[-1] > axis.stop
            ):
                raise _error(
                    "grid_too_fine",
                    f"spacing is finer than {g.SIGNIFICANT_DIGITS} significant digits: values collide",
                    (name,),
                )
            self._values[name] = values
        return self

    def values(self, name: str) -> np.ndarray | None:
        """A dimensionless axis's values (read-only), or None where the grid gives it physically."""
        values = self._values.get(name)
        if values is not None:
            values.flags.writeable = False  # shared by every reader; also re-set after unpickling
        return values


class Scene(_Model):
    excitation: str
    #: the effects the spec names and their values (absent: off): a number, or {ratio, to} for an effect
    #: given with its place (catalogue.EffectValue)
    effects: dict[str, float | dict[str, float | str]] = Field(default_factory=dict)

    @field_validator("excitation", mode="before")
    @classmethod
    def _known_excitation(cls, v: Any) -> Any:
        if not isinstance(v, str) or v not in EXCITATIONS:
            raise _error(
                "unknown_excitation",
                f"unknown excitation {show(v)} (expected one of: {', '.join(EXCITATIONS)})",
            )
        return v

    @field_validator("effects", mode="before")
    @classmethod
    def _known_effects(cls, v: Any, info: ValidationInfo) -> Any:
        if v is None:  # `effects:` left empty
            return {}
        if not isinstance(v, dict):
            raise _error("effects_type", f"must be a mapping of effect names to values (got {show(v)})")
        v = {key: value for key, value in v.items() if value is not None}  # `name:` left empty: off
        excitation = info.data.get("excitation")  # None where the excitation itself is refused
        problems = []
        for key, value in v.items():
            effect = EFFECTS.get(key) if isinstance(key, str) else None
            if effect is None:
                problems.append(_error("unknown_effect", f"unknown effect {show(key)} (known: {', '.join(EFFECTS)})",
                                       (key,)))
            elif effect.places and isinstance(value, dict):
                problems.extend(_placed_problems(key, effect, value, excitation))
            elif (reason := _bound_problem("float", effect, value)) is not None:
                if effect.places and not isinstance(value, (int, float)):
                    reason = (f"must be a number or {{ratio: number, to: {' | '.join(effect.place_names())}}} "
                              f"(got {show(value)})")
                problems.append(_error("effect_range", reason, (key,)))
        _raise_all("effects", problems)
        return {k: ({"ratio": float(x["ratio"]), "to": x["to"]} if isinstance(x, dict) else float(x))
                for k, x in v.items()}


def _placed_problems(name: str, effect: Effect, value: dict, excitation: str | None) -> list[PydanticCustomError]:
    """What is wrong with an effect given with its place, `{ratio: number, to: place}`."""
    problems = [_error("unknown_key", f"unknown key {show(key)} (allowed: {', '.join(PLACED_KEYS)})", (name, key))
                for key in value if key not in PLACED_KEYS]
    for key in PLACED_KEYS:
        if key not in value:
            problems.append(_error("missing_key", f"required key {key!r} is missing (give {{ratio: number, to: "
                                   f"{' | '.join(effect.place_names())}}}, or a bare number)", (name,)))
    if "ratio" in value and (reason := _bound_problem("float", effect, value["ratio"])) is not None:
        problems.append(_error("effect_range", reason, (name, "ratio")))
    if "to" in value:
        to = value["to"]
        if not isinstance(to, str) or to not in effect.place_names():
            problems.append(_error("effect_place", f"must be one of: {', '.join(effect.place_names())} "
                                   f"(got {show(to)})", (name, "to")))
        elif excitation is not None and to not in effect.places[excitation]:
            allowed = effect.places[excitation]
            problems.append(_error("effect_place", f"excitation {excitation!r} allows only "
                                   + " or ".join(f"to: {p} ({why})" for p, why in allowed.items())
                                   + f" (got {show(to)})", (name, "to")))
    return problems


#: a time_history: section's fields (1-DoF and structure specs): its points, pairs of numbers, and the samples
#: a forcing period
HistoryPoints = Annotated[list[Annotated[list[Finite], Field(min_length=2, max_length=2)]],
                          Field(min_length=1, max_length=1000)]
SamplesPerPeriod = Annotated[int, Strict(), Field(ge=8, le=100_000)]


class TimeHistory(_Model):
    """Points whose steady-state orbits are stored (outputs: time_history)."""

    points: HistoryPoints
    samples_per_period: SamplesPerPeriod = 256

    @field_validator("points")
    @classmethod
    def _on_the_grid_range(cls, v):
        problems = []
        for i, (r, beta) in enumerate(v):
            if not g.frequency_ratio_ok(r):
                problems.append(_error("history_r", f"frequency ratio must be {g.FREQUENCY_RATIO_SPAN} "
                                       f"(got {show(r)})", (i, 0)))
            if not g.force_ratio_ok(beta):
                problems.append(_error("history_beta", f"force ratio must be {g.FORCE_RATIO_SPAN} "
                                       f"(got {show(beta)})", (i, 1)))
        _raise_all("points", problems)
        return v

    @model_validator(mode="after")
    def _bounded_memory(self):
        if len(self.points) * self.samples_per_period > MAX_HISTORY_SAMPLES:
            raise _error("history_size", f"{len(self.points)} points x {self.samples_per_period} samples per "
                         f"period exceeds {MAX_HISTORY_SAMPLES} samples per variable", ("samples_per_period",))
        return self


def sweep_and_starts():
    """The problem of a swept spec that sets `starts` (1-DoF and structure specs alike)."""
    return _error("sweep_and_starts", "a swept run starts each point from its neighbour's orbit: settings.starts "
                  "does not apply", ("settings", "starts"))


class Sweep(_Model):
    """A stepped-sine sweep along frequency_ratio, as rigs are run: each point starts from the orbit
    its neighbour settled on (up: from the next lower frequency ratio; down: from the next higher)."""

    direction: Literal["up", "down"]


class Spec(_Sourced):
    """A validated sweep spec. Grid values: `frequency_ratio`, `force_ratio` (read-only float64)."""

    scene: Scene
    grid: Grid
    system: System | None = None
    method: str = "theory"
    outputs: tuple[str, ...] = DEFAULT_OUTPUTS
    time_history: TimeHistory | None = None
    output: str | None = None
    settings: dict[str, Any] = Field(default_factory=dict)
    accuracy: Annotated[float, Strict(), Field(allow_inf_nan=False, gt=0, lt=1)] | None = None
    sweep: Sweep | None = None
    _ratios: dict[str, np.ndarray] = PrivateAttr(default_factory=dict)
    _physical: PhysicalMap | None = PrivateAttr(default=None)

    @field_validator("method", mode="before")
    @classmethod
    def _method_available(cls, v: Any) -> Any:
        if not isinstance(v, str):
            raise _error("method_type", f"must be a method name (got {show(v)})")
        if v not in METHODS:
            raise _error("unknown_method", f"unknown method {show(v)} (available: {', '.join(METHODS)})")
        return v

    @field_validator("outputs", mode="before")
    @classmethod
    def _outputs_canonical(cls, v: Any) -> Any:
        if not isinstance(v, (list, tuple)):
            raise _error("outputs_type", f"must be a list of output names (got {show(v)})")
        if not v:
            raise _error("outputs_empty", f"must not be empty (choose from: {', '.join(OUTPUTS)})")
        for i, name in enumerate(v):
            if not isinstance(name, str) or name not in OUTPUTS:
                raise _error(
                    "unknown_output", f"unknown output {show(name)} (known: {', '.join(OUTPUTS)})", (i,)
                )
            if name in v[:i]:
                raise _error("duplicate_output", f"output {name!r} is listed twice", (i,))
        return tuple(sorted(v, key=OUTPUTS.index))

    @field_validator("output", mode="before")
    @classmethod
    def _output_path(cls, v: Any) -> Any:
        return checked_output_path(v)

    @field_validator("settings")
    @classmethod
    def _settings_in_range(cls, settings: dict[str, Any], info: ValidationInfo) -> dict[str, Any]:
        method = info.data.get("method")
        if method is None:  # the method itself is wrong: reported there
            return settings
        problems = setting_problems(method, settings)
        # field-level locations get the field name prepended by pydantic: give `at` relative to it
        _raise_all("settings", [PydanticCustomError(e.type, e.message(), {"at": (e.context or {})["at"][1:]})
                                for e in problems])
        return settings

    @model_validator(mode="after")
    def _consistent(self):
        """Every rule that ties fields together, all reported at once."""
        _raise_all("Spec", [*self._excitation_problems(), *self._output_problems(), *self._history_problems(),
                            *self._harmonic_problems(),
                            *self._sweep_problems(), *self._accuracy_problems(), *self._effect_problems(),
                            *self._map_system()])
        return self

    def _map_system(self) -> list[PydanticCustomError]:
        """Map the grid onto (r, beta) through the system (docs/equations.md §1), storing both."""
        grid, system, problems = self.grid, self.system, []
        if system is None:
            problems += [_error("system_missing", "a physical axis needs the system it is measured on: give "
                                "`system:` with the natural frequency and the excitation's force", ("grid", name))
                         for name in ("frequency", "friction_force") if getattr(grid, name) is not None]
            system = System()
        f_n, force, friction = system.natural_frequency_si, system.reference_force, system.friction
        acceleration = system.base_acceleration
        for name in ("base_amplitude", "base_acceleration"):
            if self.scene.excitation == "force" and getattr(system, name) is not None:
                problems.append(_error("amplitude_force", "a force excitation's amplitude is a force: give "
                                       "excitation_force (F0)", ("system", name)))
        friction_key = ("system", "friction_force" if system.friction_force is not None else "friction_coefficient")
        r = grid.values("frequency_ratio")
        frequency = None if r is None or f_n is None else r * f_n
        if grid.frequency is not None and self.system is not None:
            if f_n is None:
                problems.append(_error("needs_natural_frequency", "a frequency axis needs the natural frequency: "
                                       "give system.natural_frequency (or mass and stiffness)", ("grid", "frequency")))
            else:
                frequency = np.asarray(grid.frequency)
                r = ratios(frequency, f_n)
                problems += _mapped_problems(r, frequency, "Hz", f"r = f / f_n at f_n = {f_n:.6g} Hz",
                                             g.frequency_ratio_ok, g.FREQUENCY_RATIO_SPAN, ("grid", "frequency"))
        beta = grid.values("force_ratio")
        friction_force = None if beta is None or force is None else beta * force
        physical = np.asarray(grid.friction_force) if grid.friction_force is not None else \
            np.array([friction]) if beta is None and friction is not None else None
        if friction is not None and beta is not None:
            problems.append(_error("two_frictions", "grid.force_ratio sweeps the friction: give it in one place",
                                   friction_key))
        elif friction is not None and grid.friction_force is not None:
            problems.append(_error("two_frictions", "grid.friction_force sweeps the friction: give it in one "
                                   "place", friction_key))
        elif beta is None and physical is None:
            problems.append(_error("force_axis", "give a force axis (force_ratio, or friction_force with the "
                                   "system), or the friction in system.friction_force", ("grid",)))
        elif acceleration is not None and beta is not None:
            problems.append(_error("acceleration_force_ratio", "with system.base_acceleration the force ratio "
                                   "grows with f^2 along the sweep: give the friction in newtons (grid.friction_force "
                                   "or system.friction_force)", ("grid", "force_ratio")))
        elif acceleration is not None and physical is not None:
            where = ("grid", "friction_force") if grid.friction_force is not None else friction_key
            if frequency is not None and system.stiffness_si is not None:
                friction_force = physical
                force_at = system.stiffness_si * acceleration / (2.0 * np.pi * frequency) ** 2
                beta = g.round_significant((physical[:, None] / force_at[None, :]).ravel()).reshape(
                    physical.size, frequency.size)
                problems += _accelerated_problems(beta, physical, frequency, force_at, where)
            if self.sweep is not None:
                problems.append(_error("acceleration_sweep", "a stepped-sine sweep at constant acceleration is not "
                                       "supported: the force ratio changes from one frequency to the next",
                                       ("sweep",)))
        elif physical is not None and self.system is not None:
            where = ("grid", "friction_force") if grid.friction_force is not None else friction_key
            if force is None:
                problems.append(_error("needs_force", "a friction force needs the excitation's force to compare "
                                       "with: give system.excitation_force (or base_amplitude and stiffness)", where))
            else:
                friction_force, beta = physical, ratios(physical, force)
                problems += _mapped_problems(beta, physical, "N", f"beta = F_mu / F_k at F_k = {force:.6g} N",
                                             g.force_ratio_ok, g.FORCE_RATIO_SPAN, where)
        if not problems and self.system is not None:  # what the grid derives through the system
            history = None if self.time_history is None or f_n is None else \
                np.array([r_ for r_, _ in self.time_history.points]) * f_n
            scales = [("the frequency f = r f_n", frequency, "Hz", ("grid", "frequency_ratio")),
                      ("the friction force F_mu = beta F_k", friction_force, "N", ("grid", "force_ratio")),
                      ("the frequency f = r f_n of a time-history point", history, "Hz", ("time_history", "points"))]
            if acceleration is not None and frequency is not None:
                length_at = acceleration / (2.0 * np.pi * np.asarray(frequency)) ** 2
                force_at = None if system.stiffness_si is None else system.stiffness_si * length_at
                at = ("system", "base_acceleration")
                scales += [("the base's amplitude Y = a / omega^2", length_at, "m", at),
                           ("the excitation force F_k = k a / omega^2", force_at, "N", at),
                           ("the energy scale F_k Y", None if force_at is None else force_at * length_at, "J", at)]
            problems += [p for what, values, unit, at in scales if values is not None
                         and (p := range_problem(what, values, unit, at)) is not None]
        if problems:
            return problems
        assert r is not None and beta is not None  # every way to leave one out is a problem above
        self._ratios = {"frequency_ratio": r, "force_ratio": beta}
        if self.system is not None:
            self._physical = PhysicalMap(natural_frequency=f_n, reference_force=force,
                                         length_scale=system.length_scale, stiffness=system.stiffness_si,
                                         frequency=frequency, friction_force=friction_force, acceleration=acceleration,
                                         mass=system.mass_si)
        return []

    def _excitation_problems(self):
        excitation = self.scene.excitation
        if excitation not in METHODS[self.method].excitations:
            yield _error("excitation_method", f"method {self.method!r} does not simulate excitation "
                         f"{excitation!r} (methods that do: {', '.join(able(excitation))})", ("scene", "excitation"))

    def _output_problems(self):
        for name in self.outputs:
            if name not in METHODS[self.method].outputs:
                yield _error("output_method", f"method {self.method!r} cannot write output {name!r} "
                             f"(methods that can: {', '.join(able(name))})", ("outputs",))

    def _history_problems(self):
        wanted = "time_history" in self.outputs
        if wanted and self.time_history is None:
            yield _error("history_missing", "outputs lists time_history: give `time_history: {points: [[r, beta], "
                         "...]}`", ("outputs",))
        if not wanted and self.time_history is not None:
            yield _error("history_unused", "time_history is given but not listed in outputs", ("time_history",))

    def _harmonic_problems(self):
        """The output `harmonics` (settings.harmonics: its highest harmonic H): a plane of H + 1 values per grid
        point, not for a swept run."""
        wanted = "harmonics" in self.outputs
        if not wanted and "harmonics" in self.settings:
            yield _error("harmonics_unused", "given, but harmonics is not listed in outputs",
                         ("settings", "harmonics"))
        if not wanted:
            return
        if self.sweep is not None:
            yield _error("harmonics_sweep", "a swept run does not store harmonics: run the grid without sweep",
                         ("sweep",))
        H = self.settings.get("harmonics", METHODS[self.method].defaults.get("harmonics", 0))
        r, beta = self.grid.values("frequency_ratio"), self.grid.values("force_ratio")
        if isinstance(H, int) and r is not None and beta is not None and r.size * beta.size * (H + 1) > g.MAX_POINTS:
            yield _error("harmonics_size", f"{r.size * beta.size} grid points x {H + 1} harmonics exceeds "
                         f"{g.MAX_POINTS} values per variable", ("settings", "harmonics") if "harmonics" in
                         self.settings else ("outputs",))

    def _sweep_problems(self):
        if self.sweep is None:
            return
        if not METHODS[self.method].sweep:
            yield _error("sweep_method", f"method {self.method!r} cannot run a swept sweep "
                         f"(methods that can: {', '.join(able('sweep'))})", ("sweep",))
        if self.time_history is not None:
            yield _error("sweep_and_history", "a swept run's time histories would not follow the sweep: "
                         "store them from a run without sweep", ("sweep",))
        if "starts" in self.settings:
            yield sweep_and_starts()

    def _accuracy_problems(self):
        if self.accuracy is None:
            return
        chosen = METHODS[self.method].accuracy_knobs
        if not chosen:
            yield _error("accuracy_method", f"method {self.method!r} has no calibrated settings "
                         f"(accuracy works with: {', '.join(able('accuracy'))})", ("accuracy",))
        knobs = sorted(set(self.settings) & set(chosen))
        if knobs:
            yield _error("accuracy_and_knobs", f"give either accuracy or the knobs it sets, not both "
                         f"(settings also has {', '.join(knobs)})", ("accuracy",))

    def _effect_problems(self):
        for name in self.scene.effects:
            if name not in METHODS[self.method].effects:
                yield _error("effect_unsupported", f"method {self.method!r} does not model {name} "
                             f"(methods that do: {', '.join(able(name))})", ("scene", "effects", name))

    @property
    def frequency_ratio(self) -> np.ndarray:
        return self._read_only("frequency_ratio")

    @property
    def force_ratio(self) -> np.ndarray:
        """The force ratios: one per force-axis value, or at constant base acceleration one per point
        (friction force x frequency), as beta grows with f^2."""
        return self._read_only("force_ratio")

    @property
    def force_count(self) -> int:
        """Points along the force axis."""
        return int(self.force_ratio.shape[0])

    def _read_only(self, name: str) -> np.ndarray:
        values = self._ratios[name]
        values.flags.writeable = False  # shared by every reader; also re-set after unpickling
        return values

    @property
    def physical(self) -> PhysicalMap | None:
        """The physical values beside (r, beta), where the spec has a `system:`."""
        return self._physical


def checked_output_path(v: Any) -> Any:
    """A spec's `output:` as given, or a problem: it must name a file fsweep may write."""
    if v is not None and (not isinstance(v, str) or not v.strip()):
        raise _error("output_path", f"must be a non-empty file path (got {show(v)})")
    problem = name_problem(v) if isinstance(v, str) else None
    if problem is not None:  # the one rule for names (storage.outputs), said as the spec is read
        raise _error("output_path", f"{show(v)} {problem}")
    if isinstance(v, str) and v.endswith("/"):
        raise _error("output_path", f"names a folder: name the file to write (got {show(v)})")
    return v


def setting_problems(method: str, settings: dict[str, Any]) -> list[PydanticCustomError]:
    """Settings the method does not have, and values outside their meaningful range (catalogue), each
    located at ("settings", key)."""
    known = METHODS[method].settings
    problems = []
    for key, value in settings.items():
        if key not in known:
            allowed = ", ".join(known) or "none"
            problems.append(_error("unknown_setting", f"unknown setting {show(key)} for method {method!r} "
                                   f"(allowed: {allowed})", ("settings", key)))
        elif (reason := _bound_problem(known[key].kind, known[key], value)) is not None:
            problems.append(_error("setting_range", reason, ("settings", key)))
    return problems


def _mapped_problems(ratio: np.ndarray, physical: np.ndarray, unit: str, rule: str, ok, span: str,
                     at: tuple) -> list[PydanticCustomError]:
    """A physical axis whose ratios leave their range or collide at 12 significant digits."""
    bad = [i for i, x in enumerate(ratio.tolist()) if not ok(x)]
    if bad:
        i = bad[0]
        more = f" ({len(bad) - 1} more)" if len(bad) > 1 else ""
        return [_error("mapped_range", f"{physical[i]:.6g} {unit} is {rule.split(' =')[0]} = {ratio[i]:.6g} "
                       f"({rule}); it must be {span}{more}", at)]
    j = g.first_not_increasing(ratio)
    if j is not None:
        return [_error("mapped_collide", f"{physical[j - 1]:.12g} {unit} and {physical[j]:.12g} {unit} give the same "
                       f"ratio at {g.SIGNIFICANT_DIGITS} significant digits ({ratio[j]:.12g})", at)]
    return []


def _accelerated_problems(beta: np.ndarray, friction: np.ndarray, frequency: np.ndarray, force_at: np.ndarray,
                          at: tuple) -> list[PydanticCustomError]:
    """A constant-acceleration grid whose force ratios (friction x frequency) leave their range or collide."""
    bad = np.argwhere(~np.vectorize(g.force_ratio_ok)(beta))
    if bad.size:
        j, i = bad[0]
        more = f" ({len(bad) - 1} more)" if len(bad) > 1 else ""
        return [_error("mapped_range", f"{friction[j]:.6g} N at {frequency[i]:.6g} Hz is beta = {beta[j, i]:.6g} "
                       f"(beta = F_mu / F_k, F_k = k a / omega^2 = {force_at[i]:.6g} N there); it must be "
                       f"{g.FORCE_RATIO_SPAN}{more}", at)]
    collide = np.argwhere(np.diff(beta, axis=0) <= 0)
    if collide.size:
        j, i = collide[0]
        return [_error("mapped_collide", f"{friction[j]:.12g} N and {friction[j + 1]:.12g} N give the same ratio at "
                       f"{frequency[i]:.6g} Hz at {g.SIGNIFICANT_DIGITS} significant digits ({beta[j, i]:.12g})", at)]
    return []
