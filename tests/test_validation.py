"""Validation against the measured phase lags of the fixed-wall rig (friction_sweep.validation).

The real data file ships with the package (friction_sweep/data); the parsing and command tests
also run on an excerpt written here.
"""

import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from friction_sweep import validation
from friction_sweep.validation import DEFAULT_DATA, read_measurements, validate, validate_data

needs_data = pytest.mark.skipif(not DEFAULT_DATA.exists(), reason=f"measured data not found at {DEFAULT_DATA}")

# Four rows of the measured file, with its comment lines and header.
EXCERPT = """\
# Measured phase lag between base and mass displacement, fixed-wall base excitation rig.
# natural angular frequency 19.5721 rad/s; spring force amplitude k*Y = 2.5 N.
force_ratio,friction_force_N,frequency_ratio_nominal,frequency_ratio,drive_omega_rad_s,phase_deg
0.5741,1.4353,0.65,0.6487,12.6964,46.4635
0.3920,0.9800,1.25,1.2525,24.5141,150.1044
# a comment between rows is skipped too
0.2650,0.6625,0.95,0.9409,18.4154,14.9335
0.0870,0.2175,1.85,1.8597,36.3982,169.8338
"""


@pytest.fixture
def excerpt(tmp_path):
    path = tmp_path / "excerpt.csv"
    path.write_text(EXCERPT)
    return path


@pytest.fixture(scope="module")
def result():
    if not DEFAULT_DATA.exists():
        pytest.skip(f"measured data not found at {DEFAULT_DATA}")
    return validate()


@needs_data
def test_the_data_parse_to_36_points_with_4_force_ratios():
    table = read_measurements()
    assert len(table) == 36
    assert sorted(table["force_ratio"].unique()) == [0.087, 0.265, 0.392, 0.5741]
    assert (table.groupby("force_ratio").size() == 9).all()
    # the measured frequency ratio is used, not the nominal one
    assert not np.allclose(table["frequency_ratio"], table["frequency_ratio_nominal"])
    assert table["phase_deg"].between(0, 180).all()


def test_comment_lines_are_skipped_and_the_path_is_overridable(excerpt):
    table = read_measurements(excerpt)
    assert len(table) == 4
    assert table["frequency_ratio"].tolist() == [0.6487, 1.2525, 0.9409, 1.8597]
    assert table["phase_deg"].dtype == float


def test_bad_data_files_are_refused(tmp_path):
    with pytest.raises(validation.DataError, match="cannot read"):
        read_measurements(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("force_ratio,frequency_ratio\n0.1,0.5\n")
    with pytest.raises(validation.DataError, match="phase_deg"):
        read_measurements(bad)
    bad.write_text("force_ratio,frequency_ratio,phase_deg\n0.1,abc,10\n")
    with pytest.raises(validation.DataError, match="frequency_ratio must be a finite number"):
        read_measurements(bad)


def test_theory_and_event_agree_where_the_theory_says_continuous(result):
    table, _ = result
    continuous = table["theory_regime"] == "continuous"
    assert continuous.sum() == 36  # every measured point lies in the continuous region (docs/equations.md §5)
    assert (table.loc[continuous, "event_regime"] == "continuous").all()
    for definition in ("phase", "peak_phase"):
        diff = (table.loc[continuous, f"theory_{definition}_deg"] - table.loc[continuous, f"event_{definition}_deg"])
        assert np.abs(diff).max() < 1e-6, definition


def test_summary_numbers(result):
    _, summary = result
    s = summary.set_index(["method", "definition"])
    assert (s["points"] == 36).all()
    # the first-harmonic phase (what the rig measures) is within a few degrees; the peak phase is not
    for method in ("theory", "event"):
        assert s.loc[(method, "phase"), "max_abs_deg"] < 6.0
        assert s.loc[(method, "phase"), "rms_deg"] < 3.0
        assert s.loc[(method, "peak_phase"), "max_abs_deg"] > 10.0
    assert math.isclose(s.loc[("theory", "phase"), "rms_deg"], s.loc[("event", "phase"), "rms_deg"], rel_tol=1e-9)


def test_errors_are_predicted_minus_measured(excerpt):
    table, summary = validate(excerpt)
    err = table["theory_phase_error_deg"]
    np.testing.assert_allclose(err, table["theory_phase_deg"] - table["phase_deg"], atol=1e-12)
    row = summary.set_index(["method", "definition"]).loc[("theory", "phase")]
    assert row["max_abs_deg"] == pytest.approx(np.abs(err).max())
    assert row["rms_deg"] == pytest.approx(np.sqrt(np.mean(err**2)))


def test_command_writes_the_three_files(excerpt, tmp_path):
    out = tmp_path / "validation"
    res = CliRunner().invoke(validate_data, ["--data", str(excerpt), "-o", str(out)])
    assert res.exit_code == 0, res.output
    for name in validation.OUTPUT_FILES:
        assert (out / name).stat().st_size > 0, name
    assert (out / "phase_measured_vs_predicted.png").read_bytes().startswith(b"\x89PNG")
    table = pd.read_csv(out / "table.csv")
    assert len(table) == 4 and "event_peak_phase_error_deg" in table
    md = (out / "table.md").read_text()
    assert "## Summary" in md and md.count("\n| 0.") == 4
    assert "summary" in res.output and "RMS" in res.output


@needs_data
def test_command_default_data(tmp_path):
    res = CliRunner().invoke(validate_data, ["-o", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert "36 points" in res.output
    assert len(pd.read_csv(tmp_path / "table.csv")) == 36


def test_command_refuses_missing_data(tmp_path):
    res = CliRunner().invoke(validate_data, ["--data", str(tmp_path / "nope.csv"), "-o", str(tmp_path / "v")])
    assert res.exit_code == 2
    assert "cannot read the measured data" in res.output
    assert not (tmp_path / "v").exists()
