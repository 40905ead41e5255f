"""The provenance attributes a reader of a cube relies on, read one way: `fsweep info`, `check`, `plot`, the
audit (storage.cube.open_cube) and the Python API all read them here.

A cube's attributes are text from a file: its JSON ones (method_settings, physical_system,
accuracy_choice) can nest deeper than Python's recursion limit or be megabytes long, and its words
(excitation, method) can be anything. `read_json` parses a JSON attribute within a size and depth bound
(what fsweep writes is a few hundred characters, three levels deep), and `problems` lists what a cube's
provenance holds that no run writes: an excitation or method outside the catalogue, method settings that
are not the method's (a setting outside its meaningful range, an effect outside its range or place). A
cube with any such problem is refused by the reader, so that every command refuses alike.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from friction_sweep import catalogue

#: the longest JSON attribute read: fsweep writes a few hundred characters (the theory's algorithm notes)
MAX_JSON_CHARS = 65_536
#: the deepest nesting read: method_settings -> effects -> an effect's {ratio, to} is three levels
MAX_JSON_DEPTH = 8
#: the attributes that hold JSON
JSON_ATTRIBUTES = ("method_settings", "physical_system", "accuracy_choice", "structure")
#: keys of method_settings besides the method's settings and algorithm notes: the effects, a sweep's direction
SWEEP_DIRECTIONS = ("up", "down")

_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')


class BadAttribute(ValueError):
    """An attribute holds what no run writes; the message names it and says why."""


def read_json(attrs: Mapping, key: str, kind: type = dict) -> Any:
    """The JSON attribute `key` of `attrs` parsed (None where absent), of type `kind`; BadAttribute where it
    is not text, longer than MAX_JSON_CHARS, nested deeper than MAX_JSON_DEPTH, not JSON (NaN and
    Infinity included: JSON has none) or not a `kind`."""
    if key not in attrs:
        return None
    text = attrs[key]
    if not isinstance(text, str):
        raise BadAttribute(f"attribute {key} is not text ({type(text).__name__})")
    if len(text) > MAX_JSON_CHARS:
        raise BadAttribute(f"attribute {key} holds {len(text)} characters; fsweep reads at most {MAX_JSON_CHARS}")
    brackets = np.frombuffer(_STRING.sub("", text).encode("utf-8", "surrogatepass"), dtype=np.uint8)
    steps = np.isin(brackets, (ord("["), ord("{"))).astype(np.int64) - np.isin(brackets, (ord("]"), ord("}")))
    if steps.size and int(np.cumsum(steps).max()) > MAX_JSON_DEPTH:
        raise BadAttribute(f"attribute {key} nests deeper than {MAX_JSON_DEPTH} levels")

    def constant(name: str):
        raise ValueError(f"{name} is not a JSON number")

    try:
        value = json.loads(text, parse_constant=constant)
    except (ValueError, RecursionError) as err:
        raise BadAttribute(f"attribute {key} is not JSON: {' '.join(str(err).split())}") from None
    if not isinstance(value, kind):
        raise BadAttribute(f"attribute {key} is not a JSON {'object' if kind is dict else kind.__name__}")
    return value


def method_settings(attrs: Mapping) -> dict[str, Any]:
    """The cube's method_settings (an empty dict where absent), `effects` an object ({} where absent);
    BadAttribute where they are not (read_json)."""
    settings = read_json(attrs, "method_settings") or {}
    effects = settings.get("effects", {})
    if not isinstance(effects, dict):
        raise BadAttribute("attribute method_settings: effects is not a JSON object")
    return {**settings, "effects": effects}


def problems(attrs: Mapping) -> list[str]:
    """What the provenance attributes `attrs` hold that no run writes, one sentence each naming the
    attribute (empty: none)."""
    found: list[str] = []
    excitation = attrs.get("excitation")
    if not isinstance(excitation, str) or excitation not in catalogue.EXCITATIONS:
        found.append(f"attribute excitation {_shown(excitation)} is not one of {', '.join(catalogue.EXCITATIONS)}")
    name = attrs.get("method")
    record = catalogue.METHODS.get(name) if isinstance(name, str) else None
    if record is None:
        found.append(f"attribute method {_shown(name)} is not a method of the catalogue "
                     f"({', '.join(catalogue.METHODS)})")
    for key in JSON_ATTRIBUTES:
        try:
            read_json(attrs, key)
        except BadAttribute as err:
            found.append(str(err))
    if record is None or found:
        return found
    try:
        settings = method_settings(attrs)
    except BadAttribute as err:
        return [str(err)]
    for key, value in settings.items():
        found.extend(_setting(record, str(excitation), key, value))
    return found


def _shown(value: Any) -> str:
    """An attribute's value in a message: absent, or its repr cut short (the caller escapes it)."""
    if value is None:
        return "(absent)"
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _setting(record: catalogue.Method, excitation: str, key: str, value: Any) -> list[str]:
    where = f"attribute method_settings: {key}"
    if key == "effects":
        return [p for name, v in value.items() for p in _effect(record, excitation, name, v)]
    if key == "sweep":
        if isinstance(value, str) and value in SWEEP_DIRECTIONS:
            return []
        return [f"{where} is not one of {', '.join(SWEEP_DIRECTIONS)}: {_shown(value)}"]
    if key in record.algorithm:
        return [] if isinstance(value, str) else [f"{where} is not text: {_shown(value)}"]
    known = record.settings.get(key)
    if known is None:
        return [f"{where} is not a setting of method {record.name}"]
    number = not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)
    if not number or not known.contains(value) or (known.kind == "int" and value != int(value)):
        return [f"{where} is not {'an integer' if known.kind == 'int' else 'a number'} in {known.describe()}: "
                f"{_shown(value)}"]
    return []


def _effect(record: catalogue.Method, excitation: str, name: str, value: Any) -> list[str]:
    where = f"attribute method_settings: effect {name}"
    effect = catalogue.EFFECTS.get(name)
    if effect is None:
        return [f"{where} is not an effect of the catalogue ({', '.join(catalogue.EFFECTS)})"]
    if name not in record.effects:
        return [f"{where}: method {record.name} does not model it"]
    places = effect.places.get(excitation, {})
    if isinstance(value, dict) and places:
        if set(value) != set(catalogue.PLACED_KEYS) or value["to"] not in places:
            return [f"{where} is not {{ratio, to: {' | '.join(places)}}}: {_shown(value)}"]
        value = value["ratio"]
    number = not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)
    if not number or not effect.contains(value):
        return [f"{where} is not a number in {effect.describe()}: {_shown(value)}"]
    return []


__all__ = ["MAX_JSON_CHARS", "MAX_JSON_DEPTH", "JSON_ATTRIBUTES", "BadAttribute", "read_json", "method_settings",
           "problems"]
