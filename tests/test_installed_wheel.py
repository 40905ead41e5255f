"""An installed (non-editable) wheel works on its own: the package data that an installed tool reads
(the `accuracy:` calibration, the rig's measured phases) travel in the wheel, and nothing reaches back
into the source tree. Builds a wheel, installs it into a clean venv and runs its `fsweep`."""

from __future__ import annotations

import os
import shutil
import signal
import site
import subprocess
import sys
import threading
import venv
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT

pytestmark = pytest.mark.slow

# what a build must not see or copy: environments, caches, results and earlier build trees
IGNORE = shutil.ignore_patterns(".git", ".venv", "build", "dist", "results", "*.egg-info", "__pycache__",
                                ".*_cache", ".hypothesis", "*.h5")

SPEC = """\
scene: {excitation: base}
grid: {frequency_ratio: [0.5, 2.0], force_ratio: [0.1]}
method: event
accuracy: 1e-4
output: out.h5
"""


def _run(args, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=600, **kwargs)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(venv folder, environment for its commands, a working folder outside the checkout)."""
    tmp = tmp_path_factory.mktemp("wheel")
    # build from a copy, so that setuptools writes its build/ and egg-info there, not into the checkout
    src = tmp / "src"
    shutil.copytree(ROOT, src, ignore=IGNORE)
    wheels = tmp / "wheels"
    res = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--disable-pip-version-check", "-w", wheels, src],
               cwd=tmp)
    if res.returncode != 0 and "No matching distribution found for setuptools" in res.stdout + res.stderr:
        pytest.skip("pip's isolated build could not fetch setuptools (no index reachable)")
    assert res.returncode == 0, res.stdout + res.stderr
    (wheel,) = wheels.glob("friction_sweep-*.whl")

    env_dir = tmp / "venv"
    venv.create(env_dir, with_pip=False)
    py = env_dir / "bin" / "python"
    purelib = _run([py, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], check=True).stdout.strip()
    # the dependencies from this interpreter's site-packages, without downloading. A path in a .pth is
    # only appended to sys.path (its own .pth files, the editable hook among them, are not run), and
    # after the venv's own site-packages, so the wheel's copy is the one imported.
    (Path(purelib) / "test_dependencies.pth").write_text("\n".join(site.getsitepackages()) + "\n")
    res = _run([sys.executable, "-m", "pip", "--python", py, "install", "--no-deps", "--no-index",
                "--disable-pip-version-check", wheel])
    assert res.returncode == 0, res.stdout + res.stderr

    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "NUMBA_DISABLE_JIT")}
    env["XDG_DATA_HOME"] = str(tmp / "xdg")  # no user calibration: `accuracy:` must use the packaged one
    work = tmp / "work"
    work.mkdir()
    return env_dir, env, work


def test_the_wheel_is_what_is_imported(installed):
    env_dir, env, work = installed
    code = ("import friction_sweep; from friction_sweep.bench import workprecision as wp; "
            "print(friction_sweep.__file__); print(wp.calibration_path())")
    res = _run([env_dir / "bin" / "python", "-c", code], cwd=work, env=env)
    assert res.returncode == 0, res.stderr
    module, calibration = map(Path, res.stdout.split())
    assert module.is_relative_to(env_dir) and not module.is_relative_to(ROOT)
    assert calibration.is_relative_to(env_dir) and calibration.is_file()  # the packaged calibration


def test_installed_fsweep_runs_an_accuracy_spec(installed):
    env_dir, env, work = installed
    (work / "spec.yaml").write_text(SPEC)
    res = _run([env_dir / "bin" / "fsweep", "run", "spec.yaml", "-o", "out.h5"], cwd=work, env=env)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "accuracy 0.0001:" in res.stderr  # the calibration was found and used
    with xr.open_dataset(work / "out.h5", engine="h5netcdf") as ds:
        assert ds.attrs["accuracy_requested"] == 1e-4
        assert np.isfinite(ds["transmissibility"].values).all()


def test_installed_validate_data_uses_the_packaged_data(installed):
    env_dir, env, work = installed
    res = _run([env_dir / "bin" / "fsweep", "validate-data", "-o", "validation"], cwd=work, env=env)
    assert res.returncode == 0, res.stdout + res.stderr
    first = res.stdout.splitlines()[0]
    assert first.startswith("measured data: ") and "(36 points" in first
    data = Path(first.removeprefix("measured data: ").split(" (")[0])
    assert data.is_relative_to(env_dir) and data.name == "experiment_phase_fixed_wall.csv"
    assert (work / "validation" / "table.csv").is_file()


def test_installed_validate_reads_a_packaged_example(installed):
    """Issue 29 item 6: the example specs travel in the wheel, named package:examples/..."""
    env_dir, env, work = installed
    res = _run([env_dir / "bin" / "fsweep", "validate", "package:examples/demo.yaml"], cwd=work, env=env)
    assert res.returncode == 0, res.stdout + res.stderr
    spec = Path(res.stdout.split(": ok:")[0])
    assert spec.is_relative_to(env_dir) and spec.name == "demo.yaml"
    # every spec of configs/, at whatever depth (the package data's globs must reach it)
    shipped = {p.relative_to(spec.parent).as_posix() for p in spec.parent.rglob("*.yaml")}
    assert shipped == {p.relative_to(ROOT / "configs").as_posix() for p in (ROOT / "configs").rglob("*.yaml")}


def test_installed_calibrate_starts_on_the_packaged_rig(installed):
    """Issue 29 item 6: `fsweep calibrate` on the rig example from a plain install, away from the repository:
    the spec and its data come from the package. Stopped (SIGTERM) once it has read both, loaded the
    model and estimated its time: the sampling itself takes minutes and is tested in test_calibration."""
    env_dir, env, work = installed
    proc = subprocess.Popen([str(env_dir / "bin" / "fsweep"), "calibrate", "package:examples/calibration/rig.yaml",
                             "-q"], cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    watchdog = threading.Timer(600, proc.kill)
    watchdog.start()
    try:
        lines = []
        for line in proc.stdout:  # click.echo flushes every line
            lines.append(line)
            if line.startswith("estimate:"):
                break
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate()
    finally:
        watchdog.cancel()
    assert lines and lines[-1].startswith("estimate:"), "".join(lines) + err
    data = env_dir.glob("lib/python*/site-packages/friction_sweep/data/experiment_phase_fixed_wall.csv")
    assert f"from 36 rows of {next(data)} " in lines[0], lines[0]
    assert not (work / "results" / "calibration").exists()  # stopped before anything was written


def test_installed_metadata_declares_licence_platform_and_types(installed):
    """Issue 33 item 5: the wheel's own metadata (what pip and PyPI show), and its py.typed."""
    env_dir, env, work = installed
    code = ("import importlib.metadata as m, json, friction_sweep, pathlib\n"
            "meta = m.metadata('friction_sweep')\n"
            "print(json.dumps({'licence': meta['License-Expression'], 'classifiers': meta.get_all('Classifier'),\n"
            "                  'version': friction_sweep.__version__, 'files': [str(f) for f in m.files('friction_sweep')],\n"
            "                  'typed': (pathlib.Path(friction_sweep.__file__).parent / 'py.typed').is_file()}))\n")
    res = _run([env_dir / "bin" / "python", "-c", code], cwd=work, env=env)
    assert res.returncode == 0, res.stderr
    import json
    import tomllib

    got = json.loads(res.stdout)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert got["licence"] == "MIT" and got["version"] == project["version"] and got["typed"]
    assert "Operating System :: POSIX :: Linux" in got["classifiers"]
    assert any(f.endswith("licenses/LICENSE") for f in got["files"]), got["files"]
