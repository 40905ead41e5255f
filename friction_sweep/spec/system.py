"""The physical system behind (r, beta): a spec's `system:` block, its physical grid axes, and the map
between physical and dimensionless values (docs/equations.md §1).

    r = f / f_n,    beta = F_mu / F_k,    f_n = sqrt(k/m) / (2 pi)

F_k is the amplitude of the force that drives the mass: k Y for `base` and `joined` (the spring's force
amplitude, the paper's F_k), F0 for `force`. Lengths are measured in L = F_k / k (Y, or F0/k), forces in
F_k and energies in F_k L: a length, force or energy out of the computation is a physical one times these.

Any two of natural_frequency, mass and stiffness fix the third; the excitation is a force (excitation_force)
or, for base and joined, the base's amplitude (base_amplitude, with the stiffness) or its acceleration
(base_acceleration, what shaker controllers hold: Y = a / omega^2, so F_k = k a / omega^2 falls and beta
grows with f^2 along a sweep); the friction is a force (friction_force) or a coefficient times a normal
load, given here or swept on the grid's friction_force axis. Only what a spec uses is required: a
dimensionless axis needs nothing from the system.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
from pydantic import BeforeValidator, model_validator

from . import grid as g
from .base import Model, problem, raise_all, show
from .quantities import (
    ACCELERATION,
    FORCE,
    FREQUENCY,
    LENGTH,
    MASS,
    RATIO,
    SI_SPAN,
    STIFFNESS,
    Kind,
    QuantityError,
    in_range,
    to_si,
)


def _quantity(kind: Kind, *, zero: bool = False):
    """A field holding `kind` in SI: read from its text, positive (or zero where `zero`)."""

    def read(value: Any) -> float:
        try:
            x = to_si(value, kind)
        except QuantityError as err:
            raise problem("quantity", str(err)) from None
        if x < 0 or (x == 0 and not zero):
            raise problem("quantity_sign", f"must be {'zero or ' if zero else ''}positive (got {show(value)})")
        return x

    return Annotated[float, BeforeValidator(read)]


class System(Model):
    """`system:` of a spec, each quantity in SI (Hz, kg, N/m, N, m; the coefficient a plain number)."""

    natural_frequency: _quantity(FREQUENCY) | None = None  # type: ignore[valid-type]
    mass: _quantity(MASS) | None = None  # type: ignore[valid-type]
    stiffness: _quantity(STIFFNESS) | None = None  # type: ignore[valid-type]
    excitation_force: _quantity(FORCE) | None = None  # type: ignore[valid-type]
    base_amplitude: _quantity(LENGTH) | None = None  # type: ignore[valid-type]
    base_acceleration: _quantity(ACCELERATION) | None = None  # type: ignore[valid-type]
    friction_force: _quantity(FORCE, zero=True) | None = None  # type: ignore[valid-type]
    friction_coefficient: _quantity(RATIO, zero=True) | None = None  # type: ignore[valid-type]
    normal_load: _quantity(FORCE) | None = None  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _determined(self):
        problems = []
        given = [n for n in ("natural_frequency", "mass", "stiffness") if getattr(self, n) is not None]
        if len(given) == 3:
            problems.append(problem("over_determined", "give two of natural_frequency, mass and stiffness, not "
                                    "all three: any two fix the third", ("mass",)))
        elif given in (["mass"], ["stiffness"]):
            other = "stiffness" if given == ["mass"] else "mass"
            problems.append(problem("under_determined", f"{given[0]} alone fixes no natural frequency: give "
                                    f"{other} or natural_frequency as well", (given[0],)))
        amplitudes = [n for n in ("excitation_force", "base_amplitude", "base_acceleration")
                      if getattr(self, n) is not None]
        if len(amplitudes) > 1:
            problems.append(problem("two_amplitudes", f"give the excitation one way: {' or '.join(amplitudes)}, "
                                    "not both", (amplitudes[-1],)))
        for name, what in (("base_amplitude", "k Y"), ("base_acceleration", "k a / omega^2")):
            if getattr(self, name) is not None and self.stiffness_si is None:
                problems.append(problem("amplitude_needs_stiffness", f"a base {name.split('_')[1]} drives the mass "
                                        f"with the spring's force {what}: give the stiffness (or mass and "
                                        "natural_frequency)", (name,)))
        by_coefficient = (self.friction_coefficient, self.normal_load)
        if self.friction_force is not None and any(x is not None for x in by_coefficient):
            problems.append(problem("two_frictions", "give friction_force or friction_coefficient with "
                                    "normal_load, not both", ("friction_force",)))
        elif (by_coefficient[0] is None) != (by_coefficient[1] is None):
            have, need = ("friction_coefficient", "normal_load") if by_coefficient[1] is None else \
                ("normal_load", "friction_coefficient")
            problems.append(problem("friction_half", f"{have} needs {need}: the friction force is their "
                                    "product", (have,)))
        raise_all("system", problems or self._derived_problems())
        return self

    def _derived_problems(self) -> list:
        """Each value the system derives, finite and in the range of a physical value (quantities.SI_RANGE),
        located at the key it comes from: what a product or ratio of two values in range may leave."""
        f_n, k, force, length = self.natural_frequency_si, self.stiffness_si, self.reference_force, self.length_scale
        given_f = self.natural_frequency is not None
        derived = [
            ("the natural frequency f_n = sqrt(k / m) / (2 pi)", f_n, "Hz", "stiffness", not given_f),
            ("omega_n = 2 pi f_n", None if f_n is None else 2.0 * math.pi * f_n, "rad/s",
             "natural_frequency" if given_f else "stiffness", True),
            ("the stiffness k = m (2 pi f_n)^2", k, "N/m", "mass", self.stiffness is None),
            ("the excitation force F_k = k Y", force, "N", "base_amplitude", self.excitation_force is None),
            ("the length scale L = F_k / k", length, "m", "excitation_force", self.base_amplitude is None),
            ("the energy scale F_k L", None if force is None or length is None else force * length, "J",
             "excitation_force" if self.excitation_force is not None else "base_amplitude", True),
            ("the friction force mu N", self.friction, "N", "normal_load", self.friction_force is None),
        ]
        return [p for what, value, unit, key, is_derived in derived if is_derived and value is not None
                and (p := range_problem(what, np.array([value]), unit, (key,))) is not None]

    @property
    def natural_frequency_si(self) -> float | None:
        """f_n in Hz, as given or sqrt(k/m) / (2 pi)."""
        if self.natural_frequency is not None:
            return self.natural_frequency
        if self.mass is not None and self.stiffness is not None:
            return math.sqrt(self.stiffness / self.mass) / (2.0 * math.pi)
        return None

    @property
    def stiffness_si(self) -> float | None:
        """k in N/m, as given or m (2 pi f_n)^2."""
        if self.stiffness is not None:
            return self.stiffness
        if self.mass is not None and self.natural_frequency is not None:
            return self.mass * (2.0 * math.pi * self.natural_frequency) ** 2
        return None

    @property
    def mass_si(self) -> float | None:
        """m in kg, as given or k / (2 pi f_n)^2."""
        if self.mass is not None:
            return self.mass
        if self.stiffness is not None and self.natural_frequency is not None:
            return self.stiffness / (2.0 * math.pi * self.natural_frequency) ** 2
        return None

    @property
    def reference_force(self) -> float | None:
        """F_k in N: the excitation's force amplitude, given or k Y; None at constant acceleration, where
        it depends on the frequency (force_at)."""
        if self.excitation_force is not None:
            return self.excitation_force
        k = self.stiffness_si
        if self.base_amplitude is not None and k is not None:
            return k * self.base_amplitude
        return None

    @property
    def length_scale(self) -> float | None:
        """L in m: the base's amplitude as given, else F_k / k where both are known."""
        if self.base_amplitude is not None:
            return self.base_amplitude
        k, force = self.stiffness_si, self.reference_force
        return force / k if k is not None and force is not None else None

    @property
    def friction(self) -> float | None:
        """F_mu in N, given or mu N; None where the grid sweeps it."""
        if self.friction_force is not None:
            return self.friction_force
        if self.friction_coefficient is not None and self.normal_load is not None:
            return self.friction_coefficient * self.normal_load
        return None


