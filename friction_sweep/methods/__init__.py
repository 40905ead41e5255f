"""Registry of sweep methods: one module per method, each implementing `MethodModule` below.

What a method can do (excitations, effects, settings with defaults and ranges, outputs, `accuracy:`,
`sweep:`) is its record in friction_sweep.catalogue, which each module holds as CATALOGUE; the module
holds only how it computes.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from typing import Any, Protocol, cast

import numpy as np

from friction_sweep import catalogue


class MethodModule(Protocol):
    """What the sweep layer calls on a method module."""

    CATALOGUE: catalogue.Method

    def variables_for(self, excitation: str, outputs: Sequence[str]) -> tuple[str, ...]:
        """Per-point variable names written for the requested output groups."""
        ...

    def compute_tile(self, excitation: str, r: Any, beta: Any, outputs: Sequence[str],
                     effects: catalogue.Effects | None = None,
                     settings: Mapping[str, Any] | None = None) -> dict[str, np.ndarray]:
        """Every variable of a (beta x r) tile, plus the theory's continuous limit per r."""
        ...


def get(name: str) -> MethodModule:
    """The module of a catalogued method, `friction_sweep.methods.<name>`, imported on first use: a run
    loads its own method's libraries only (SciPy's integrators are `paper`'s alone). Methods that can
    run a stepped-sine sweep also have compute_sweep_tile(..., direction); those that write time
    histories have time_histories(excitation, points, samples_per_period, effects, settings)."""
    record = catalogue.method(name)  # KeyError naming the methods there are
    return cast(MethodModule, importlib.import_module(f"{__name__}.{record.name}"))
