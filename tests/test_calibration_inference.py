"""The calibration's posterior file is a full ArviZ InferenceData (issue 33, item 2): pointwise
log_likelihood (so az.loo, az.waic and az.compare run on it), prior draws, the rows' constant data,
sample_stats as ArviZ names them, the diagnostics once (on the parameters they describe), and the file's
own title, history and Conventions; `--quiet` prints no ArviZ FutureWarning.

Two cheap theory calibrations of one synthetic data set (a held-out series among them): the plain model
and the same with a constant phase offset.
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import warnings

import h5py
import numpy as np
import pytest
from calibration_synthetic import RATIOS, model_for
from click.testing import CliRunner
from conftest import ROOT
from scipy import stats

from friction_sweep.cli import main

pytestmark = pytest.mark.skipif(importlib.util.find_spec("emcee") is None, reason="the calibrate extra")

#: the synthetic rig: two series; 0.3 is held out (predicted, not fitted)
BETAS = (0.2, 0.3)
TRUE_SCALE, TRUE_NOISE_DEG = 1.1, 2.0
PLAIN = "  friction_scale: {log_normal: [1, 0.2]}\n  noise_phase: {half_normal: 3 deg}\n"
OFFSET = PLAIN + "  discrepancy_phase: {normal: [0 deg, 3 deg]}\n"
SAMPLER = ("sampler: {walkers: 16, seed: 0, autocorr_times: 10, min_ess: 50, max_steps: 400, check_every: 100, "
           "predictive_draws: 20}\n")


def write_rig(path):
    """Phases the theory model gives at friction_scale TRUE_SCALE (as calibration_synthetic makes its data),
    with von Mises noise of TRUE_NOISE_DEG."""
    rng = np.random.default_rng(7)
    r, beta = np.tile(RATIOS, len(BETAS)).tolist(), np.repeat(BETAS, len(RATIOS)).tolist()
    path.write_text("r,beta,phase\n" + "".join(f"{x!r},{b!r},0.0\n" for x, b in zip(r, beta, strict=True)))
    phase = model_for(path, "theory", PLAIN).predict(np.array([[TRUE_SCALE, TRUE_NOISE_DEG]]))["phase"][0]
    assert np.isfinite(phase).all()  # every row in continuous motion
    noisy = phase + np.degrees(rng.vonmises(0.0, 1.0 / np.radians(TRUE_NOISE_DEG) ** 2, size=phase.size))
    path.write_text("r,beta,phase\n" + "".join(f"{x!r},{b!r},{float(p)!r}\n" for x, b, p in zip(r, beta, noisy,
                                                                                                  strict=True)))
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """{name: the posterior.nc of the calibration with those parameters}."""
    folder = tmp_path_factory.mktemp("calibrations")
    csv = write_rig(folder / "rig.csv")
    out = {}
    for name, parameters in (("plain", PLAIN), ("offset", OFFSET)):
        spec = folder / f"{name}.yaml"
        spec.write_text(f"data:\n  file: {csv}\n  columns: {{frequency_ratio: r, force_ratio: beta, phase: phase}}\n"
                        f"  holdout: [0.3]\nscene: {{excitation: base}}\nmethod: theory\nparameters:\n{parameters}"
                        + SAMPLER)
        res = CliRunner().invoke(main, ["calibrate", str(spec), "-q", "-o", str(folder / name)])
        assert res.exit_code == 0, (res.output, res.exception)
        out[name] = folder / name / "posterior.nc"
    return out


def load(path):
    import arviz as az

    return az.from_netcdf(path, engine="h5netcdf")


def test_the_posterior_file_holds_every_group_arviz_expects(runs):
    idata = load(runs["plain"])
    assert {"posterior", "prior", "log_likelihood", "sample_stats", "observed_data", "constant_data",
            "posterior_predictive"} <= set(idata.groups())
    post, ll = idata.posterior, idata.log_likelihood
    # one pointwise value per sample and fitted row: the held-out series (0.3) is predicted, not fitted
    assert ll["phase"].dims == ("chain", "draw", "row")
    assert ll["phase"].shape == (post.sizes["chain"], post.sizes["draw"], len(RATIOS))
    assert idata.observed_data.sizes["row"] == 2 * len(RATIOS)
    np.testing.assert_array_equal(ll["row"].values, idata.constant_data["row"].values[idata.constant_data["fitted"] == 1])
    assert np.isfinite(ll["phase"].values).all()
    assert set(idata.sample_stats.data_vars) == {"lp", "acceptance_rate"}
    rate = idata.sample_stats["acceptance_rate"].values
    assert set(np.unique(rate)) <= {0.0, 1.0}
    assert rate.mean() == pytest.approx(idata.sample_stats.attrs["acceptance_fraction"], abs=0.1)


def test_lp_is_the_log_prior_plus_the_pointwise_log_likelihood(runs):
    """sample_stats.lp = log prior (scipy's densities) + the sum of log_likelihood over the fitted rows."""
    idata = load(runs["offset"])
    post = idata.posterior
    log_prior = (stats.lognorm(0.2, scale=1.0).logpdf(post["friction_scale"].values)
                 + stats.halfnorm(scale=3.0).logpdf(post["noise_phase"].values)
                 + stats.norm(0.0, 3.0).logpdf(post["discrepancy_phase"].values))
    total = log_prior + idata.log_likelihood["phase"].sum("row").values
    np.testing.assert_allclose(total, idata.sample_stats["lp"].values, rtol=1e-10, atol=1e-9)


def test_the_pointwise_log_likelihood_is_the_von_mises_of_each_row(runs):
    """A few samples recomputed: von Mises (scipy's) of each fitted row's measured lag about the forward
    model's lag plus the offset, concentration 1 / noise^2."""
    idata = load(runs["offset"])
    rows = idata.log_likelihood["row"].values
    fitted = np.isin(idata.constant_data["row"].values, rows)
    measured = idata.observed_data["phase"].sel(row=rows).values
    model = model_for(runs["offset"].parent.parent / "rig.csv", "theory", OFFSET)
    for chain, draw in ((0, 0), (3, 17), (15, -1)):
        sample = idata.posterior.isel(chain=chain, draw=draw)
        theta = np.array([[float(sample[name]) for name in model.names]])
        mu = np.radians(model.predict(theta)["phase"][0][fitted] + float(sample["discrepancy_phase"]))
        kappa = 1.0 / np.radians(float(sample["noise_phase"])) ** 2
        expected = stats.vonmises(kappa, loc=mu).logpdf(np.radians(measured))
        got = idata.log_likelihood["phase"].isel(chain=chain, draw=draw).values
        np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9)