def range_problem(what: str, values: np.ndarray, unit: str, at: tuple):
    """A problem where a derived physical value is not finite or leaves quantities.SI_RANGE (the first such
    value and how many more), else None."""
    values = np.asarray(values, dtype=np.float64).ravel()
    bad = np.flatnonzero(~in_range(values))
    if not bad.size:
        return None
    more = f" ({bad.size - 1} more)" if bad.size > 1 else ""
    return problem("derived_range", f"{what} is {values[bad[0]]:.3g} {unit}{more}: every physical value must be "
                   f"{SI_SPAN} in SI units (the inputs are out of proportion)", at)


def physical_axis(value: Any, kind: Kind) -> tuple[float, ...]:
    """A physical grid axis in SI: one quantity, a list of them (strictly increasing), or
    {start, stop, num} / {start, stop, step} (inclusive, each value rounded to 12 significant digits as a
    dimensionless axis is). Problems are raised all at once, located at the item."""

    def read(x: Any, at: tuple, zero: bool) -> float | None:
        try:
            v = to_si(x, kind)
        except QuantityError as err:
            problems.append(problem("quantity", str(err), at))
            return None
        if v < 0 or (v == 0 and not zero):
            problems.append(problem("quantity_sign", f"must be {'zero or ' if zero else ''}positive (got {show(x)})",
                                    at))
            return None
        return v

    problems: list = []
    zero = kind is FORCE  # no friction is a force ratio of 0; no frequency is no sweep
    if isinstance(value, list):
        if not value:
            raise problem("axis_empty", "must not be empty")
        values = [read(x, (i,), zero) for i, x in enumerate(value)]
        raise_all("axis", problems)
        for i in range(1, len(values)):
            if values[i] <= values[i - 1]:  # type: ignore[operator]
                what = "duplicate value" if values[i] == values[i - 1] else "not sorted"
                raise problem("not_increasing", f"values must be strictly increasing: {what} {show(value[i])} "
                              f"after {show(value[i - 1])}", (i,))
        return tuple(float(v) for v in values)  # type: ignore[arg-type]
    if isinstance(value, dict):
        unknown = sorted(set(value) - {"start", "stop", "num", "step"})
        for key in unknown:
            problems.append(problem("unknown_key", f"unknown key {show(key)} (allowed: start, stop, num, step)",
                                    (key,)))
        for key in ("start", "stop"):
            if key not in value:
                problems.append(problem("missing", f"required key {key!r} is missing"))
        raise_all("axis", problems)
        start, stop = read(value["start"], ("start",), zero), read(value["stop"], ("stop",), zero)
        num, step = value.get("num"), value.get("step")
        if (num is None) == (step is None):
            problems.append(problem("num_or_step", "give exactly one of 'num' or 'step' (got "
                                    f"{'both' if num is not None else 'neither'})"))
        elif num is not None and (isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= g.MAX_POINTS):
            problems.append(problem("num", f"must be an integer from 1 to {g.MAX_POINTS} (got {show(num)})",
                                    ("num",)))
        step_si = read(step, ("step",), False) if step is not None else None
        raise_all("axis", problems)
        assert start is not None and stop is not None  # else raised above
        if stop < start:
            raise problem("stop_below_start", f"must be >= start ({show(value['start'])}) (got {show(value['stop'])})",
                          ("stop",))
        if num is not None:
            if num == 1 and start != stop:
                raise problem("num_one", f"num = 1 needs start == stop (got start {show(value['start'])}, stop "
                              f"{show(value['stop'])})", ("num",))
            out = g.linspace_values(start, stop, num)
        else:
            assert step_si is not None
            if g.step_count(start, stop, step_si)[0] > g.MAX_POINTS:
                raise problem("too_many_points", f"step gives more than {g.MAX_POINTS} points", ("step",))
            out = g.step_values(start, stop, step_si)
        if g.first_not_increasing(out) is not None:
            raise problem("grid_too_fine", f"spacing is finer than {g.SIGNIFICANT_DIGITS} significant digits: "
                          "values collide")
        return tuple(out.tolist())
    v = read(value, (), zero)
    raise_all("axis", problems)
    return (float(v),)  # type: ignore[arg-type]


