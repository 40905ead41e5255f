"""What one forcing period reports besides its end state: the accumulator record and the status.

Both period integrators (event.py, rk4.py) add into one float array `acc`, whose slots are named in
ACC_FIELDS:
    ic, is          integrals of q cos(r t), q sin(r t) over the measured periods
    xmax, tmax      largest response x = q + c cos(r t) and its period-local time
    xmin            smallest response
    stuck, stops    time stuck, stick entries of positive duration
    events, qmax    velocity zeros, and the largest |q| at them (the orbit's size)
    jac11 .. jac22  the period map's monodromy matrix d(q, v)(T)/d(q, v)(0), row-major
    jac_ok          1 where that matrix is valid (event kernel, slip only)
    qlo, qhi        lowest and highest q at velocity zeros (with the period's ends: the orbit's range)
    slide           distance q slides over the measured periods: sum of |q(end) - q(start)| over slip
                    pieces, in which q is monotone (times the kinetic friction: the energy friction
                    dissipates, docs/equations.md §6 "Energy balance")
The first-harmonic integrals, the extremes and the sliding distance are gathered only on measured
periods; the rest always.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.codes import SteadyState
from friction_sweep.kernels.jit import jit

#: status of a period's advance: done, or out of work budget (the steady-state code it leads to)
OK = 0
BUDGET = SteadyState.EVENT_BUDGET

ACC_FIELDS = ("ic", "is", "xmax", "tmax", "xmin", "stuck", "stops", "events", "qmax",
              "jac11", "jac12", "jac21", "jac22", "jac_ok", "qlo", "qhi", "slide")
ACC = {name: i for i, name in enumerate(ACC_FIELDS)}
ACC_SIZE = len(ACC_FIELDS)
ACC_IC = ACC["ic"]
ACC_IS = ACC["is"]
ACC_XMAX = ACC["xmax"]
ACC_TMAX = ACC["tmax"]
ACC_XMIN = ACC["xmin"]
ACC_STUCK = ACC["stuck"]
ACC_STOPS = ACC["stops"]
ACC_EVENTS = ACC["events"]
ACC_QMAX = ACC["qmax"]
ACC_JAC = ACC["jac11"]  # the matrix's four slots follow in row-major order
ACC_JAC_OK = ACC["jac_ok"]
ACC_QLO = ACC["qlo"]
ACC_QHI = ACC["qhi"]
ACC_SLIDE = ACC["slide"]


def new_accumulator():
    """A fresh, reset accumulator (for callers from Python: tests)."""
    acc = np.zeros(ACC_SIZE)
    reset_accumulator(acc)
    return acc


@jit
def reset_accumulator(acc):
    acc[:] = 0.0  # jac_ok = 0: only the event kernel vouches for a monodromy matrix
    acc[ACC_XMAX] = -math.inf
    acc[ACC_XMIN] = math.inf
    acc[ACC_QLO] = math.inf
    acc[ACC_QHI] = -math.inf


@jit
def note_stop(acc, q):
    """Count a velocity zero at q: events, the orbit's size (max |q|) and its range of q."""
    acc[ACC_EVENTS] += 1.0
    acc[ACC_QMAX] = max(acc[ACC_QMAX], abs(q))
    acc[ACC_QLO] = min(acc[ACC_QLO], q)
    acc[ACC_QHI] = max(acc[ACC_QHI], q)


@jit
def offer_extreme(acc, x, t):
    """Offer the response x at time t as the period's max or min."""
    if x > acc[ACC_XMAX]:
        acc[ACC_XMAX] = x
        acc[ACC_TMAX] = t
    if x < acc[ACC_XMIN]:
        acc[ACC_XMIN] = x


@jit
def measure_stick(acc, qs, ta, tb, r, c):
    """Measure a stick at qs from ta to tb, exactly: the harmonic integrals of a constant and the
    extremes of x = qs + c cos(r t), at the ends and, for c != 0, where r t is a multiple of pi."""
    acc[ACC_IC] += qs * (math.sin(r * tb) - math.sin(r * ta)) / r
    acc[ACC_IS] += qs * (math.cos(r * ta) - math.cos(r * tb)) / r
    offer_extreme(acc, qs + c * math.cos(r * ta), ta)
    offer_extreme(acc, qs + c * math.cos(r * tb), tb)
    if c != 0.0:
        k = math.ceil(r * ta / math.pi)
        while k * math.pi < r * tb:
            offer_extreme(acc, qs + c * math.cos(k * math.pi), k * math.pi / r)
            k += 1
