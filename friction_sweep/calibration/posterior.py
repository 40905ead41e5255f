"""The posterior of a calibration: priors times the likelihood of the measured rows.

Phases are angles, so their likelihood is circular: the measured lag phi_i given the model's mu_i (plus the
discrepancy offset delta) is von Mises with concentration kappa_i = 1 / sigma_i^2 (sigma in radians),

    log p(phi_i) = kappa_i (cos(phi_i - mu_i - delta) - 1) - log(2 pi I0e(kappa_i)),

which for small residuals is the Gaussian of sd sigma_i and never sees a wrap-around at +-180 degrees;
sigma_i^2 = noise_phase^2 + (the row's uncertainty)^2. Transmissibilities are positive ratios: log T_i is
Gaussian about log of the model's, sd^2 = noise_transmissibility^2 + (the row's uncertainty of log T)^2.

Where the model gives no value (theory off continuous motion, an unbounded or unsettled point) the
likelihood is zero: the parameters cannot have produced what was measured.

Across resonance the first-harmonic lag jumps from about phi to 180 - phi (Coulomb damping is no
damping at the natural frequency), so the likelihood is discontinuous in the natural frequency wherever a
measured row's r crosses 1: as f_n passes a row's drive frequency, that row's predicted lag flips to the
other side. Between two such crossings it is smooth (fit.py fits each such interval on its own); the
sampler needs no smoothness.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from .model import ForwardModel

#: a row whose model value is missing counts in the least-squares residuals as this many sd's beyond the
#: worst misfit the row can have (a phase 180 degrees off: 2/sigma; a transmissibility off by e^5): worse
#: than any value, yet finite, so that the search can leave the region
MISSING_BEYOND = 10.0
MISSING_LOG_T = 5.0


class Posterior:
    """log prior, log likelihood and their sum for parameter vectors (rows of a 2-D array)."""

    def __init__(self, model: ForwardModel):
        self.model = model
        self.rows = model.obs.fitted  # the likelihood's rows: held-out rows are predicted, not fitted

    def log_prior(self, theta: np.ndarray) -> np.ndarray:
        theta = np.atleast_2d(theta)
        total = np.zeros(theta.shape[0])
        for i, p in enumerate(self.model.parameters):
            total += p.prior.logpdf(theta[:, i])
        return total

    def phase_sd(self, theta: np.ndarray) -> np.ndarray:
        """sd of each row's phase (degrees): (n_vectors, n_rows)."""
        return self.sd(theta, "phase")

    def sd(self, theta: np.ndarray, measured: str) -> np.ndarray:
        """sd of each row's measured quantity (phase: degrees; transmissibility: of log T), the noise
        level and the row's own uncertainty added in quadrature: (n_vectors, n_rows)."""
        obs = self.model.obs
        noise = self.model.column(theta, f"noise_{measured}")
        var = np.zeros((theta.shape[0], obs.size))
        if noise is not None:
            var += noise[:, None] ** 2
        row = getattr(obs, f"{measured}_sd")
        if row is not None:
            var += row[None, :] ** 2
        return np.sqrt(var)

    def offset(self, theta: np.ndarray) -> np.ndarray:
        delta = self.model.column(theta, "discrepancy_phase")
        return np.zeros(theta.shape[0]) if delta is None else delta

    def pointwise_terms(self, theta: np.ndarray, predicted: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """log p of every row, per measured quantity (obs.measured: the von Mises of the phase, the
        Gaussian of log T): {quantity: (n_vectors, n_rows)}; -inf where the model gives no value."""
        theta = np.atleast_2d(theta)
        obs = self.model.obs
        terms = {}
        # a zero sd (a noise level of 0 with no row uncertainty: the edge of its prior) has no density; it
        # and a missing model value come out as inf or NaN here, and as -inf below, without warnings
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            if obs.phase is not None:
                sd = np.radians(self.phase_sd(theta))
                kappa = 1.0 / sd**2
                d = np.radians(obs.phase[None, :] - predicted["phase"] - self.offset(theta)[:, None])
                terms["phase"] = kappa * (np.cos(d) - 1.0) - np.log(2.0 * np.pi * special.i0e(kappa))
            if obs.transmissibility is not None:
                sd = self.sd(theta, "transmissibility")
                z = (np.log(obs.transmissibility)[None, :] - np.log(predicted["transmissibility"])) / sd
                terms["transmissibility"] = -0.5 * z**2 - np.log(sd * np.sqrt(2.0 * np.pi))
        return {name: np.where(np.isfinite(t), t, -np.inf) for name, t in terms.items()}

    def pointwise(self, theta: np.ndarray, predicted: dict[str, np.ndarray]) -> np.ndarray:
        """log p of every row (summed over the measured quantities): (n_vectors, n_rows); -inf where the
        model gives no value."""
        return self._summed(self.pointwise_terms(theta, predicted), np.atleast_2d(theta).shape[0])

    def _summed(self, terms: dict[str, np.ndarray], n: int) -> np.ndarray:
        total = np.zeros((n, self.model.obs.size))
        for term in terms.values():
            total += term
        return total

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        """log posterior (unnormalised) of each row of theta: what the sampler draws from."""
        return self.evaluate(theta)[0]

    def evaluate(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(log posterior (n_vectors,), the fitted rows' log likelihood per quantity (n_vectors, quantities,
        fitted rows)): the second is ArviZ's pointwise log_likelihood of a sample (report.inference_data),
        NaN where the prior excludes the vector."""
        theta = np.atleast_2d(theta)
        lp = self.log_prior(theta)
        out = np.full(theta.shape[0], -np.inf)
        terms = np.full((theta.shape[0], len(self.model.obs.measured), int(self.rows.sum())), np.nan)
        inside = np.isfinite(lp)
        if inside.any():
            predicted = self.model.predict(theta[inside])
            pointwise = self.pointwise_terms(theta[inside], predicted)
            terms[inside] = np.stack([pointwise[name][:, self.rows] for name in self.model.obs.measured], axis=1)
            # summed as pointwise() sums (the reduction's order decides the last bits, and the sampler's path)
            out[inside] = lp[inside] + self._summed(pointwise, int(inside.sum()))[:, self.rows].sum(axis=1)
        return out, terms

    def residuals(self, theta: np.ndarray, predicted: dict[str, np.ndarray]) -> np.ndarray:
        """Least-squares residuals of one parameter vector: per fitted row and quantity, the signed
        sqrt(2 kappa (1 - cos d)) of the von Mises (the Gaussian (d / sigma) for small d) and (log T
        misfit) / sd; then each prior's term (priors.Prior.residual). Their squares sum to -2 log
        posterior up to terms in the noise levels alone (which fit.py profiles)."""
        theta = np.atleast_2d(theta)
        obs = self.model.obs
        parts = []
        if obs.phase is not None:
            sd = np.radians(self.phase_sd(theta)[0])
            d = np.radians(obs.phase - predicted["phase"][0] - self.offset(theta)[0])
            res = np.sign(np.sin(d)) * np.sqrt(2.0 * (1.0 - np.cos(d))) / sd
            parts.append(np.where(np.isfinite(res), res, 2.0 / sd + MISSING_BEYOND)[self.rows])
        if obs.transmissibility is not None:
            sd = self.sd(theta, "transmissibility")[0]
            res = (np.log(obs.transmissibility) - np.log(predicted["transmissibility"][0])) / sd
            parts.append(np.where(np.isfinite(res), res, MISSING_LOG_T / sd + MISSING_BEYOND)[self.rows])
        parts.append(np.array([p.prior.residual(float(theta[0, i])) for i, p in enumerate(self.model.parameters)]))
        return np.concatenate(parts)
