"""The stroboscopic (period) map P: one forcing period with the integrator the settings choose.

P takes the state (q, v, mode) at forcing phase 0 to the state one period T = 2 pi / r later. The
event kernel (event.py) computes it exactly between events, the RK4 kernel (rk4.py) on a fixed grid;
both fill the same accumulator record (measure.py). P^k, its own error and the mode of a state at
rest live here too, for the march (steady.py) and the shooting solve (shoot.py).

Which integrator is a compile-time choice: every function that integrates takes `rk4`, None for the
event kernel and True for RK4 (integrator(settings)). numba prunes the branch of the other one before
it types it (a test on None of an argument's type), so a run compiles only the integrator it uses: the
RK4 kernel is a fifth of the event run's compile otherwise.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.event import advance_period
from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import ACC_JAC_OK, reset_accumulator
from friction_sweep.kernels.rk4 import advance_period_rk4
from friction_sweep.kernels.segments import TWO_PI
from friction_sweep.kernels.settings import KERNEL_RK4, SET_KERNEL, SET_STEPS_PER_PERIOD, SET_STOP_TOL
from friction_sweep.kernels.stick import decide

#: rounding of one period of the event map, relative to the orbit's size (measured: 5.5e-15 at
#: r = 1 +- 1e-10)
MAP_ROUNDING = 32.0 * 2.220446049250313e-16


def integrator(settings: np.ndarray) -> bool | None:
    """The `rk4` argument of the kernels for a settings record: None for the event kernel, True for RK4."""
    return True if settings[SET_KERNEL] == KERNEL_RK4 else None


@jit
def advance(q, v, mode, p, settings, budget, measure, acc, rk4):
    """One period with the integrator `rk4` chooses (a compile-time switch: cached kernels cannot take
    functions). Returns (q, v, mode, status, work)."""
    if rk4 is None:
        return advance_period(q, v, mode, p, settings[SET_STOP_TOL], budget, measure, acc, None, None, None)
    return advance_period_rk4(q, v, mode, p, int(settings[SET_STEPS_PER_PERIOD]), budget, measure, acc)


@jit
def period(q, v, mode, p, settings, budget, acc, rk4):
    """One unmeasured period into a fresh accumulator (the march's step)."""
    reset_accumulator(acc)
    return advance(q, v, mode, p, settings, budget, False, acc, rk4)


@jit
def mode_of(q, v, p):
    """The mode of a state at forcing phase 0: the direction of motion, or at rest what the force decides."""
    if v > 0.0:
        return 1
    if v < 0.0:
        return -1
    return decide(0.0, q, p.A, p.r, p.bs)


@jit
def map_k(q, v, k, p, settings, budget, measure, acc, rk4):
    """P^k(q, v): k periods from (q, v), measured together in `acc` if asked. Returns (q, v, status,
    work); acc's jac_ok vouches for the monodromy matrix only for k = 1."""
    reset_accumulator(acc)
    mode = mode_of(q, v, p)
    work = 0
    for _ in range(k):
        q, v, mode, st, w = advance(q, v, mode, p, settings, budget - work, measure, acc, rk4)
        work += w
        if st != 0:
            return q, v, st, work
    if k > 1:
        acc[ACC_JAC_OK] = 0.0
    return q, v, 0, work


@jit
def map_error(r, settings):
    """Relative error of one period of the map: rounding for the event kernel; for RK4 also its
    truncation over the period, (2 pi / r) h^4 / 120 with h = 2 pi / (r steps_per_period) in natural
    time (the RK4 map of the oscillator has its resonance detuned by about that much, so at r = 1
    it has a bounded orbit of size ~1e8 that the true system lacks)."""
    if settings[SET_KERNEL] != KERNEL_RK4:
        return MAP_ROUNDING
    h = TWO_PI / (r * settings[SET_STEPS_PER_PERIOD])
    return max(MAP_ROUNDING, TWO_PI / r * h ** 4 / 120.0)
