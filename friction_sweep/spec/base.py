"""What every spec model shares: the frozen strict base model, and problems raised all at once with the
location of the offending item."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, PrivateAttr, ValidationError
from pydantic_core import InitErrorDetails, PydanticCustomError


def show(v: Any) -> str:
    """A value as the user wrote it in YAML, for error messages."""
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if type(v).__name__ == "TaggedScalar":  # a value with a tag of its own: `!custom 1`
        v = f"{v.tag} {v.value}"
    if isinstance(v, float):
        if v != v:
            return ".nan"
        if v in (float("inf"), float("-inf")):
            return ".inf" if v > 0 else "-.inf"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


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
