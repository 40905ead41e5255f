"""Stage two: posterior samples from emcee's ensemble sampler, run until its own diagnostics say enough.

The walkers start from the prior (draws at which the model explains the data at all: a finite
posterior), not from a tight ball at the MAP, so that a second mode the prior allows is not missed. The
moves are differential evolution (80 %) and its snooker variant (20 %), which jump between separated modes
better than the default stretch move: the natural frequency's posterior is cut into pieces where the
rows cross resonance (posterior.py).

Diagnostics valid for an ensemble sampler (the walkers are not independent chains, so per-chain R-hat
does not apply): emcee's integrated autocorrelation time tau of every parameter, over the walkers' mean
(Goodman & Weare 2010; Foreman-Mackey et al. 2013); the run's length in units of the largest tau; the
effective sample size walkers x kept steps / tau per parameter; the mean acceptance fraction. The run
goes on, check_every steps at a time, until the length is at least autocorr_times x tau and every
effective sample size at least min_ess (or max_steps: then the result says it did not converge). The first
quarter of the run is dropped as burn-in (at least BURN_TAUS x tau).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .posterior import Posterior

#: burn-in dropped: this share of the run, at least BURN_TAUS autocorrelation times of the slowest parameter
BURN_FRACTION = 0.25
BURN_TAUS = 5.0
#: prior draws per walker tried before giving up on finding the walkers a start the data allow
START_TRIES = 200


class NoLikelihood(ValueError):
    """Every draw of the prior gives the data zero likelihood: the prior and the data cannot agree."""


@dataclass
class Chains:
    samples: np.ndarray  # (walkers, kept steps, ndim) after burn-in
    log_posterior: np.ndarray  # (walkers, kept steps)
    tau: np.ndarray  # (ndim,) integrated autocorrelation time, steps
    steps: int  # total steps run
    burn: int
    acceptance: float  # mean acceptance fraction
    converged: bool
    seconds: float
    evaluations: int  # parameter vectors evaluated

    @property
    def ess(self) -> np.ndarray:
        return self.samples.shape[0] * self.samples.shape[1] / self.tau

    @property
    def length_in_tau(self) -> float:
        return self.steps / float(np.max(self.tau))


def start_from_prior(post: Posterior, walkers: int, rng: np.random.Generator) -> np.ndarray:
    """`walkers` prior draws with a finite posterior (NoLikelihood where none can be found)."""
    model = post.model
    found: list[np.ndarray] = []
    tried = 0
    while len(found) < walkers and tried < START_TRIES * walkers:
        batch = np.column_stack([p.prior.sample(rng, walkers) for p in model.parameters])
        tried += walkers
        lp = post(batch)
        found.extend(batch[np.isfinite(lp)])
    if len(found) < walkers:
        raise NoLikelihood(f"{len(found)} of {tried} draws of the prior give the data a nonzero likelihood "
                           f"(needed {walkers}): at almost every parameter the prior allows, the {model.method} "
                           "model has no value at some fitted row (theory: the motion sticks there; event: "
                           "unbounded or unsettled)")
    return np.asarray(found[:walkers])


def sample(post: Posterior, *, walkers: int, seed: int, autocorr_times: float, min_ess: int, max_steps: int,
           check_every: int, progress: Callable[[int, float | None], None] | None = None) -> Chains:
    """Run emcee until the diagnostics are met (module docstring)."""
    import emcee

    rng = np.random.default_rng(seed)
    start = start_from_prior(post, walkers, rng)
    ndim = start.shape[1]
    calls = [0]

    def log_prob(theta):
        calls[0] += theta.shape[0]
        return post(theta)

    sampler = emcee.EnsembleSampler(walkers, ndim, log_prob, vectorize=True,
                                    moves=[(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)])
    sampler._random = np.random.mtrand.RandomState(seed)  # emcee's own generator, seeded for reproducibility
    began = time.perf_counter()
    state = start
    steps = 0
    tau = np.full(ndim, np.inf)
    converged = False
    burn = 0
    previous = np.inf
    while steps < max_steps:
        n = min(check_every, max_steps - steps)
        state = sampler.run_mcmc(state, n, progress=False)
        steps += n
        # tau over the run's last three quarters (the first quarter is burn-in, which must span at least
        # BURN_TAUS tau); a run counts as converged only on an estimate that also held still since the
        # last check (emcee's own advice: an estimate from a run shorter than ~50 tau is biased low)
        burn = int(steps * BURN_FRACTION)
        tau = sampler.get_autocorr_time(tol=0, discard=burn)
        kept = steps - burn
        steady = abs(np.max(tau) - previous) <= 0.05 * np.max(tau)
        previous = float(np.max(tau))
        if progress is not None:
            progress(steps, previous)
        if steady and steps >= autocorr_times * previous and np.min(walkers * kept / tau) >= min_ess \
                and burn >= BURN_TAUS * previous:
            converged = True
            break
    chain = sampler.get_chain(discard=burn)  # (steps, walkers, ndim)
    lp = sampler.get_log_prob(discard=burn)
    return Chains(np.swapaxes(chain, 0, 1), lp.T, tau, steps, burn, float(np.mean(sampler.acceptance_fraction)),
                  converged, time.perf_counter() - began, calls[0])
