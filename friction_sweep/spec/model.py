"""Pydantic models of a sweep spec; grid values are computed, never stored as fields."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    PrivateAttr,
    Strict,
    Tag,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from . import grid as g

EXCITATIONS = ("force", "base", "joined")
METHODS_AVAILABLE = ("theory", "event", "rk4", "paper", "auto")
OUTPUTS = ("transmissibility", "phase", "regime", "time_history")
DEFAULT_OUTPUTS = ("transmissibility", "phase", "regime")
EFFECTS: tuple[str, ...] = ("viscous_damping", "static_friction_ratio")

#: methods whose settings `accuracy:` can choose from the benchmark's calibration, and the knobs it sets
ACCURACY_METHODS = ("event", "rk4", "auto")
ACCURACY_KNOBS = {"stop_tol", "steady_tol", "steps_per_period"}
#: methods that can store steady-state time histories
HISTORY_METHODS = ("event", "auto")
#: methods that can run a stepped-sine sweep (each point started from its neighbour's orbit)
SWEEP_METHODS = ("event", "rk4")
#: which physical effects each method models (a spec asking for more is refused)
METHOD_EFFECTS = {"theory": (), "event": EFFECTS, "rk4": EFFECTS, "paper": (), "auto": ()}


@dataclass(frozen=True)
class Setting:
    """One accuracy or budget knob of a method (`settings:` in a spec) and its meaningful range.

    Values outside [low, high] are refused: inside it every value gives a right answer or an honest
    label (`unsettled`), at a cost the run's estimate covers; `why` says what the bounds protect.
    """

    kind: Literal["int", "float"]
    low: float
    high: float
    why: str

    def check(self, value: Any) -> str | None:
        """Why `value` is refused, or None."""
        integer = isinstance(value, int) and not isinstance(value, bool)
        if isinstance(value, bool) or not (integer or (self.kind == "float" and isinstance(value, float))):
            return f"must be {'an integer' if self.kind == 'int' else 'a number'} (got {show(value)})"
        if not integer and not math.isfinite(value):
            return f"must be a finite number (got {show(value)})"
        if not self.low <= value <= self.high:
            return f"must be between {_number(self.low)} and {_number(self.high)} (got {show(value)}): {self.why}"
        return None

    def describe(self) -> str:
        return f"[{_number(self.low)}, {_number(self.high)}]"


# Bounds measured on grids of 77 r x 30 beta against the defaults (closing note of issue 14): inside
# them every value labels every point right or honestly (`unsettled`), at a cost the estimate bounds.
_STEADY = {
    "steady_tol": Setting("float", 1e-13, 1e-6, "the relative change per period below which the map has "
                          "settled: looser mislabels slow transients near the stick-slip limit, tighter than "
                          "rounding finds false period-2 orbits"),
    "stop_tol": Setting("float", 1e-15, 1e-10, "a stop is |v| <= stop_tol x the state's size: looser misplaces "
                        "stops (r = 1 goes unsettled from 1e-9), tighter than rounding never finds them"),
    "max_periods": Setting("int", 1, 100_000, "forcing periods marched per point at most (cost grows with it)"),
    "max_orbit_period": Setting("int", 1, 1024, "longest period-k orbit looked for (each period's cost grows "
                                "with it)"),
    "work_budget": Setting("int", 1, 10**8, "stop searches and events per point at most: 0.1-0.3 us each, so "
                           "at most about 30 s a point"),
    "shoot_after": Setting("int", 1, 1_000_000, "periods marched before the first shooting attempt"),
    "shoot_every": Setting("int", 1, 1_000_000, "periods between shooting attempts"),
    "initial_displacement": Setting("float", -2.0, 2.0, "start of the march, in the equation's length unit: "
                                    "farther starts settle on wrong or no orbits within the budget"),
    "initial_velocity": Setting("float", -2.0, 2.0, "start of the march, in the equation's velocity unit: "
                                "farther starts settle on wrong or no orbits within the budget"),
}
#: each method's accuracy and budget knobs (`settings:` in a spec) and their meaningful ranges
METHOD_SETTINGS: dict[str, dict[str, Setting]] = {
    "theory": {},
    "event": {**_STEADY, "starts": Setting("int", 1, 2, "1: from rest only; 2: also from a moving start")},
    "auto": {**_STEADY, "theory_margin": Setting("float", 1e-6, 1.0, "relative distance from the theory's "
                                                 "continuous limit inside which the simulation decides")},
    "rk4": {**{k: v for k, v in _STEADY.items() if k != "stop_tol"},
            "starts": Setting("int", 1, 2, "1: from rest only; 2: also from a moving start"),
            "steps_per_period": Setting("int", 256, 100_000, "fixed RK4 steps per forcing period: fewer give "
                                        "errors above 1e-4 (84 % at 16) and false resonances; cost grows with it")},
    "paper": {
        # a point holds periods x samples_per_period samples: at most 10^7 (80 MB) with these bounds
        "periods": Setting("int", 20, 10_000, "forcing periods simulated from rest: fewer leave the transient "
                           "in the measurement (cost grows with it)"),
        "samples_per_period": Setting("int", 16, 1000, "output samples per forcing period: more count a "
                                      "smooth point's samples as stops; memory grows with it"),
        "transient_fraction": Setting("float", 0.0, 0.9, "share of the periods discarded as transient; at "
                                      "least a tenth is kept to measure"),
        "rtol": Setting("float", 1e-10, 1e-3, "ode45's relative tolerance: looser errs by tens of percent, "
                        "tighter than 1e-10 costs hours a point"),
        "atol": Setting("float", 1e-12, 1e-6, "ode45's absolute tolerance: looser labels moving points stuck"),
        "stick_velocity": Setting("float", 1e-3, 0.1, "a sample is stuck when |v| <= this x max |v|: outside, "
                                  "stick-slip reads as continuous"),
        "stuck_displacement_per_atol": Setting("float", 100.0, 1000.0, "no motion: max |q| <= this x atol; "
                                               "larger labels moving points stuck"),
        "max_evaluations": Setting("int", 10_000, 10**8, "right-hand-side evaluations per point at most: 5.7 us "
                                   "each, so at most about 10 min a point"),
    },
}

#: stored time-history samples per variable at most (16 MB of float64 each, 8 variables)
MAX_HISTORY_SAMPLES = 2_000_000

# Union tags appear in pydantic's error locations; the angle brackets keep them apart from YAML keys.
AXIS_TAGS = frozenset({"<number>", "<list>", "<range>"})

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


def show(v: Any) -> str:
    """A value as the user wrote it in YAML, for error messages."""
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if v != v:
            return ".nan"
        if v in (float("inf"), float("-inf")):
            return ".inf" if v > 0 else "-.inf"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _number(x: float) -> str:
    """A bound as a reader writes it: 1000000, 1e-06, 10000000000."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"


