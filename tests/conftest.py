"""Shared test helpers: constants (taken from the package where it defines them), the small theory
spec most CLI tests run, and fixtures. Test modules import the constants with `from conftest import ...`
(pytest puts tests/ on sys.path, as it does for independent_integrator)."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from friction_sweep.catalogue import DEFAULT_OUTPUTS

ROOT = Path(__file__).resolve().parents[1]
#: what a spec computes when it names no outputs
OUTPUTS = DEFAULT_OUTPUTS
#: the static friction the two-state tests use (no package default: 1.0 means "no static friction")
STATIC = {"static_friction_ratio": 1.5}

#: run the CLI from a folder so that relative outputs land there
in_dir = contextlib.chdir

SMALL_SPEC = """\
scene:
  excitation: {excitation}
  effects: {{}}
grid:
  frequency_ratio: {{start: 0.2, stop: 3.0, num: 15}}
  force_ratio: [0.0, 0.3, 0.9]
method: theory
outputs: [transmissibility, phase, regime]
output: {output}
"""


def small_spec(excitation: str = "base", output: str = "out.h5") -> str:
    """A cheap theory spec (15 x 3 points)."""
    return SMALL_SPEC.format(excitation=excitation, output=output)


def write_spec(tmp_path: Path, excitation: str = "base", output: str = "out.h5", text: str | None = None) -> Path:
    """`text` (else the small spec) as tmp_path/spec.yaml."""
    path = tmp_path / "spec.yaml"
    path.write_text(text if text is not None else small_spec(excitation, output))
    return path


def one_error_line(res, code: int) -> str:
    """The refusal's single stderr line, after checking the exit code and that no traceback came."""
    assert res.exit_code == code, res.output
    assert isinstance(res.exception, SystemExit), res.exception  # not an uncaught error
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("fsweep: error: "), res.stderr
    assert "Traceback" not in res.output
    return lines[0]


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


@pytest.fixture
def no_matplotlib(monkeypatch):
    """matplotlib unimportable, as where the `figures` extra is not installed (even if another test
    imported it already)."""
    import importlib.util

    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a, **k: None if name.split(".")[0] == "matplotlib" else real(name, *a, **k))


@pytest.fixture(scope="session")
def compiled() -> None:
    """The event and rk4 kernels compiled once per session (loaded from numba's cache), so that no
    test's timing or deadline pays for compilation."""
    from friction_sweep import methods

    for name in ("event", "rk4"):
        methods.get(name).compute_tile("base", np.array([1.5]), np.array([0.1]), ("regime",))
