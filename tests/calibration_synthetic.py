"""Synthetic calibration problems: data made by the tool itself at parameters drawn from the prior, with
noise drawn from the likelihood's own distribution, and the sampler's 95 % intervals checked against the
truth. Where the truth is drawn from the prior and the posterior is sampled correctly, each interval
holds the truth in 95 % of the data sets (simulation-based calibration, Cook, Gelman & Rubin 2006; Talts et
al. 2018). A module of its own so that worker processes can import it."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from friction_sweep.calibration.data import read_observations
from friction_sweep.calibration.model import ForwardModel
from friction_sweep.calibration.posterior import Posterior
from friction_sweep.calibration.sampler import Targets, sample, start_from_prior
from friction_sweep.calibration.spec import parse_calibration_text

#: frequency ratios of the synthetic rig: both sides of resonance, in the continuous region of the priors
RATIOS = (0.7, 0.8, 0.9, 1.15, 1.3, 1.5, 1.7, 1.9)
#: the event model infers the natural frequency too: rows next to resonance (0.97, 1.03, about one prior
#: sd from it), so that the truth often puts a row on the other side than the prior's centre does and the
#: likelihood's jumps across resonance are part of what is checked
EVENT_RATIOS = (0.7, 0.85, 0.97, 1.03, 1.15, 1.4, 1.7, 1.9)
RATIOS_OF = {"theory": RATIOS, "event": EVENT_RATIOS}
#: the cheap sampler configuration CI affords (the full one is `make calibrate`'s)
WALKERS = 16
TARGETS = Targets(autocorr_times=20, min_ess=300)
SAMPLER = {"max_steps": 4000, "check_every": 100}

PARAMETERS = {
    "theory": "  friction_ratio: {uniform: [0.05, 0.45]}\n  noise_phase: {half_normal: 3 deg}\n",
    # the simulation's points are cheap, so the natural frequency (which moves every r) is inferred too
    "event": "  friction_ratio: {uniform: [0.05, 0.45]}\n  noise_phase: {half_normal: 3 deg}\n"
             "  natural_frequency: {normal: [1, 0.03]}\n",
}


def spec_text(csv: Path, method: str, parameters: str | None = None) -> str:
    return (f"data:\n  file: {csv}\n  columns: {{frequency_ratio: r, force_ratio: beta, phase: phase}}\n"
            f"scene: {{excitation: base}}\nmethod: {method}\nparameters:\n{parameters or PARAMETERS[method]}")


def write_data(path: Path, phases, beta: float = 0.2, ratios=RATIOS) -> Path:
    path.write_text("r,beta,phase\n" + "".join(f"{r!r},{beta!r},{float(p)!r}\n"
                                               for r, p in zip(ratios, phases, strict=True)))
    return path


def model_for(csv: Path, method: str, parameters: str | None = None) -> ForwardModel:
    spec = parse_calibration_text(spec_text(csv, method, parameters), source=str(csv.parent / "spec.yaml"))
    return ForwardModel(spec, read_observations(spec))


def one_data_set(method: str, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool] | None:
    """Data set k: (truth, 2.5 % and 97.5 % posterior quantiles, whether the run converged), or None where
    the truth drawn gives the model no value at some row (the prior there is truncated by the likelihood,
    for data and fit alike)."""
    rng = np.random.default_rng(1000 + k)
    ratios = RATIOS_OF[method]
    with tempfile.TemporaryDirectory() as folder:
        template = write_data(Path(folder) / "template.csv", np.zeros(len(ratios)), ratios=ratios)
        model = model_for(template, method)
        truth = np.array([p.prior.sample(rng, 1)[0] for p in model.parameters])
        phase = model.predict(truth[None, :])["phase"][0]
        if not np.isfinite(phase).all():
            return None
        sd = np.radians(truth[model.names.index("noise_phase")])
        measured = phase + np.degrees(rng.vonmises(0.0, 1.0 / sd**2, size=phase.size))
        fitted = model_for(write_data(Path(folder) / "data.csv", measured, ratios=ratios), method)
        post = Posterior(fitted)
        chains = sample(post, start_from_prior(post, WALKERS, rng), seed=k, targets=TARGETS, **SAMPLER)
    flat = chains.samples.reshape(-1, fitted.ndim)
    lo, hi = np.percentile(flat, [2.5, 97.5], axis=0)
    return truth, lo, hi, chains.converged
