"""fsweep runs on POSIX systems (Linux, macOS), as pyproject.toml's classifiers declare: a run holds its
output's lock with flock(2) (batch.checkpoint), every write opens its temporary with O_NOFOLLOW and fsyncs
the folder (storage.atomic), and a stopped worker is sent SIGKILL. Elsewhere the command line says so in
one line rather than with a traceback from the first of them it meets."""

from __future__ import annotations

import importlib.util
import os


def missing() -> str | None:
    """Why this system cannot run fsweep (None: it can)."""
    if importlib.util.find_spec("fcntl") is None or not hasattr(os, "O_NOFOLLOW"):
        return (f"fsweep needs a POSIX system (Linux, macOS): its output lock is flock(2) and its writes open "
                f"with O_NOFOLLOW, which this one (os.name {os.name!r}) lacks")
    return None
