"""Exact harmonics of a steady orbit (outputs: harmonics): one replay of the orbit with the event kernel,
every piece integrated against e^{-i k r t} in closed form (kernels/fourier.py). Compiled only where a run
asks for the output.

Coefficients are one-sided, as harmonic balance writes a response (NLvib, pyHarm):

    q(t) = Re sum_{k=0}^{H} Q_k e^{i k r t},   Q_0 = (1/T') int q dt,  Q_k = (2/T') int q e^{-i k r t} dt

over the orbit's T' = orbit x 2 pi / r from the kernel's section (the forcing's maximum), and likewise F_k
of the friction force. Then |Q_1 + c| is the first-harmonic transmissibility and Parseval reads
mean(q^2) = Q_0^2 + (1/2) sum_{k>=1} |Q_k|^2 (as H -> infinity, for a period-1 orbit; an orbit of k > 1
periods has subharmonics r/k, 2r/k, ... besides these).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.event import advance_period
from friction_sweep.kernels.fourier import HARM_F, HARM_Q
from friction_sweep.kernels.jenkins import JACC_SIZE, advance_period_jenkins
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import ACC_SIZE, BUDGET, reset_accumulator
from friction_sweep.kernels.point import JenkinsPoint, Point
from friction_sweep.kernels.segments import TWO_PI


@jit
def orbit_harmonics(q, v, mode, orbit, p, vtol, budget, harm):
    """Replay `orbit` periods from (q, v, mode) on the orbit and write the coefficients Q_k, F_k (module
    docstring) into harm[HARM_Q], harm[HARM_F] (shape (2, H + 1)). Returns BUDGET if the replay ran out of
    `budget` (harm is then NaN), else 0."""
    acc = np.empty(ACC_SIZE)
    harm[:, :] = 0.0
    work = 0
    for _ in range(orbit):
        reset_accumulator(acc)
        q, v, mode, st, w = advance_period(q, v, mode, p, vtol, budget - work, False, acc, None, None, None, harm)
        work += w
        if st == BUDGET or work > budget:
            harm[:, :] = np.nan
            return BUDGET
    _coefficients(harm, orbit * TWO_PI / p.r)
    return 0


@jit
def _coefficients(harm, span):
    """The integrals over the orbit's span into one-sided coefficients: 1/span for k = 0, 2/span above."""
    for row in (HARM_Q, HARM_F):
        harm[row, 0] = harm[row, 0].real / span
        for k in range(1, harm.shape[1]):
            harm[row, k] *= 2.0 / span


@jit
def orbit_harmonics_jenkins(q, v, w, mode, orbit, p, vtol, budget, harm):
    """orbit_harmonics for the Jenkins contact (kernels/jenkins.py): from (q, v, w, mode) on the orbit, the
    friction force being the contact spring's, kappa (q - w), while the slider sticks."""
    acc = np.empty(JACC_SIZE)
    harm[:, :] = 0.0
    anchor = np.nan  # labels only: the motion does not depend on it
    work = 0
    for _ in range(orbit):
        reset_accumulator(acc)
        q, v, w, mode, anchor, st, wk = advance_period_jenkins(q, v, w, mode, anchor, p, vtol, budget - work, False,
                                                               acc, None, None, None, harm)
        work += wk
        if st == BUDGET or work > budget:
            harm[:, :] = np.nan
            return BUDGET
    _coefficients(harm, orbit * TWO_PI / p.r)
    return 0


@jit
def harmonics_points(A, r, bk, bs, zeta, c, q, v, mode, orbit, vtol, budget, harm):
    """orbit_harmonics over 1-D arrays of points from their orbits' states (a solve's end_q, end_v,
    end_mode, orbit_period); harm has shape (n, 2, H + 1). A point with orbit 0 (no steady state) is NaN."""
    for i in range(r.size):
        if orbit[i] <= 0:
            harm[i, :, :] = np.nan
            continue
        orbit_harmonics(q[i], v[i], mode[i], orbit[i], Point(A[i], r[i], bk[i], bs[i], zeta[i], c[i]), vtol,
                        budget, harm[i])


@jit
def harmonics_points_jenkins(A, r, bk, bs, zeta, c, kappa, q, v, w, mode, orbit, vtol, budget, harm):
    """harmonics_points for the Jenkins contact, from its orbits' states (end_q, end_v, end_w, end_mode)."""
    for i in range(r.size):
        if orbit[i] <= 0 or np.isnan(w[i]):
            harm[i, :, :] = np.nan
            continue
        orbit_harmonics_jenkins(q[i], v[i], w[i], mode[i], orbit[i],
                                JenkinsPoint(A[i], r[i], bk[i], bs[i], zeta[i], c[i], kappa), vtol, budget, harm[i])