@dataclass(frozen=True)
class PhysicalMap:
    """A spec's physical values beside the dimensionless ones it computes with (SI; None where unknown).

    At constant base acceleration a, F_k and L depend on the frequency: L = a / (2 pi f)^2, F_k = k L
    (scales_at); the grid's dims are then the physical ones (`physical_dims`)."""

    natural_frequency: float | None  # f_n, Hz
    reference_force: float | None  # F_k, N (None at constant acceleration)
    length_scale: float | None  # L, m (None at constant acceleration)
    stiffness: float | None  # k, N/m
    frequency: np.ndarray | None  # Hz, one per frequency ratio
    friction_force: np.ndarray | None  # N, one per force ratio
    acceleration: float | None = None  # a, m/s^2, where the base's acceleration is held
    mass: float | None = None  # m, kg

    @property
    def physical_dims(self) -> bool:
        """Whether the cube's dims are (friction_force, frequency): at constant acceleration beta varies
        along both, so it is a 2-D coordinate, not a dim."""
        return self.acceleration is not None

    def scales_at(self, frequency) -> tuple[np.ndarray | float | None, np.ndarray | float | None]:
        """(F_k, L) at the given frequencies (Hz): constant, or k a / omega^2 and a / omega^2."""
        if self.acceleration is None:
            return self.reference_force, self.length_scale
        length = self.acceleration / (2.0 * math.pi * np.asarray(frequency, dtype=np.float64)) ** 2
        return (self.stiffness * length if self.stiffness is not None else None), length

    def describe(self, excitation: str) -> list[str]:
        """Lines saying what (r, beta) mean physically, for `fsweep validate` and `fsweep info`."""
        lines = []
        if self.natural_frequency is not None:
            lines.append(f"natural frequency f_n = {self.natural_frequency:.6g} Hz "
                         f"(omega_n = {2 * math.pi * self.natural_frequency:.6g} rad/s): r = f / f_n")
        if self.reference_force is not None:
            what = "F0" if excitation == "force" else "k Y"
            lines.append(f"excitation force F_k = {what} = {self.reference_force:.6g} N: beta = F_mu / F_k")
        if self.acceleration is not None:
            lines.append(f"base acceleration a = {self.acceleration:.6g} m/s^2 held: Y = a / omega^2, "
                         "F_k = k Y, beta = F_mu / F_k grows with f^2 (dims frequency, friction_force)")
        if self.length_scale is not None:
            what = "F0 / k" if excitation == "force" else "Y"
            lines.append(f"length scale {what} = {self.length_scale:.6g} m: displacements = ratios x {what}")
        if self.stiffness is not None:
            lines.append(f"stiffness k = {self.stiffness:.6g} N/m")
        return lines


def ratios(values: np.ndarray, scale: float) -> np.ndarray:
    """values / scale, rounded to the grid's 12 significant digits (so 5 Hz / 25 Hz is r = 0.2 exactly)."""
    return g.round_significant(np.asarray(values, dtype=np.float64) / scale)
