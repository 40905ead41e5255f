"""Files shipped with the package, named `package:PATH` from a spec or the command line.

PATH is relative to the installed package's folder (importlib.resources), so a name holds from a plain
`pip install`, whatever the working directory:
- `package:examples/` the example specs, the repository's configs/ (friction_sweep/examples is a link to
  it, copied into the wheel and the sdist): `package:examples/demo.yaml`,
  `package:examples/calibration/rig.yaml`, ...;
- `package:data/` the rig's measured phases: `package:data/experiment_phase_fixed_wall.csv`.

`fsweep run`, `validate` and `calibrate` take such a name for SPEC, `validate-data --data` for its CSV, and
a calibration spec's `data: {file: ...}` for its data. Only inputs: the name is read, never written.
"""

from __future__ import annotations

import importlib.resources
import os
from pathlib import Path, PurePosixPath

import click

PREFIX = "package:"
#: where the example specs lie inside the package (shown by the refusal of a name that is not there)
EXAMPLES = f"{PREFIX}examples/"


def named(name: str | os.PathLike[str]) -> bool:
    """Whether `name` names a packaged file (`package:PATH`) rather than a path."""
    return os.fspath(name).startswith(PREFIX)


def root() -> Path:
    """The installed package's folder (a plain folder: the wheel is installed unzipped)."""
    return Path(str(importlib.resources.files("friction_sweep")))


def problem(name: str) -> str | None:
    """Why `package:PATH` names no file inside the package (None when it does, or is no such name)."""
    if not named(name):
        return None
    rest = PurePosixPath(name[len(PREFIX):])
    if not rest.parts or rest.is_absolute() or ".." in rest.parts or "\\" in str(rest):
        return f"{name!r}: a packaged file is named {PREFIX}PATH, PATH inside the package (no '..', not absolute)"
    if not root().joinpath(*rest.parts).is_file():
        return (f"{name!r}: no such file in the installed package ({root()}); the example specs are "
                f"{EXAMPLES}NAME.yaml (see its examples/ folder)")
    return None


def resolve(name: str | os.PathLike[str]) -> Path:
    """The file `name` names: the packaged file for `package:PATH` (see `problem` for one that is not
    there), else `name` itself as a path."""
    text = os.fspath(name)
    if not named(text):
        return Path(text)
    return root().joinpath(*PurePosixPath(text[len(PREFIX):]).parts)


class InputPath(click.ParamType):
    """A command-line input file: a path, or `package:PATH` (refused in one line when not in the package)."""

    name = "path"

    def convert(self, value, param, ctx) -> Path:
        if isinstance(value, Path):
            return value
        reason = problem(value)
        if reason is not None:
            self.fail(reason, param, ctx)
        return resolve(value)
