"""Issue 29 item 6: the example specs and the rig's data ship with the package and are named
`package:PATH` from the command line and from a spec, so that they work away from the repository
(the installed wheel itself: tests/test_installed_wheel.py)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import ROOT, in_dir, one_error_line

import friction_sweep as fs
from friction_sweep.calibration.data import read_observations
from friction_sweep.calibration.spec import data_path, load_calibration_spec
from friction_sweep.cli import main
from friction_sweep.packaged import resolve

PACKAGE = ROOT / "friction_sweep"
EXAMPLES = sorted(p.relative_to(ROOT / "configs") for p in (ROOT / "configs").rglob("*.yaml"))


@pytest.mark.parametrize("rel", EXAMPLES, ids=str)
def test_every_config_is_a_packaged_example(rel):
    path = resolve(f"package:examples/{rel.as_posix()}")
    assert path.is_relative_to(PACKAGE) and path.is_file()
    assert path.read_bytes() == (ROOT / "configs" / rel).read_bytes()


def test_the_rig_spec_copied_anywhere_still_finds_its_data(tmp_path):
    """Its data were named relative to configs/calibration/: a copy of the spec (or the spec read from an
    installed package) found no file."""
    spec = tmp_path / "elsewhere" / "rig.yaml"
    spec.parent.mkdir()
    shutil.copy(ROOT / "configs/calibration/rig.yaml", spec)
    obs = read_observations(load_calibration_spec(spec))
    assert obs.size == 36
    assert Path(obs.path).resolve() == (PACKAGE / "data/experiment_phase_fixed_wall.csv").resolve()


@pytest.mark.parametrize("name", ["rig.yaml", "rig_holdout.yaml"])
def test_the_packaged_calibration_specs_read_the_packaged_data(name):
    spec = load_calibration_spec(resolve(f"package:examples/calibration/{name}"))
    assert data_path(spec) == PACKAGE / "data/experiment_phase_fixed_wall.csv"


def test_calibrate_help_names_the_packaged_rig():
    res = CliRunner().invoke(main, ["calibrate", "--help"])
    assert res.exit_code == 0
    text = " ".join(res.output.split())
    assert "fsweep calibrate package:examples/calibration/rig.yaml" in text
    assert "package:data/experiment_phase_fixed_wall.csv" in text
    assert resolve("package:examples/calibration/rig.yaml").is_file()  # what the help names is there


def test_validate_a_packaged_spec_from_another_folder(tmp_path):
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["validate", "package:examples/demo.yaml"])
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith(f"{PACKAGE / 'examples' / 'demo.yaml'}: ok:")


def test_api_refuses_a_packaged_name_that_is_not_there():
    with pytest.raises(fs.FsweepError, match="no such file in the installed package"):
        fs.sweep("package:examples/no_such.yaml")


def test_validate_data_reads_packaged_data_by_name(tmp_path):
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["validate-data", "--data", "package:data/nope.csv"])
    line = one_error_line(res, 2)
    assert "'package:data/nope.csv': no such file in the installed package" in line
