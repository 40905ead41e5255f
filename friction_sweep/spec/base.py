"""What every spec model shares: the frozen strict base model, and problems raised all at once with the
location of the offending item."""

from __future__ import annotations

import numbers
import warnings
from typing import Any

from pydantic import BaseModel, ConfigDict, PrivateAttr, ValidationError
from pydantic_core import InitErrorDetails, PydanticCustomError

#: the longest a value is shown in a message
_SHOWN_CHARS = 60


def show(v: Any) -> str:
    """A value as the user wrote it in YAML, for error messages: at most about 60 characters, an integer of
    many digits by its number of digits (never converted to text whole: Python refuses beyond 4300 digits,
    and a megabyte of digits is no message), a YAML type no spec key takes by its YAML name (`!!set`,
    `!!binary`, a timestamp), never as the Python object that holds it."""
    text = _shown(v, _SHOWN_CHARS + 1)
    return text if len(text) <= _SHOWN_CHARS else text[:_SHOWN_CHARS - 3] + "..."


def _shown(v: Any, room: int) -> str:
    """show without the final cut; `room`: characters wanted (containers stop listing beyond it)."""
    import datetime
    from collections.abc import Mapping, Set

    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if type(v).__name__ == "TaggedScalar":  # a value with a tag of its own: `!custom 1`
        return _shown(f"{v.tag} {v.value}", room)
    if isinstance(v, numbers.Integral):  # numpy's integers too
        return _integer(int(v))
    if isinstance(v, numbers.Real) and not isinstance(v, float):  # numpy's floats of other widths
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            v = float(v)
    if isinstance(v, float):
        if v != v:
            return ".nan"
        if v in (float("inf"), float("-inf")):
            return ".inf" if v > 0 else "-.inf"
        return repr(v)
    if isinstance(v, str):
        return repr(v[:room])
    if isinstance(v, (bytes, bytearray)):
        return f"binary data of {len(v)} bytes (!!binary)"
    if isinstance(v, (datetime.date, datetime.datetime)):
        return f"a timestamp ({v.isoformat()})"
    if isinstance(v, Mapping):
        return _listed(((f"{_shown(k, room)}: {_shown(x, room)}" for k, x in v.items())), "{", "}", room)
    if isinstance(v, (Set, type({}.keys()))):
        return "a set (!!set) " + _listed((_shown(x, room) for x in v), "{", "}", room)
    if isinstance(v, (list, tuple)):
        return _listed((_shown(x, room) for x in v), "[", "]", room)
    if isinstance(v, complex):
        return f"a complex number ({v.real!r}, {v.imag!r})"
    return f"a value of type {type(v).__name__}"


def _integer(v: int) -> str:
    """An integer as its digits, or beyond 40 digits as "an integer of N digits" (N counted without text)."""
    magnitude = abs(v)
    if magnitude < 10**40:
        return str(v)
    digits = int((magnitude.bit_length() - 1) * 0.30102999566398120) + 1  # log10(2): exact or one short
    if magnitude >= 10**digits:
        digits += 1
    return f"{'a negative' if v < 0 else 'an'} integer of {digits} digits"


def _listed(items, opening: str, closing: str, room: int) -> str:
    """Items in flow style, listed until about `room` characters."""
    parts: list[str] = []
    used = 0
    for item in items:
        if used > room:
            parts.append("...")
            break
        parts.append(item)
        used += len(item) + 2
    return opening + ", ".join(parts) + closing


def problem(kind: str, message: str, at: tuple = ()) -> PydanticCustomError:
    # `at` extends the error's location, so the report can point at the offending item.
    # The message is final text: pydantic only substitutes `{at}`, which no message contains.
    return PydanticCustomError(kind, message, {"at": at})


def raise_all(title: str, errors: list[PydanticCustomError]) -> None:
    """Raise every problem found at once (pydantic merges a ValidationError raised in a validator)."""
    if errors:
        raise ValidationError.from_exception_data(
            title, [InitErrorDetails(type=e, loc=(), input=None) for e in errors]
        )


class Model(BaseModel):
    # frozen: the computed grid arrays must stay in step with the fields they come from
    model_config = ConfigDict(extra="forbid", frozen=True)


class Sourced(Model):
    """A validated YAML file's model: where it was read from and its text (set by its parser)."""

    _source_path: str = PrivateAttr(default="<string>")
    _text: str = PrivateAttr(default="")

    @property
    def source_path(self) -> str:
        return self._source_path

    @property
    def text(self) -> str:
        return self._text