def _error(kind: str, message: str, at: tuple = ()) -> PydanticCustomError:
    # `at` extends the error's location, so the report can point at the offending item.
    # The message is final text: pydantic only substitutes `{at}`, which no message contains.
    return PydanticCustomError(kind, message, {"at": at})


def _raise_all(title: str, errors: list[PydanticCustomError]) -> None:
    """Raise every problem found at once (pydantic merges a ValidationError raised in a validator)."""
    if errors:
        raise ValidationError.from_exception_data(
            title, [InitErrorDetails(type=e, loc=(), input=None) for e in errors]
        )


class _Model(BaseModel):
    # frozen: the computed grid arrays must stay in step with the fields they come from
    model_config = ConfigDict(extra="forbid", frozen=True)


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
        return g.step_count(self.start, self.stop, self.step)[0]

    def values(self) -> np.ndarray:
        if self.num is not None:
            return g.linspace_values(self.start, self.stop, self.num)
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
    if isinstance(v, (dict, _Range)):  # a model instance when serialising
        return "<range>"
    if isinstance(v, list):
        return "<list>"
    if isinstance(v, (int, float, str)):  # strings and booleans get a "must be a number" error
        return "<number>"
    return None


def _axis(element: Any, range_model: type[_Range]) -> Any:
    return Annotated[
        Union[
            Annotated[element, Tag("<number>")],
            Annotated[list[element], Field(min_length=1), AfterValidator(_increasing), Tag("<list>")],
            Annotated[range_model, Tag("<range>")],
        ],
        Discriminator(
            _axis_kind,
            custom_error_type="grid_axis",
            custom_error_message="must be a number, a list of numbers, "
            "or a mapping with start, stop and one of num or step",
        ),
    ]


