"""Time histories of a structure's steady orbit (issue 31): every mass's displacement and every contact's
force, sampled uniformly over whole forcing periods from the orbit's state at the section (DESIGN §7).

The orbit is replayed by the same exact flow as the steady search (period.advance), one sample interval
T / S at a time, so the samples are the orbit's to rounding; a contact's force at a sample is its mode's
row, lambda_j = L_j . z (flow.build_mode: sigma mu slipping, k_t (u - p) for a stuck Jenkins slider, the
constraint force of a stuck rigid contact), 0 without friction.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.settings import SET_STOP_TOL
from friction_sweep.kernels.structure.flow import INACTIVE
from friction_sweep.kernels.structure.period import C_L, C_OK, OK, advance, lookup
from friction_sweep.kernels.structure.steady import flow_size, replay_start

#: replay statuses: the samples are written; the replay failed (budget, a mode that cannot be built)
SAMPLED, NOT_SAMPLED = 0, 1


@jit
def sample_orbit(Minv, K, C, W, F, cp, omega, settings, state, periods, samples, xs, lams):
    """From state (steady.state_size's layout, at t = 0), xs[p S + s] = x and lams[p S + s] = lambda at
    t = (p + s / S) T for p < periods, s < S = samples; SAMPLED, or NOT_SAMPLED where the replay failed."""
    n = K.shape[0]
    m = W.shape[0]
    N = flow_size(K, W, cp)
    dt = 2.0 * np.pi / omega / samples
    vtol = settings[SET_STOP_TOL]
    ok, z, st, cache, budget, J, jflag, harm, xmax, mc = replay_start(Minv, K, C, W, F, cp, omega, settings, state)
    if not ok:
        return NOT_SAMPLED
    c_L = cache[C_L]
    c_ok = cache[C_OK]
    for p in range(periods):
        for s in range(samples):
            row = p * samples + s
            mi = lookup(st, Minv, K, C, W, F, cp, omega, dt, cache)
            if not c_ok[mi]:
                return NOT_SAMPLED
            for i in range(n):
                xs[row, i] = z[i]
            for j in range(m):
                lam = 0.0
                if st[j] != INACTIVE:
                    for i in range(N):
                        lam += c_L[mi, j, i] * z[i]
                lams[row, j] = lam
            if advance(z, st, dt, Minv, K, C, W, F, cp, omega, cache, vtol, budget, False, J, jflag, False, harm,
                       xmax, mc, None) != OK:
                return NOT_SAMPLED
        # the forcing's phase back to exactly 0 at each section, as the steady search does
        z[N - 3] = 1.0
        z[N - 2] = 0.0
    return SAMPLED
