"""The Makefile's targets a user runs write under results/ (and figures/out/) only: following the docs
never dirties the work tree (issue 29: `make calibrate` used to rewrite the tracked README). Only the
maintainers' `refresh-readme` publishes measured tables into tracked files."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest
from conftest import ROOT

USER_TARGETS = ["demo", "bench", "bench-quick", "calibrate", "cubes", "figures-quick", "validate"]
#: what refresh-readme publishes, and the scripts that would write it
PUBLISHED = ["README.md", "friction_sweep/bench/calibration.json"]


def _dry_run(target: str) -> str:
    if shutil.which("make") is None:
        pytest.skip("make is not installed")
    res = subprocess.run(["make", "-n", "-B", target], cwd=ROOT, capture_output=True, text=True, check=False)
    assert res.returncode == 0, res.stderr
    return res.stdout


@pytest.mark.parametrize("target", USER_TARGETS)
def test_a_user_target_names_no_tracked_file_to_write(target):
    recipe = _dry_run(target)
    for path in PUBLISHED:
        assert path not in recipe, f"make {target} writes {path}:\n{recipe}"
    assert "readme_tables.py" not in recipe


def test_the_scripts_user_targets_run_do_not_write_the_readme():
    """The README is written by benchmarks/readme_tables.py alone (which only refresh-readme runs)."""
    for script in (ROOT / "benchmarks").glob("*.py"):
        if script.name == "readme_tables.py":
            continue
        code = script.read_text()
        assert not re.search(r"""["']README\.md["']""", code), f"{script.name} names README.md"


def test_refresh_readme_publishes_what_bench_and_calibrate_measured():
    recipe = _dry_run("refresh-readme")
    assert "cp results/bench/calibration.json friction_sweep/bench/calibration.json" in recipe
    assert "readme_tables.py" in recipe


def test_durations_are_stated_once_and_as_measured():
    """Issue 29 item 8: "about 35 s" for figures-quick (290 s under load), and test-fast's "under a minute" in
    the Makefile's help, its comment and the README. A duration lives in the README, measured (CPU time,
    named so), or the command prints its own estimate (fsweep bench, fsweep run and validate)."""
    duration = re.compile(r"\b(\d+(\.\d+)?\s*|(a|half a)\s+)(s|sec|seconds?|min|minutes?)\b")
    for name in ("Makefile", "figures.mk"):
        assert not duration.search((ROOT / name).read_text()), name
    readme = (ROOT / "README.md").read_text()
    figures = readme[readme.index("`make figures-quick` draws"):]
    figures = figures[:figures.index("\n\n")]
    assert "CPU time" in figures and "fsweep validate SPEC" in figures
