"""Exact Fourier integrals of a structure's orbit, step by step (outputs: harmonics; DESIGN §7).

On a step of the exact flow (period.advance) from z0 at time t0, of length s <= h (|A| h <= 1/2 in the
mode's scale: flow.STEP_RATE), the state is its Taylor polynomial to rounding, z(t0 + tau) = sum_{j<=KT}
zk_j tau^j / j!, zk_j = A^j z0 (the coefficients advance forms). So every row r of interest (a mass's x_i,
a contact's force lambda = L z) integrates against the harmonic k of the forcing in closed form:

    int_0^s r(t0 + tau) e^{-i k w (t0 + tau)} dtau = e^{-i k w t0} sum_j (r . zk_j) s^{j+1} m_j(k w s),
    m_j(x) = int_0^1 u^j / j! e^{-i x u} du,

with e^{-i k w t0} = (cos w t0 - i sin w t0)^k read from the state's forcing slots. Nothing divides by
(A - i k w) (singular at resonance, with an undamped mode, at k = 0); the truncation of the Taylor
polynomial is the flow's own (below rounding), and |e^{-i x u}| = 1 carries it unchanged.

The moments m_j(x), x = k w s (at most STEP_RATE k: w is among the rates a step is short against), each
by its stable recurrence:
- forward, m_j = (m_{j-1} - e^{-ix} / j!) / (i x), from m_0 = e^{-ix/2} sinc(x/2), where j < x
  (an error shrinks by j / x a step);
- backward, m_{j-1} = e^{-ix} / j! + i x m_j, where j >= x, from m_J = e^{-ix} sum_l (i x)^l / (J+l+1)!
  at J = KT + TAIL_START (used where x < KT: the series' ratio x / (J + l + 2) is below 1/2, no cancellation).
A full step's moments depend on (k w h) only: they are kept per mode slot and reused step after step.
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.structure.flow import INACTIVE, KT

#: the backward recurrence's start above the highest Taylor power (the tail series' ratio there)
TAIL_START = KT
#: the tail series' terms: its ratio is at most 1/2 (x <= KT + 1 < J / 2), so 60 reach 2^-60
_TAIL_TERMS = 60


@jit
def moments(x, out):
    """out[j] = m_j(x) = int_0^1 u^j / j! e^{-i x u} du for j < out.size (module docstring), x >= 0."""
    J1 = out.shape[0]
    if x == 0.0:
        f = 1.0
        for j in range(J1):
            f /= j + 1
            out[j] = f
        return
    e = cmath.exp(-1j * x)
    # forward where j < x (m_0 by the half-angle form, exact where x is a multiple of 2 pi)
    j0 = min(int(x), J1 - 1) if x >= 1.0 else -1
    if j0 >= 0:
        half = 0.5 * x
        out[0] = cmath.exp(-1j * half) * (math.sin(half) / half)
        fact = 1.0
        for j in range(1, j0 + 1):
            fact /= j
            out[j] = (out[j - 1] - e * fact) / (1j * x)
    if j0 >= J1 - 1:
        return
    # backward from the tail series at J, down to j0 + 1
    J = J1 - 1 + TAIL_START
    inv = 1.0
    for i in range(1, J + 2):
        inv /= i  # 1 / (J + 1)!
    acc = 0.0 + 0.0j
    term = inv + 0.0j
    for i in range(_TAIL_TERMS):
        acc += term
        term *= 1j * x / (J + i + 2)
        if abs(term) < 1e-18 * abs(acc):
            break
    mj = e * acc
    invf = inv * (J + 1)  # 1 / J!
    for j in range(J, j0 + 1, -1):
        mj = e * invf + 1j * x * mj  # m_{j-1}
        if j - 1 < J1:
            out[j - 1] = mj
        invf *= j  # 1 / (j-1)!


@jit
def new_fourier(n, m, H, slots):
    """The replay's accumulator and workspaces: sums (H + 1, n + m) complex (the integrals of x_1..x_n and of
    every contact's force against e^{-i k w t}), the full-step moments of each of the mode cache's `slots`
    (period.CACHE) (slots, H + 1, KT + 1) and the step length they were built for (NaN: none), a step's moments
    (H + 1, KT + 1), the rows' Taylor coefficients (n + m, KT + 1)."""
    return (np.zeros((H + 1, n + m), dtype=np.complex128), np.zeros((slots, H + 1, KT + 1), dtype=np.complex128),
            np.full(slots, np.nan), np.empty((H + 1, KT + 1), dtype=np.complex128), np.empty((n + m, KT + 1)))


@jit
def _fill(table, omega, s):
    """table[k, j] = s^{j+1} m_j(k omega s)."""
    H1 = table.shape[0]
    for k in range(H1):
        moments(k * omega * s, table[k])
        p = s
        for j in range(table.shape[1]):
            table[k, j] *= p
            p *= s


@jit
def fourier_step(fou, zk, s, full, mi, h, st, L, n, m, N, omega):
    """Add one step of the flow (Taylor coefficients zk of the state at its start, length s; a full step of
    mode slot mi, length h, where `full`) to fou's sums (module docstring)."""
    sums, slot_tab, slot_h, tab, rows = fou
    H1 = sums.shape[0]
    if full:
        if slot_h[mi] != h:
            _fill(slot_tab[mi], omega, h)
            slot_h[mi] = h
        table = slot_tab[mi]
    else:
        _fill(tab, omega, s)
        table = tab
    K1 = zk.shape[0]
    for j in range(K1):
        for i in range(n):
            rows[i, j] = zk[j, i]
        for c in range(m):
            acc = 0.0
            if st[c] != INACTIVE:
                for i in range(N):
                    acc += L[c, i] * zk[j, i]
            rows[n + c, j] = acc
    base = complex(zk[0, N - 3], -zk[0, N - 2])  # e^{-i w t0}
    ph = 1.0 + 0.0j
    for k in range(H1):
        for r in range(n + m):
            acc = 0.0 + 0.0j
            for j in range(K1):
                acc += rows[r, j] * table[k, j]
            sums[k, r] += ph * acc
        ph *= base
