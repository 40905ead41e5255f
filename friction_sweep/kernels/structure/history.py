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
from friction_sweep.kernels.settings import SET_STOP_TOL, SET_WORK_BUDGET
from friction_sweep.kernels.structure.flow import INACTIVE
from friction_sweep.kernels.structure.period import MC_SIZE, OK, advance, lookup, new_cache
from friction_sweep.kernels.structure.steady import _section, _start, flow_size

#: replay statuses: the samples are written; the replay failed (budget, a mode that cannot be built)
SAMPLED, NOT_SAMPLED = 0, 1


@jit
def sample_orbit(Minv, K, C, W, F, cp, omega, settings, state, periods, samples, xs, lams):
    """From state (steady.state_size's layout, at t = 0), xs[p S + s] = x and lams[p S + s] = lambda at
    t = (p + s / S) T for p < periods, s < S = samples; SAMPLED, or NOT_SAMPLED where the replay failed."""
    n = K.shape[0]
    m = W.shape[0]
    N = flow_size(K, W, cp)
    Nd = N - 3
    T = 2.0 * np.pi / omega
    dt = T / samples
    vtol = settings[SET_STOP_TOL]
    budget = np.array([int(settings[SET_WORK_BUDGET])])
    cache = new_cache(n, m, N)
    A = np.empty((N, N))
    L = np.empty((max(m, 1), N))
    R = np.empty((N, N))
    J = np.zeros((N, Nd))
    jflag = np.ones(1)
    harm = np.zeros((n, 4))
    xmax = np.zeros(n)
    mc = np.zeros((max(m, 1), MC_SIZE))
    z = np.zeros(N)
    z[N - 3] = 1.0
    z[N - 1] = 1.0
    st = np.zeros(max(m, 1), dtype=np.int64)[:m]
    _start(z, st, state, W, cp, n, Nd)
    if not _section(z, st, Minv, K, C, W, F, cp, omega, vtol, A, L, R, budget, cache[-1]):
        return NOT_SAMPLED
    c_L = cache[3]
    c_ok = cache[8]
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