FrequencyAxis = _axis(FrequencyRatio, FrequencyRange)
ForceAxis = _axis(ForceRatio, ForceRange)


def _axis_size(axis: float | list[float] | _Range) -> int:
    if isinstance(axis, _Range):
        return axis.size
    return len(axis) if isinstance(axis, list) else 1


def _axis_values(axis: float | list[float] | _Range) -> np.ndarray:
    if isinstance(axis, _Range):
        return axis.values()
    return np.atleast_1d(np.asarray(axis, dtype=np.float64)).copy()


class Grid(_Model):
    frequency_ratio: FrequencyAxis
    force_ratio: ForceAxis
    _values: dict[str, np.ndarray] = PrivateAttr(default_factory=dict)

    @model_validator(mode="after")
    def _build(self):
        nf, nb = _axis_size(self.frequency_ratio), _axis_size(self.force_ratio)
        if nf * nb > g.MAX_POINTS:
            raise _error(
                "too_many_points",
                f"grid has {nf * nb} points ({nf} x {nb}); at most {g.MAX_POINTS} are allowed",
            )
        for name in ("frequency_ratio", "force_ratio"):
            axis = getattr(self, name)
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

    def _read_only(self, name: str) -> np.ndarray:
        values = self._values[name]
        values.flags.writeable = False  # shared by every reader; also re-set after unpickling
        return values

    @property
    def frequency_ratio_values(self) -> np.ndarray:
        return self._read_only("frequency_ratio")

    @property
    def force_ratio_values(self) -> np.ndarray:
        return self._read_only("force_ratio")


class Effects(_Model):
    """Physical effects beyond the plain model; absent means off (bit-identical to the plain model)."""

    viscous_damping: Annotated[float, Strict(), Field(allow_inf_nan=False, ge=0, lt=1)] | None = None
    # measured ratios are 1-2; beyond 100 the stick band swallows every excitation the grid allows
    static_friction_ratio: Annotated[float, Strict(), Field(allow_inf_nan=False, ge=1, le=100)] | None = None

    def declared(self) -> dict[str, float]:
        """The effects the spec names, as a plain dict."""
        return {k: float(v) for k, v in self.model_dump().items() if v is not None}


class Scene(_Model):
    excitation: Literal["force", "base", "joined"]
    effects: Effects = Field(default_factory=Effects)

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
    def _no_effects(cls, v: Any) -> Any:
        if v is None:  # `effects:` left empty
            return {}
        if isinstance(v, dict):
            unknown = [k for k in v if k not in EFFECTS]
            if unknown:
                raise _error(
                    "unknown_effect",
                    f"unknown effect {show(unknown[0])} (known: {', '.join(EFFECTS)})",
                    (unknown[0],),
                )
        return v


OutputName = Literal["transmissibility", "phase", "regime", "time_history"]


class TimeHistory(_Model):
    """Points whose steady-state orbits are stored (outputs: time_history)."""

    points: Annotated[list[Annotated[list[Finite], Field(min_length=2, max_length=2)]],
                      Field(min_length=1, max_length=1000)]
    samples_per_period: Annotated[int, Strict(), Field(ge=8, le=100_000)] = 256

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


class Sweep(_Model):
    """A stepped-sine sweep along frequency_ratio, as rigs are run: each point starts from the orbit
    its neighbour settled on (up: from the next lower frequency ratio; down: from the next higher)."""

    direction: Literal["up", "down"]


