"""`fsweep validate` takes run's options and gives every refusal `fsweep run` with the same options would
give, before anything is computed (issue 29: validate said ok for an existing output that run refused)."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import in_dir

from friction_sweep.cli import main

SPEC = """\
scene: {excitation: base}
grid: {frequency_ratio: {start: 0.5, stop: 2.0, num: 40}, force_ratio: [0.1, 0.4]}
method: theory
output: out.h5
"""
HUGE = SPEC.replace("method: theory", "method: rk4\nsettings: {steps_per_period: 65536}").replace(
    "num: 40", "num: 200000")
#: issue 30: a structure spec (two masses, two contacts), and one of 20 masses in a chain, too large to run
#: without --yes
STRUCTURE = """\
scene: {excitation: force}
structure:
  masses: {blade: 1.0, damper: 0.1}
  springs: [[ground, blade, 1.0], [blade, damper, 2.0]]
  contacts: [{name: platform, between: [damper, ground], friction: 0.3}]
  forcing: {blade: 1.0}
grid: {frequency: [0.5, 1.0, 2.0], friction_scale: [0.5, 1.0]}
output: out.h5
"""
CHAIN = "".join(f", m{i}: 1" for i in range(1, 20))
HUGE_STRUCTURE = STRUCTURE.replace("damper: 0.1}", "damper: 0.1" + CHAIN + "}").replace(
    "[blade, damper, 2.0]]", "[blade, damper, 2.0], [damper, m1, 1]" + "".join(
        f", [m{i}, m{i + 1}, 1]" for i in range(1, 19)) + "]").replace(
    "[0.5, 1.0, 2.0]", "{start: 0.1, stop: 3.0, num: 100000}")


def _cube(d: Path) -> None:
    assert CliRunner().invoke(main, ["run", "spec.yaml", "-q"]).exit_code == 0


def _foreign_checkpoint(d: Path) -> None:
    part = d / ".out.h5.partial"
    part.mkdir()
    (part / "manifest.json").write_text('{"key": "another sweep", "tiles": 2}')
    (part / "tile-00000.npz").write_bytes(b"PK")


CASES = [
    ("existing output", SPEC, _cube, [], "exists; pass --overwrite"),
    ("--resume and --overwrite", SPEC, None, ["--resume", "--overwrite"], "not both"),
    ("--resume on a complete output", SPEC, _cube, ["--resume"], "nothing to resume"),
    ("a checkpoint of another sweep", SPEC, _foreign_checkpoint, [], "rm -r"),
    ("an empty scheduler address", SPEC, None, ["--scheduler", ""], "not a scheduler address"),
    ("a huge grid without --yes", HUGE, None, [], "pass --yes"),
    ("the output is the spec", SPEC, None, ["-o", "spec.yaml", "--overwrite"], "is the spec"),
    ("-j 0", SPEC, None, ["-j", "0"], "Invalid value for '-j'"),
    ("structure: an unknown mass", STRUCTURE.replace("[damper, ground]", "[dampr, ground]"), None, [],
     "structure.contacts[0].between[0]: 'dampr' is no mass"),
    ("structure: existing output", STRUCTURE, _cube, [], "exists; pass --overwrite"),
    ("structure: --resume on a complete output", STRUCTURE, _cube, ["--resume"], "nothing to resume"),
    ("structure: a checkpoint of another sweep", STRUCTURE, _foreign_checkpoint, [], "rm -r"),
    ("structure: a huge grid without --yes", HUGE_STRUCTURE, None, [], "pass --yes"),
]


@pytest.mark.parametrize("text, setup, flags, words", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_validate_refuses_what_run_refuses(tmp_path, text, setup, flags, words):
    (tmp_path / "spec.yaml").write_text(text)
    with in_dir(tmp_path):
        if setup is not None:
            setup(tmp_path)
        before = sorted(p.name for p in tmp_path.iterdir())
        checked = CliRunner().invoke(main, ["validate", "spec.yaml", *flags])
        assert sorted(p.name for p in tmp_path.iterdir()) == before  # validate writes nothing
        ran = CliRunner().invoke(main, ["run", "spec.yaml", "-q", *flags])
    assert ran.exit_code == 2 and words in ran.output, ran.output
    assert checked.exit_code == 2, checked.output
    said = checked.output.strip().splitlines()[-1].replace("fsweep validate --help", "fsweep run --help")
    assert said == ran.output.strip().splitlines()[-1]


def test_validate_prints_what_accuracy_chooses(tmp_path):
    (tmp_path / "spec.yaml").write_text(SPEC.replace("method: theory", "method: event\naccuracy: 1.0e-6"))
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["validate", "spec.yaml"])
    assert res.exit_code == 0, res.output
    assert "accuracy 1e-06: event with {" in res.output
    assert '"steady_tol": ' in res.output  # the settings line: every setting the cube will record


def test_validate_states_the_workers_run_would_start(tmp_path):
    (tmp_path / "spec.yaml").write_text(SPEC)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["validate", "spec.yaml", "-j", "8", "--executor", "threads"])
    assert res.exit_code == 0, res.output
    assert "(not 8:" in res.output
