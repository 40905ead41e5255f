"""Exact harmonics of a structure's steady orbit (outputs: harmonics; issue 32): one replay of the orbit by the
exact flow (period.advance) from its state at the section, every step integrated against e^{-i k w t} in closed
form (fourier.py). Compiled only where a run asks for the output.

Coefficients are one-sided, as harmonic balance writes a response (NLvib, pyHarm) and as the 1-DoF output is:

    x_i(t) = Re sum_{k=0}^{H} X_ik e^{i k w t},  X_i0 = (1/T') int x_i dt,  X_ik = (2/T') int x_i e^{-i k w t} dt

over the orbit's T' = orbit x 2 pi / w from the section (t = 0, the excitation's maximum), and likewise for
every contact's force lambda_j (the time histories' contact_force). Then |X_i1| is the first-harmonic amplitude
of mass i and -arg X_i1 its phase; Parseval: mean(x_i^2) = X_i0^2 + (1/2) sum_{k>=1} |X_ik|^2 (as H -> infinity,
for a period-1 orbit; an orbit of k > 1 periods has subharmonics w/k, 2w/k, ... besides these).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.settings import SET_STOP_TOL
from friction_sweep.kernels.structure.fourier import new_fourier
from friction_sweep.kernels.structure.period import CACHE, OK, advance
from friction_sweep.kernels.structure.steady import flow_size, point_forces, replay_start

#: replay statuses: the coefficients are written; the replay failed (budget, a mode that cannot be built)
REPLAYED, NOT_REPLAYED = 0, 1


@jit
def orbit_harmonics(Minv, K, C, W, F, cp, omega, settings, state, periods, out):
    """From state (steady.state_size's layout, at t = 0) over `periods` forcing periods: out[k, i] = X_ik for
    the masses i < n and out[k, n + j] the force of contact j (module docstring), k = 0..H (out: (H + 1,
    n + m) complex). REPLAYED, or NOT_REPLAYED (out NaN) where the replay failed."""
    n = K.shape[0]
    m = W.shape[0]
    N = flow_size(K, W, cp)
    T = 2.0 * np.pi / omega
    vtol = settings[SET_STOP_TOL]
    fou = new_fourier(n, m, out.shape[0] - 1, CACHE)
    out[:, :] = np.nan
    ok, z, st, cache, budget, J, jflag, harm, xmax, mc = replay_start(Minv, K, C, W, F, cp, omega, settings, state)
    if not ok:
        return NOT_REPLAYED
    for _ in range(periods):
        if advance(z, st, T, Minv, K, C, W, F, cp, omega, cache, vtol, budget, False, J, jflag, False, harm, xmax,
                   mc, fou) != OK:
            return NOT_REPLAYED
        # the forcing's phase back to exactly 0 at each section, as the steady search does
        z[N - 3] = 1.0
        z[N - 2] = 0.0
    sums = fou[0]
    span = periods * T
    for r in range(n + m):
        out[0, r] = sums[0, r].real / span
        for k in range(1, out.shape[0]):
            out[k, r] = 2.0 * sums[k, r] / span
    return REPLAYED


@jit
def harmonics_batch(Minv, K, C, W, F_cos, F_sin_per_w, cp0, omegas, scales, settings, states, orbits, out):
    """orbit_harmonics for each point p (frequency omegas[p], every friction times scales[p], as
    steady.solve_batch) from its orbit's state states[p] over orbits[p] periods into out[p]; a point with no
    orbit (orbits[p] <= 0) is NaN."""
    F = np.empty((2, K.shape[0]))
    cp = cp0.copy()
    for p in range(omegas.shape[0]):
        if orbits[p] <= 0:
            out[p, :, :] = np.nan
            continue
        point_forces(F_cos, F_sin_per_w, cp0, omegas[p], scales[p], F, cp)
        orbit_harmonics(Minv, K, C, W, F, cp, omegas[p], settings, states[p], orbits[p], out[p])
