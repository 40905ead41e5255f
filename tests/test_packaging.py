"""Issue 33 item 5: the package's metadata says what it is and where it runs (one version, an SPDX licence
with its file, the platform, its types), and the sdist holds what the README points to."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import tarfile
import tomllib
import venv

import pytest
from conftest import ROOT

import friction_sweep

PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
PACKAGE_DATA = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]


def test_the_version_is_written_once_in_pyproject():
    """It was written in pyproject.toml and again in friction_sweep/__init__.py."""
    for path in (ROOT / "friction_sweep").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "__version__" for t in node.targets):
                assert getattr(node.value, "value", None) != PROJECT["version"], f"{path}: the version again"
    assert "version" in PROJECT
    import importlib.metadata

    assert friction_sweep.__version__ == importlib.metadata.version("friction_sweep")


def test_the_licence_is_an_spdx_expression_with_its_file():
    assert PROJECT["license"] == "MIT"  # a string (PEP 639), not the deprecated {text = ...} table
    assert PROJECT["license-files"] == ["LICENSE"]
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License\n") and "Permission is hereby granted, free of charge" in text


def test_the_classifiers_declare_the_platform_and_the_types():
    classifiers = PROJECT["classifiers"]
    assert "Operating System :: POSIX :: Linux" in classifiers
    assert "Operating System :: OS Independent" not in classifiers  # the lock is flock(2)
    assert "Typing :: Typed" in classifiers
    assert (ROOT / "friction_sweep" / "py.typed").is_file() and "py.typed" in PACKAGE_DATA["friction_sweep"]
    assert f"Programming Language :: Python :: {PROJECT['requires-python'].removeprefix('>=')}" in classifiers


def test_without_posix_the_command_line_says_so_in_one_line(tmp_path):
    """Where fcntl is missing (Windows) `fsweep run` died with a traceback from the lock's import."""
    spec = tmp_path / "spec.yaml"
    spec.write_text("scene: {excitation: base}\ngrid: {frequency_ratio: [0.5], force_ratio: [0.1]}\nmethod: theory\n")
    code = ("import sys\nsys.modules['fcntl'] = None  # as on a system without it\n"
            "from friction_sweep.cli import main\nmain(['run', sys.argv[1], '-o', sys.argv[2]])\n")
    res = subprocess.run([sys.executable, "-c", code, str(spec), str(tmp_path / "out.nc")], capture_output=True,
                         text=True, env={**os.environ, "PYTHONPATH": str(ROOT)}, check=False)
    assert res.returncode == 1, res.stderr
    assert res.stderr.startswith("fsweep: error: fsweep needs a POSIX system (Linux, macOS)")
    assert len(res.stderr.splitlines()) == 1, res.stderr
    assert not (tmp_path / "out.nc").exists()


@pytest.mark.slow
def test_the_sdist_holds_what_the_readme_points_to(tmp_path):
    """configs/ and docs/ (the README's specs and pictures), the licence, and the package with its example
    specs as files (friction_sweep/examples is a link in the repository)."""
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    py = env_dir / "bin" / "python"
    res = subprocess.run([py, "-m", "pip", "install", "-q", "--disable-pip-version-check", "setuptools>=77", "wheel"],
                         capture_output=True, text=True, check=False)
    if res.returncode != 0:
        pytest.skip(f"setuptools>=77 could not be installed (no index reachable?): {res.stderr[-300:]}")
    code = "import sys\nfrom setuptools import build_meta\nprint(build_meta.build_sdist(sys.argv[1]))\n"
    res = subprocess.run([py, "-c", code, str(tmp_path / "dist")], cwd=ROOT, capture_output=True, text=True,
                         check=False)
    try:
        assert res.returncode == 0, res.stdout + res.stderr
        name = res.stdout.split()[-1]
        with tarfile.open(tmp_path / "dist" / name) as tar:
            members = {m.name.split("/", 1)[1]: m for m in tar.getmembers() if "/" in m.name}
    finally:  # setuptools writes its egg-info into the tree it builds from
        for egg in ROOT.glob("*.egg-info"):
            if egg.stat().st_mtime >= tmp_path.stat().st_mtime:
                subprocess.run(["rm", "-r", str(egg)], check=False)
    for rel in (p.relative_to(ROOT).as_posix() for p in (ROOT / "configs").rglob("*.yaml")):
        assert members[rel].isfile(), rel
        assert members[f"friction_sweep/examples/{rel.removeprefix('configs/')}"].isfile(), rel
    for rel in ("docs/equations.md", "docs/demo.png", "LICENSE", "README.md", "Makefile", "figures.mk",
                "friction_sweep/py.typed", "friction_sweep/data/experiment_phase_fixed_wall.csv"):
        assert members[rel].isfile(), rel
    assert not [n for n in members if n.endswith((".h5", ".nc", ".pyc"))]
