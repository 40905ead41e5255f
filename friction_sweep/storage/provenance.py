"""What every result file records about how it was made."""

from __future__ import annotations

import datetime as _dt
import importlib.metadata as _md
import json
import platform
import sys

import friction_sweep

_DEPENDENCIES = ("numpy", "numba", "xarray", "scipy", "h5netcdf", "h5py")


def version(dist: str) -> str:
    """The installed version of the distribution `dist`, or "not installed"."""
    try:
        return _md.version(dist)
    except _md.PackageNotFoundError:
        return "not installed"


def utc_now() -> str:
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat().replace("+00:00", "Z")


def history_line(command: str) -> str:
    return f"{utc_now()}: {command} (friction_sweep {friction_sweep.__version__})"


def attributes(*, spec_text: str, spec_path: str, excitation: str, method: str, settings: dict) -> dict:
    """Global attributes: the spec text, versions and the method's settings (netCDF-safe types)."""
    attrs = {
        "spec": spec_text,
        "spec_path": spec_path,
        "excitation": excitation,
        "method": method,
        "method_settings": json.dumps(settings, sort_keys=True),
        "friction_sweep_version": friction_sweep.__version__,
        "python_version": platform.python_version(),
        "platform": sys.platform,
    }
    for dist in _DEPENDENCIES:
        attrs[f"{dist}_version"] = version(dist)
    return attrs
