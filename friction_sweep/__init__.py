"""friction_sweep: a 1-DoF mass-spring oscillator with Coulomb friction, swept over (r, beta).

Two ways to the same outputs: Den Hartog's closed-form theory (continuous motion only) and numerical
simulation with exact stick-slip (every regime). Layers, each importing only those before it:
catalogue, codes, ties, exits, errors, progress (what methods can do; stored codes; tie tolerances; exit
codes; the API's exception; the progress bar) · spec (units stripped in spec/quantities.py) · theory ·
kernels (numba) · storage (schema, cubes, atomic writes) · methods · bench, quicklook (fsweep plot's
drawings), measured (a rig's CSV) · batch (tiles, executors, checkpoint), calibration (fsweep calibrate) ·
api · cli, validation.

The Python API (friction_sweep.api): `sweep(path_or_dict)`, `sweep_yaml(text)`,
`open_cube(path)`, `peak(spec)` and `optimize(spec)` (the resonance peak and the friction minimising it),
`backbone(spec)` (amplitude and equivalent damping along the phase resonance) return xarray Datasets;
every refusal is a `FsweepError`. They are loaded on first use, so that
`import friction_sweep` (and the CLI) stays cheap.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version
from typing import Any

try:  # pyproject.toml's, the one place the version is written
    __version__ = version("friction_sweep")
except PackageNotFoundError:  # a source tree on the path but never installed
    __version__ = "0+unknown"

_API = ("sweep", "sweep_yaml", "open_cube", "peak", "optimize", "backbone")
__all__ = [*_API, "FsweepError", "SpecError", "__version__"]


def __getattr__(name: str) -> Any:
    if name in _API:
        from friction_sweep import api

        return getattr(api, name)
    if name == "FsweepError":
        from friction_sweep.errors import FsweepError

        return FsweepError
    if name == "SpecError":
        from friction_sweep.spec.errors import SpecError

        return SpecError
    raise AttributeError(f"module 'friction_sweep' has no attribute {name!r}")
