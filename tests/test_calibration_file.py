"""The user's calibration (`fsweep bench --calibrate`, read by `accuracy:` in specs) checked whole when read
(friction_sweep.bench.workprecision.read_calibration): a file that is not one is a one-line refusal naming
the file, the key and the reason, from `validate`, `run` and the API alike (issue 28, class 17: tracebacks)."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner
from conftest import in_dir

import friction_sweep as fs
from friction_sweep.bench import workprecision as wp
from friction_sweep.cli import main

SPEC = """\
scene: {excitation: base}
grid: {frequency_ratio: [0.5, 1.5], force_ratio: [0.3]}
method: event
accuracy: 1.0e-6
output: out.h5
"""
ROW = {"settings": {"stop_tol": 1e-12, "steady_tol": 1e-10}, "worst_error": 2e-8, "seconds_per_point": 8e-5}


def _with(**change):
    return json.dumps({"event": [{**ROW, **change}]})


BAD = {
    # name: (the file's text, what the message says after "calibration.json: ")
    "not JSON": ("{event: [", "not JSON (Expecting property name"),
    "empty": ("", "not JSON (Expecting value: line 1 column 1"),
    "a list": ("[1, 2]", "must be a JSON object of rows by method (got a list)"),
    "a string": ('"event"', "must be a JSON object of rows by method (got a string)"),
    "rows a string": ('{"event": "fast"}', "event: must be a list of rows (got a string)"),
    "a row a number": ('{"event": [3]}', "event[0]: must be an object with keys settings, worst_error"),
    "a key missing": (json.dumps({"event": [{"settings": {}, "worst_error": 1e-8}]}), "event[0]: must have exactly"),
    "worst_error a string": (_with(worst_error="small"), 'event[0].worst_error: must be a number >= 0, or null '
                             '(got "small")'),
    "worst_error NaN": (_with(worst_error=float("nan")), "event[0].worst_error: must be a number >= 0"),
    "worst_error negative": (_with(worst_error=-1), "event[0].worst_error: must be a number >= 0"),
    "worst_error true": (_with(worst_error=True), "event[0].worst_error: must be a number >= 0, or null (got true)"),
    "seconds a string": (_with(seconds_per_point="1 ms"), "event[0].seconds_per_point: must be a finite number"),
    "seconds infinite": (_with(seconds_per_point=float("inf")), "event[0].seconds_per_point: must be a finite"),
    "settings a list": (_with(settings=[1e-8]), "event[0].settings: must be an object"),
    "a setting a string": (_with(settings={"stop_tol": "1e-8"}), 'event[0].settings.stop_tol: must be a finite number'),
    "a setting 400 digits": ('{"event": [{"settings": {"max_periods": 1' + "0" * 400 + '}, "worst_error": 1e-9, '
                             '"seconds_per_point": 1e-5}]}', "event[0].settings.max_periods: must be a finite"),
    "an unknown setting": (_with(settings={"stop_tol": 1e-8, "speed": 11}), "event[0].settings.\"speed\": not a "
                           "setting of event"),
    "an unknown row": ('{"fastest": []}', '"fastest": unknown row name'),
    "not UTF-8": (b"\xff\xfe{}".decode("latin-1"), "not UTF-8 text"),
}


@pytest.fixture
def user_calibration(tmp_path, monkeypatch):
    """Where `accuracy:` looks first: $XDG_DATA_HOME/friction_sweep/calibration.json."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    path = wp.user_calibration()
    path.parent.mkdir(parents=True)
    return path


@pytest.mark.parametrize("name", list(BAD))
@pytest.mark.parametrize("command", ["validate", "run"])
def test_a_calibration_that_is_not_one_is_a_one_line_refusal(tmp_path, user_calibration, name, command):
    text, words = BAD[name]
    user_calibration.write_bytes(text.encode("latin-1") if name == "not UTF-8" else text.encode())
    (tmp_path / "spec.yaml").write_text(SPEC)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, [command, "spec.yaml", "-q"] if command == "run" else [command, "spec.yaml"])
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    assert res.exit_code == 2, res.output
    assert res.output.count("\n") == 1, res.output
    assert f"spec.yaml: accuracy: {user_calibration}: {words}" in res.output
    assert not (tmp_path / "out.h5").exists()


def test_the_api_raises_the_same_refusal(tmp_path, user_calibration):
    user_calibration.write_text("[]")
    with pytest.raises(fs.FsweepError, match="calibration.json: must be a JSON object"):
        fs.sweep_yaml(SPEC)


def test_a_good_user_calibration_is_read(tmp_path, user_calibration):
    """What the checks let through: a calibration `fsweep bench --calibrate` writes (the packaged one, with
    its infinite and null errors), and a user's with one row."""
    user_calibration.write_text(wp.PACKAGED_CALIBRATION.read_text())
    assert wp.read_calibration(user_calibration) == json.loads(wp.PACKAGED_CALIBRATION.read_text())
    user_calibration.write_text(_with())
    settings, row = wp.choose("event", 1e-6)
    assert settings == ROW["settings"] and row["worst_error"] == ROW["worst_error"]
