"""The performance curve's picture (fsweep optimize --plot, `make demo`; friction_sweep/design/performance_figure.py):
Den Hartog's prediction it draws against the exact peak where the peak's motion is continuous, and the
command's refusals before it computes."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.design import performance_figure as pf

SPEC = ("scene: {excitation: base}\ngrid: {frequency_ratio: {start: 0.05, stop: 3.0, num: 60}, "
        "force_ratio: [0.5, 0.8, 0.82, 0.9, 1.0, 1.1]}\nmethod: event\n")


def test_den_hartog_is_the_exact_peak_where_the_peak_is_continuous():
    """Undamped base scene: where the exact peak lies in continuous motion its value is Den Hartog's
    closed form's maximum (maximised on DH_POINTS ratios: to that grid's resolution, 1e-4 here); below
    pi/4 the exact peak is infinite."""
    beta = np.array([0.5, 0.79, 0.8, 0.81, 0.82])
    ds = fs.peak({"scene": {"excitation": "base"}, "grid": {"frequency_ratio": {"start": 0.05, "stop": 3.0,
                  "num": 60}, "force_ratio": beta}, "method": "event"})
    dh = pf.den_hartog_peaks("base", beta, 0.05, 3.0)
    assert np.isinf(ds.resonance_peak.values[0])
    continuous = ds.resonance_regime.values == Regime.CONTINUOUS
    assert continuous.sum() >= 2, ds.resonance_regime.values
    np.testing.assert_allclose(dh[continuous], ds.resonance_peak.values[continuous], rtol=1e-4)


def test_cli_optimize_plot_writes_the_picture(tmp_path):
    pytest.importorskip("matplotlib")
    spec = tmp_path / "s.yaml"
    spec.write_text(SPEC)
    png = tmp_path / "p.png"
    done = CliRunner().invoke(main, ["optimize", str(spec), "--plot", str(png)])
    assert done.exit_code == 0, done.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and f"wrote {png}" in done.output


def test_cli_optimize_plot_refuses_an_existing_picture_before_computing(tmp_path, monkeypatch):
    spec = tmp_path / "s.yaml"
    spec.write_text(SPEC)
    png = tmp_path / "p.png"
    png.write_bytes(b"mine")

    def never(*args, **kwargs):
        raise AssertionError("computed before refusing")

    monkeypatch.setattr(fs.api, "optimize", never)
    done = CliRunner().invoke(main, ["optimize", str(spec), "--plot", str(png)])
    assert done.exit_code == 2 and "exists" in done.output + (done.stderr or "")
    assert png.read_bytes() == b"mine"
