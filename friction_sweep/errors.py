"""The one exception type of the Python API: every refusal the CLI reports as `fsweep: error: ...` (exit 2)
is raised as a FsweepError carrying the same message. Spec problems are its subclass SpecError."""

from __future__ import annotations


class FsweepError(Exception):
    """An input friction_sweep refuses (a spec, a cube, a setting), with the message the CLI prints."""
