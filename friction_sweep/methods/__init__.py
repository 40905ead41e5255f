"""Registry of sweep methods. A method is one module declaring what it can do:

    NAME, EXCITATIONS, EFFECTS (the physical effects it models), SETTINGS (defaults, recorded in the cube),
    variables_for(excitation, outputs) -> names,
    compute_tile(excitation, r, beta, outputs, effects=None, settings=None) -> arrays,
    and, for the simulation methods that can run a stepped-sine sweep (`sweep:` in a spec),
    compute_sweep_tile(excitation, r, beta, outputs, effects=None, settings=None, direction="up")

New methods (event, rk4, paper, auto) register here with the same interface.
"""

from __future__ import annotations

from types import ModuleType

from friction_sweep.methods import auto, event, paper, rk4, theory

REGISTRY: dict[str, ModuleType] = {m.NAME: m for m in (theory, event, rk4, paper, auto)}


def get(name: str) -> ModuleType:
    try:
        return REGISTRY[name]
    except KeyError:
        raise KeyError(f"unknown method {name!r} (available: {', '.join(sorted(REGISTRY))})") from None