def test_loo_waic_and_compare_run_on_the_calibrations(runs):
    import arviz as az

    plain, offset = load(runs["plain"]), load(runs["offset"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # a short test run's Pareto k and WAIC variance notes
        loo, waic = az.loo(plain), az.waic(plain)
        compared = az.compare({"plain": plain, "offset": offset})
    assert loo.n_data_points == len(RATIOS) and np.isfinite(loo.elpd_loo)
    assert np.isfinite(waic.elpd_waic)
    assert set(compared.index) == {"plain", "offset"} and compared["rank"].min() == 0
    # the truth has no offset: a model with one cannot predict the data much better
    assert compared.loc["offset", "elpd_loo"] <= compared.loc["plain", "elpd_loo"] + 2 * compared["dse"].max() + 1


def test_prior_draws_follow_the_priors(runs):
    prior = load(runs["plain"]).prior
    scale = prior["friction_scale"].values.ravel()
    assert prior["friction_scale"].shape[0] == 1 and scale.size >= 500
    assert stats.kstest(scale, stats.lognorm(0.2, scale=1.0).cdf).pvalue > 1e-3
    assert (prior["noise_phase"].values >= 0).all()
    assert prior["noise_phase"].attrs["units"] == "degree"


def test_constant_data_are_the_rows_of_the_data_file(runs):
    idata = load(runs["plain"])
    csv = np.loadtxt(runs["plain"].parent.parent / "rig.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(idata.constant_data["frequency_ratio"].values, csv[:, 0])
    np.testing.assert_array_equal(idata.constant_data["force_ratio"].values, csv[:, 1])
    np.testing.assert_array_equal(idata.constant_data["fitted"].values, (csv[:, 1] != 0.3).astype(np.int8))


def test_diagnostics_are_stored_once_on_the_parameters_and_the_file_says_what_it_is(runs):
    idata = load(runs["plain"])
    for name in ("friction_scale", "noise_phase"):
        attrs = idata.posterior[name].attrs
        assert {"autocorr_time", "effective_sample_size", "walker_rhat", "map", "units", "prior"} <= set(attrs)
    per_parameter = {"autocorr_time", "autocorr_time_names", "effective_sample_size", "walker_rhat", "map"}
    assert [(group, k) for group in idata.groups() for k in getattr(idata, group).attrs if k in per_parameter] == []
    with h5py.File(runs["plain"], "r") as f:
        root = dict(f.attrs)
        assert root["Conventions"] == "CF-1.10"
        assert "calibration" in root["title"] and "fsweep calibrate" in root["history"]
        assert "spec" in root and "autocorr_time" not in root
        for group in f:
            assert "spec" not in f[group].attrs, group  # the provenance once, at the root


def test_quiet_prints_no_arviz_future_warning(tmp_path, runs):
    """ArviZ 0.2x warns once a day (a stamp in the user's cache): a fresh cache makes it warn."""
    spec = runs["plain"].parent.parent / "plain.yaml"
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    probe = subprocess.run([sys.executable, "-c", "import arviz"], env=env, capture_output=True, text=True)
    assert "FutureWarning" in probe.stderr  # the warning this test is about is there to silence
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache2")
    res = subprocess.run([sys.executable, "-m", "friction_sweep", "calibrate", str(spec), "-q", "-o",
                          str(tmp_path / "out")], env=env, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr
    assert "Warning" not in res.stderr, res.stderr