class Spec(_Model):
    """A validated sweep spec. Grid values: `frequency_ratio`, `force_ratio` (read-only float64)."""

    scene: Scene
    grid: Grid
    method: str = "theory"
    outputs: tuple[OutputName, ...] = DEFAULT_OUTPUTS
    time_history: TimeHistory | None = None
    output: str | None = None
    settings: dict[str, Any] = Field(default_factory=dict)
    accuracy: Annotated[float, Strict(), Field(allow_inf_nan=False, gt=0, lt=1)] | None = None
    sweep: Sweep | None = None
    _source_path: str = PrivateAttr(default="<string>")
    _text: str = PrivateAttr(default="")

    @field_validator("method", mode="before")
    @classmethod
    def _method_available(cls, v: Any) -> Any:
        if not isinstance(v, str):
            raise _error("method_type", f"must be a method name (got {show(v)})")
        if v not in METHODS_AVAILABLE:
            raise _error("unknown_method", f"unknown method {show(v)} (available: {', '.join(METHODS_AVAILABLE)})")
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
        if v is not None and (not isinstance(v, str) or not v.strip()):
            raise _error("output_path", f"must be a non-empty file path (got {show(v)})")
        if isinstance(v, str) and any(ord(ch) < 32 for ch in v):
            raise _error("output_path", f"must not hold control characters such as NUL or newline (got {show(v)})")
        if isinstance(v, str) and v.endswith("/"):
            raise _error("output_path", f"names a folder: name the file to write (got {show(v)})")
        return v

    @field_validator("settings")
    @classmethod
    def _settings_in_range(cls, settings: dict[str, Any], info: ValidationInfo) -> dict[str, Any]:
        method = info.data.get("method")
        if method is None:  # the method itself is wrong: reported there
            return settings
        known = METHOD_SETTINGS[method]
        problems = []
        for key, value in settings.items():
            if key not in known:
                allowed = ", ".join(known) or "none"
                problems.append(_error("unknown_setting", f"unknown setting {show(key)} for method {method!r} "
                                       f"(allowed: {allowed})", ("settings", key)))
            elif (reason := known[key].check(value)) is not None:
                problems.append(_error("setting_range", reason, ("settings", key)))
        # field-level locations get the field name prepended by pydantic: give `at` relative to it
        _raise_all("settings", [PydanticCustomError(e.type, e.message(), {"at": e.context["at"][1:]})
                                for e in problems])
        return settings

    @model_validator(mode="after")
    def _consistent(self):
        """Every rule that ties fields together, all reported at once."""
        _raise_all("Spec", [*self._history_problems(), *self._sweep_problems(), *self._accuracy_problems(),
                            *self._effect_problems()])
        return self

    def _history_problems(self):
        wanted = "time_history" in self.outputs
        if wanted and self.time_history is None:
            yield _error("history_missing", "outputs lists time_history: give `time_history: {points: [[r, beta], "
                         "...]}`", ("outputs",))
        if not wanted and self.time_history is not None:
            yield _error("history_unused", "time_history is given but not listed in outputs", ("time_history",))
        if wanted and self.method not in HISTORY_METHODS:
            yield _error("history_method", f"method {self.method!r} cannot store time histories "
                         f"(methods that can: {', '.join(HISTORY_METHODS)})", ("outputs",))

    def _sweep_problems(self):
        if self.sweep is None:
            return
        if self.method not in SWEEP_METHODS:
            yield _error("sweep_method", f"method {self.method!r} cannot run a swept sweep "
                         f"(methods that can: {', '.join(SWEEP_METHODS)})", ("sweep",))
        if self.time_history is not None:
            yield _error("sweep_and_history", "a swept run's time histories would not follow the sweep: "
                         "store them from a run without sweep", ("sweep",))
        if "starts" in self.settings:
            yield _error("sweep_and_starts", "a swept run starts each point from its neighbour's orbit: "
                         "settings.starts does not apply", ("settings", "starts"))

    def _accuracy_problems(self):
        if self.accuracy is None:
            return
        if self.method not in ACCURACY_METHODS:
            yield _error("accuracy_method", f"method {self.method!r} has no calibrated settings "
                         f"(accuracy works with: {', '.join(ACCURACY_METHODS)})", ("accuracy",))
        knobs = sorted(set(self.settings) & ACCURACY_KNOBS)
        if knobs:
            yield _error("accuracy_and_knobs", f"give either accuracy or the knobs it sets, not both "
                         f"(settings also has {', '.join(knobs)})", ("accuracy",))

    def _effect_problems(self):
        for name in self.scene.effects.declared():
            if name not in METHOD_EFFECTS[self.method]:
                able = [m for m, effects in METHOD_EFFECTS.items() if name in effects]
                yield _error("effect_unsupported", f"method {self.method!r} does not model {name} "
                             f"(methods that do: {', '.join(able)})", ("scene", "effects", name))

    @property
    def frequency_ratio(self) -> np.ndarray:
        return self.grid.frequency_ratio_values

    @property
    def force_ratio(self) -> np.ndarray:
        return self.grid.force_ratio_values

    @property
    def source_path(self) -> str:
        return self._source_path

    @property
    def text(self) -> str:
        return self._text
