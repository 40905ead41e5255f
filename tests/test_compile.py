"""The first run on a machine: numba compiles the kernels a run calls, and only those, and the run says so
while it does; the next run finds them cached and says nothing of it. Structural checks (which kernels
numba compiled, read off its cache's index files), never a clock."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from friction_sweep.batch import estimate, kernel_cache
from friction_sweep.cli import main

SPEC = """\
scene: {excitation: base}
grid:
  frequency_ratio: [0.5, 1.5]
  force_ratio: [0.1, 0.4]
method: event
outputs: [transmissibility, regime]
"""


def _run(spec: Path, out: Path, cache: Path) -> subprocess.CompletedProcess:
    code = "import sys; from friction_sweep.cli import main; sys.exit(main(sys.argv[1:]))"
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_DISABLE_JIT"}
    return subprocess.run([sys.executable, "-c", code, "run", str(spec), "-o", str(out), "--overwrite"],
                          capture_output=True, text=True, check=False, env={**env, "NUMBA_CACHE_DIR": str(cache)})


def _compiled_functions(cache: Path) -> set[str]:
    """`module.function` of every kernel numba compiled into `cache` (one index file each)."""
    return {index.name.split("-")[0] for index in cache.rglob("*.nbi")}


@pytest.mark.slow
def test_a_cold_run_says_it_compiles_and_compiles_only_what_the_spec_uses(tmp_path, monkeypatch):
    """A rigid event run without time histories compiles neither the RK4 integrator, nor the Jenkins
    contact's kernels, nor the sampling of time histories; its kernels are cached for the event
    integrator only (an rk4 run of the same scene would still compile)."""
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC)
    cache = tmp_path / "cache"
    cold = _run(spec, tmp_path / "a.h5", cache)
    assert cold.returncode == 0, cold.stderr
    assert estimate.COMPILING in cold.stderr
    assert "compiling the simulation kernels (first run)" in cold.stderr  # the estimate counts it
    compiled = _compiled_functions(cache)
    assert "steady.solve_points" in compiled and "event.advance_period" in compiled
    assert not {name for name in compiled if name.startswith(("rk4.", "jenkins"))}, compiled
    assert "event._sample" not in compiled
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(cache))
    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    assert kernel_cache.warm("steady", "solve_points", ("none",))
    assert not kernel_cache.warm("steady", "solve_points", ("bool",))
    warm = _run(spec, tmp_path / "b.h5", cache)
    assert warm.returncode == 0, warm.stderr
    assert estimate.COMPILING not in warm.stderr
    assert "compiling" not in warm.stderr


def test_a_run_whose_kernels_are_not_cached_says_so_before_its_sweep(tmp_path, monkeypatch, compiled):
    """The compile gets its own line (the estimate's share of it too), before the sweep; quiet: nothing."""
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC)
    monkeypatch.setattr(kernel_cache, "warm", lambda *args: False)
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "a.h5")])
    assert res.exit_code == 0, res.output
    assert estimate.COMPILING in res.stderr
    assert res.stderr.index("estimate:") < res.stderr.index(estimate.COMPILING)
    quiet = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "b.h5"), "-q"])
    assert quiet.exit_code == 0 and estimate.COMPILING not in quiet.stderr


def test_a_run_whose_kernels_are_cached_says_nothing_of_compiling(tmp_path, monkeypatch, compiled):
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC)
    monkeypatch.setattr(kernel_cache, "warm", lambda *args: True)
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "a.h5")])
    assert res.exit_code == 0, res.output
    assert "compiling" not in res.stderr
