"""Stage two: posterior samples from emcee's ensemble sampler, run until its own diagnostics say enough.

The walkers start from the prior (draws at which the model explains the data at all: a finite
posterior), not from a tight ball at the MAP, so that a second mode the prior allows is not missed. The
moves are differential evolution (80 %) and its snooker variant (20 %), which jump between separated modes
better than the default stretch move: the natural frequency's posterior is cut into pieces where the
rows cross resonance (posterior.py).

Diagnostics valid for an ensemble sampler (the walkers are not independent chains, so the effective
sample size of independent chains does not apply): emcee's integrated autocorrelation time tau of every
parameter, from the walkers' autocorrelation functions averaged (Goodman & Weare 2010; Foreman-Mackey et
al. 2013); the kept run's length in units of the largest tau; the effective sample size walkers x kept
steps / tau per parameter; the mean acceptance fraction. tau cannot see walkers stuck apart in different
modes (each walker is centred on its own mean), so the walkers' split R-hat must agree too (WALKER_RHAT).
The run goes on, check_every steps at a time, until the kept run is at least autocorr_times x tau long,
every effective sample size at least min_ess and the R-hat below its bound (or max_steps: then the result
says it did not converge). The first quarter of the run is dropped as burn-in (at least BURN_TAUS x tau).

Each evaluation's pointwise log likelihood (every fitted row, per measured quantity) rides along as emcee's
blob, so the kept samples' log_likelihood (ArviZ's, for LOO and WAIC) costs no model evaluation: memory
of 8 bytes per step, walker and fitted row (36 rows, 32 walkers: 9 kB a step, 0.2 GB at 20000 steps).
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
#: walkers in groups that never cross show an R-hat above 1 (two groups 10 sd apart: 1.68) while tau and
#: the ESS, each walker's own, look fine; the ensemble's precision is tau's business, this only tells
#: whether the walkers agree
WALKER_RHAT = 1.05
#: prior draws per walker tried before giving up on finding the walkers a start the data allow
START_TRIES = 200


class NoLikelihood(ValueError):
    """Every draw of the prior gives the data zero likelihood: the prior and the data cannot agree."""


@dataclass
class Chains:
    samples: np.ndarray  # (walkers, kept steps, ndim) after burn-in
    log_posterior: np.ndarray  # (walkers, kept steps)
    tau: np.ndarray  # (ndim,) integrated autocorrelation time, steps
    rhat: np.ndarray  # (ndim,) split R-hat with the walkers as chains: walkers stuck apart show here
    steps: int  # total steps run
    burn: int
    acceptance: float  # mean acceptance fraction
    converged: bool
    seconds: float
    evaluations: int  # parameter vectors evaluated
    #: (walkers, kept steps, measured quantities, fitted rows): each sample's log likelihood per row, as the
    #: sampler computed it (emcee's blobs): ArviZ's log_likelihood group, for LOO and WAIC
    pointwise: np.ndarray
    #: (walkers, kept steps): whether the step's proposal was accepted (the walker moved)
    accepted: np.ndarray

    @property
    def ess(self) -> np.ndarray:
        return self.samples.shape[0] * self.samples.shape[1] / self.tau

    @property
    def length_in_tau(self) -> float:
        """The kept run (after burn-in), in autocorrelation times of the slowest parameter."""
        return self.samples.shape[1] / float(np.max(self.tau))


@dataclass(frozen=True)
class Targets:
    """What a run must meet to count as converged (the spec's sampler settings)."""

    autocorr_times: float
    min_ess: int


def diagnose(chain: np.ndarray, burn: int) -> tuple[np.ndarray, np.ndarray]:
    """(tau, rhat) per parameter of chain (steps, walkers, ndim) past `burn`: emcee's integrated
    autocorrelation time (the walkers' autocorrelation functions averaged, each about its own mean) and
    the split R-hat of the walkers as chains (ArviZ, rank-normalised). tau alone cannot see walkers that
    sit in different modes and never cross (each is centred on its own mean); R-hat compares them."""
    import emcee

    from .inference import import_arviz

    az = import_arviz()
    kept = chain[burn:]
    # a walker that has not moved in the kept window (early in a run) has no autocovariance: emcee divides
    # by it and gets NaN, and a NaN tau is no convergence (converged() is False), which is the answer
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = emcee.autocorr.integrated_time(kept, tol=0)
    rhat = np.array([float(az.rhat(np.ascontiguousarray(kept[:, :, i].T))) for i in range(kept.shape[2])])
    return tau, rhat


def converged(tau: np.ndarray, rhat: np.ndarray, kept: int, walkers: int, burn: int, targets: Targets) -> bool:
    """The kept run spans autocorr_times tau of every parameter, every ESS is at least min_ess, the
    burn-in spans BURN_TAUS tau, and no two groups of walkers disagree (R-hat <= WALKER_RHAT)."""
    slowest = float(np.max(tau))
    return (kept >= targets.autocorr_times * slowest and float(np.min(walkers * kept / tau)) >= targets.min_ess
            and burn >= BURN_TAUS * slowest and float(np.max(rhat)) <= WALKER_RHAT)


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
                           "unbounded or unsettled; either: the mass never leaves rest)")
    return np.asarray(found[:walkers])


