"""Errors raised for a sweep spec that cannot be read or does not validate."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from friction_sweep.errors import FsweepError


@dataclass(frozen=True)
class SpecProblem:
    """One problem in a spec file, located by file, line/column (1-based) and dotted key."""

    path: str
    line: int | None
    column: int | None
    key: str
    reason: str

    def __str__(self) -> str:
        where = self.path
        if self.line is not None:
            where += f":{self.line}"
            if self.column is not None:
                where += f":{self.column}"
        return f"{where}: {self.key}: {self.reason}" if self.key else f"{where}: {self.reason}"


class SpecError(FsweepError):
    """All problems found in one spec; the attributes repeat those of the first problem."""

    def __init__(self, errors: Sequence[SpecProblem]):
        if not errors:
            raise ValueError("SpecError needs at least one problem")
        self.errors: list[SpecProblem] = list(errors)
        first = self.errors[0]
        self.path = first.path
        self.line = first.line
        self.column = first.column
        self.key = first.key
        self.reason = first.reason
        super().__init__(str(self))

    @classmethod
    def single(
        cls,
        path: str,
        reason: str,
        *,
        key: str = "",
        line: int | None = None,
        column: int | None = None,
    ) -> SpecError:
        return cls([SpecProblem(path, line, column, key, reason)])

    def __str__(self) -> str:
        return "\n".join(str(e) for e in self.errors)

    # The default reduce would call __init__ with the message string; worker processes pickle errors.
    def __reduce__(self):
        return (type(self), (self.errors,))
