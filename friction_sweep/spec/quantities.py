"""Physical quantities as a spec writes them ("40 kN/m", "314 rad/s", "0.5 g"), read with pint into SI floats.

This is the one place where units are stripped: the rest of the tool computes in (r, beta) and attaches
SI units (Hz, N, m, J, s) to what it writes. pint is imported on first use only, so a spec without a
`system:` block costs nothing.

Two traps a plain `to()` falls into, handled here:
- pint treats the radian as dimensionless, so `(314 rad/s).to("Hz")` is 314 Hz. A frequency whose units
  hold an angle (rad/s, deg/s, rpm, rev/min, cycle/s) is an angular frequency: f = omega / (2 pi). One
  without (Hz, 1/s, 1/min) counts cycles.
- "g" is the gram: an acceleration written in g (`0.5 g`) means standard gravity, 9.80665 m/s^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

from .base import show
from .expression import ExpressionError, evaluate


@dataclass(frozen=True)
class Kind:
    """A physical quantity a spec may give: its name in messages, its SI unit and an example."""

    #: with its article, for messages
    name: str
    #: the SI unit values are returned in, as pint reads it
    si: str
    example: str


FREQUENCY = Kind("a frequency", "Hz", "50 Hz or 314 rad/s")
FORCE = Kind("a force", "N", "12 N")
STIFFNESS = Kind("a stiffness", "N/m", "40 kN/m")
MASS = Kind("a mass", "kg", "2 kg")
LENGTH = Kind("a length", "m", "1 mm")
ACCELERATION = Kind("an acceleration", "m/s**2", "0.5 g or 4.9 m/s**2")
RATIO = Kind("a dimensionless number", "dimensionless", "0.3")
#: an angle, in degrees: a bare number is degrees already, a string any angle unit (deg, rad, arcmin)
ANGLE = Kind("an angle", "degree", "5 deg")
KINDS = (FREQUENCY, FORCE, STIFFNESS, MASS, LENGTH, ACCELERATION, RATIO, ANGLE)


#: a quantity is a number and a unit: longer text is not one
MAX_TEXT = 64
#: the largest power a unit expression may raise to (m**3, s**-2 need 3): a literal bound keeps every
#: value the expression computes a float, whatever its nesting (pint, given `(9**99)**99`, computes
#: integers of millions of digits)
MAX_EXPONENT = 4
#: every physical value a spec gives or the tool derives from it (f_n, omega_n, k, F_k, L, F_k L, each
#: grid frequency and friction force), in SI units, is 0 or of a magnitude in this range: beyond it
#: products of two such values leave a double's range (1e200 N/m x 1e200 m) or fall to 0 (1e-200 kg x
#: 1e-200 Hz^2), and every physical oscillator fits inside it many times over
SI_RANGE = (1e-30, 1e30)
#: the range in words, for messages
SI_SPAN = f"0 or between {SI_RANGE[0]:g} and {SI_RANGE[1]:g}"

class QuantityError(ValueError):
    """A quantity that cannot be read as the kind asked for; the message is the reason, for a spec problem."""


@cache
def registry() -> Any:
    import pint

    return pint.UnitRegistry()


def _dimensionality(kind: Kind) -> Any:
    return registry().Quantity(1, kind.si).dimensionality


def _describe(dimensionality: Any) -> str:
    for kind in KINDS:
        if dimensionality == _dimensionality(kind):
            return kind.name
    return f"of dimension {dimensionality}"


def to_si(value: Any, kind: Kind) -> float:
    """`value` (a string such as "40 kN/m"; a bare number only for a dimensionless kind) as a float in the
    kind's SI unit. QuantityError says why it cannot be; zero and negative values are the caller's to judge."""
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise QuantityError(f"must be {kind.name} such as '{kind.example}' (got {show(value)})")
    if not isinstance(value, str):
        if kind is RATIO or kind is ANGLE:
            try:
                x = float(value)
            except OverflowError:  # an integer of hundreds of digits
                raise QuantityError(f"must be finite (got {show(value)})") from None
            return _finite(x, show(value), kind)
        raise QuantityError(f"must be {kind.name} with its unit, such as '{kind.example}' (got {show(value)}: "
                            "a number without a unit)")
    if len(value) > MAX_TEXT:
        raise QuantityError(f"must be {kind.name} such as '{kind.example}': a number and a unit in at most "
                            f"{MAX_TEXT} characters (got {len(value)} characters: {value[:MAX_TEXT]!r}...)")
    ureg = registry()
    try:
        quantity = evaluate(value, MAX_EXPONENT, lambda name: ureg.Quantity(1.0, name), ureg.Quantity)
    except ExpressionError as err:
        raise QuantityError(f"cannot read {value!r} as {kind.name} such as '{kind.example}': {err}") from None
    if kind is ACCELERATION and quantity.dimensionality == _dimensionality(MASS) \
            and dict(quantity.unit_items()) == {"gram": 1}:
        quantity = quantity.magnitude * ureg.standard_gravity
    if kind is ANGLE:  # pint's angles are dimensionless: an angle is one whose units hold the radian
        if not quantity.dimensionless or "radian" not in dict(quantity.to_root_units().unit_items()):
            raise QuantityError(f"must be {kind.name} such as '{kind.example}' (got {show(value)})")
        return _finite(float(quantity.to("degree").magnitude), value, kind)
    if kind is RATIO:
        if not quantity.dimensionless:
            raise QuantityError(f"must be {kind.name} (got {value!r}: {_describe(quantity.dimensionality)})")
        return _finite(float(quantity.to("dimensionless").magnitude), value, kind)
    if quantity.dimensionality != _dimensionality(kind):
        got = "a number without a unit" if quantity.dimensionless else _describe(quantity.dimensionality)
        raise QuantityError(f"must be {kind.name} such as '{kind.example}' (got {value!r}: {got})")
    if kind is FREQUENCY:
        root = quantity.to_root_units()
        angular = dict(root.unit_items()).get("radian", 0)
        if angular:  # rad/s, rpm, cycle/s: an angle per time
            return _finite(float(root.to("radian / second").magnitude) / (2.0 * math.pi), value, kind)
        return _finite(float(quantity.to("Hz").magnitude), value, kind)
    return _finite(float(quantity.to(kind.si).magnitude), value, kind)


def _finite(x: float, value: str, kind: Kind) -> float:
    if not math.isfinite(x):
        raise QuantityError(f"must be finite (got {value!r})")
    if not in_range(x):
        unit = "" if kind is RATIO else f" {kind.si}"
        raise QuantityError(f"must be {SI_SPAN}{unit} (got {value!r}: {x:.3g}{unit})")
    return x


def in_range(x: Any) -> Any:
    """Whether x (SI; a float or an array, elementwise) is 0 or of a magnitude in SI_RANGE: what every
    physical value must be (NaN and infinities are not)."""
    magnitude = np.abs(x)
    return (magnitude == 0) | ((magnitude >= SI_RANGE[0]) & (magnitude <= SI_RANGE[1]))