def sample(post: Posterior, start: np.ndarray, *, seed: int, targets: Targets, max_steps: int, check_every: int,
           progress: Callable[[int, str], None] | None = None) -> Chains:
    """Run emcee from `start` (walkers x ndim, start_from_prior) until the targets are met (module
    docstring), or max_steps."""
    import emcee

    walkers, ndim = start.shape
    calls = [0]

    def log_prob(theta):
        calls[0] += theta.shape[0]
        lp, terms = post.evaluate(theta)
        # per walker (log posterior, blob): emcee keeps each accepted sample's pointwise log likelihood
        return list(zip(lp, terms.reshape(theta.shape[0], -1), strict=True))

    sampler = emcee.EnsembleSampler(walkers, ndim, log_prob, vectorize=True,
                                    moves=[(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)])
    sampler.random_state = np.random.RandomState(seed).get_state()  # emcee's own generator: reproducible
    began = time.perf_counter()
    state = start
    steps = 0
    ok = False
    previous = np.inf
    while steps < max_steps:
        n = min(check_every, max_steps - steps)
        # a proposal outside the prior or where the model has no value has log posterior -inf, which emcee
        # rejects by design; its arithmetic on it (-inf - -inf in a move's acceptance) would only warn
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            state = sampler.run_mcmc(state, n, progress=False)
        steps += n
        # the first quarter is burn-in; a run counts as converged only on a tau estimate that also held
        # still since the last check (emcee's advice: an estimate from a short run is biased low)
        burn = int(steps * BURN_FRACTION)
        tau, rhat = diagnose(sampler.get_chain(), burn)
        steady = abs(float(np.max(tau)) - previous) <= 0.05 * float(np.max(tau))
        previous = float(np.max(tau))
        if progress is not None:
            progress(n, f"tau ~ {previous:.0f}, R-hat {float(np.max(rhat)):.3f}")
        if steady and converged(tau, rhat, steps - burn, walkers, burn, targets):
            ok = True
            break
    whole = sampler.get_chain()  # (steps, walkers, ndim)
    chain = whole[burn:]
    lp = sampler.get_log_prob(discard=burn)
    # burn >= 1: a converged run's burn-in spans BURN_TAUS tau, an unconverged one is max_steps >= 100 long
    moved = np.any(whole[burn:] != whole[burn - 1:-1], axis=2)
    blobs = sampler.get_blobs(discard=burn)  # emcee squeezes axes of length 1: restore them
    kept, quantities, rows = chain.shape[0], len(post.model.obs.measured), int(post.rows.sum())
    pointwise = np.asarray(blobs, dtype=np.float64).reshape(kept, walkers, quantities, rows)
    return Chains(np.swapaxes(chain, 0, 1), lp.T, tau, rhat, steps, burn, float(np.mean(sampler.acceptance_fraction)),
                  ok, time.perf_counter() - began, calls[0], np.swapaxes(pointwise, 0, 1), moved.T)
