"""Sticking, shared by both period integrators: the static band, when a stick ends, and the stick phase.

A mass at rest at q feels the net force d = A cos(r t) - q (forcing minus spring). It stays stuck
while |d| <= bs (the static friction band) and, when it leaves the band, slips in the direction of d.
A stick is exact for every integrator: q and v are frozen and its end is a closed form.
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jit import jit, jit_inline
from friction_sweep.kernels.measure import ACC_STOPS, ACC_STUCK, measure_stick
from friction_sweep.kernels.segments import FORCE_TIE, TWO_PI
from friction_sweep.ties import TIE_RTOL

#: A stick shorter than this fraction of the forcing period is a grazing contact, not a stop: at the
#: continuous limit the exact stick lasts zero time and rounding leaves ~1e-12 of a period, while a
#: friction ratio 1e-9 above the limit already sticks for ~1e-9 of a period.
GRAZING_STICK = 1e-10

#: After a slip that could not start (the force touched the band edge tangentially and turned back,
#: or pushed out of it by less than FORCE_TIE: a tie that rounding can decide either way), the next
#: stick exit is where the force leaves the band by more than the tie, and at least this fraction of a
#: period later, so that time always advances (no Zeno cycle of exit -> no motion -> stick).
TANGENT_SKIP = 1e-13


@jit_inline
def net_force(t, q, A, r):
    """Forcing minus spring on a mass at rest at q at time t: what friction must hold."""
    return A * math.cos(r * t) - q


@jit
def stuck_for_good(qs, A, bs):
    """A stick at qs never ends: the force's whole swing A + |qs| stays inside the static band bs, to
    the tie tolerance (friction_sweep.ties: beta = 1 and beta = r*r are ties however they round)."""
    return A + abs(qs) <= bs * (1.0 + TIE_RTOL)


@jit
def decide(t, q, A, r, bs):
    """Mode at rest at time t: 0 (stick) if the force is inside the static band, else its sign.
    A band that holds the force's whole swing (to the tie tolerance, friction_sweep.ties) is a stick."""
    d = net_force(t, q, A, r)
    if abs(d) <= bs or stuck_for_good(q, A, bs):
        return 0
    return 1 if d > 0.0 else -1


@jit
def slip_direction(t, q, A, r):
    """Direction in which the force sets the mass sliding when it leaves a stick at t."""
    return 1 if net_force(t, q, A, r) > 0.0 else -1


@jit
def stick_exit(t0, qs, A, r, bs):
    """First time t >= t0 at which |A cos(r t) - qs| > bs (static friction), or inf if never.

    Closed form: the force leaves the band through cos(r t) = (qs + bs)/A upwards or
    cos(r t) = (qs - bs)/A downwards; each is an arccos, repeated every forcing period.
    """
    if A <= 0.0 or stuck_for_good(qs, A, bs):
        return math.inf
    u0 = r * t0
    d = net_force(t0, qs, A, r)
    ddot = -A * r * math.sin(u0)
    # on the band edge and moving out: leave now (avoids waiting a period because of rounding)
    if (d >= bs and ddot > 0.0) or (d <= -bs and ddot < 0.0):
        return t0
    best = math.inf
    c_hi = (qs + bs) / A
    if c_hi < 1.0:
        if c_hi < -1.0:
            return t0
        al = math.acos(c_hi)
        k = math.ceil((u0 + al) / TWO_PI)
        best = min(best, TWO_PI * k - al)
    c_lo = (qs - bs) / A
    if c_lo > -1.0:
        if c_lo > 1.0:
            return t0
        al = math.acos(c_lo)
        k = math.ceil((u0 - al) / TWO_PI)
        best = min(best, al + TWO_PI * k)
    return max(best / r, t0)


@jit
def stick_phase(acc, q, t, T, p, new_stop, measure, stalled):
    """A stick from t (exact for every integrator): count a new stop if it lasts longer than a grazing
    contact, add the time stuck, measure it if asked. Returns the exit time (>= T when the mass stays
    stuck to the period end). stalled: the last slip could not start (see TANGENT_SKIP)."""
    A, r, bs = p.A, p.r, p.bs
    if stalled:
        skip = TANGENT_SKIP * T
        te = max(stick_exit(t + skip, q, A, r, bs + FORCE_TIE * (A + bs + abs(q))), t + skip)
    else:
        te = max(stick_exit(t, q, A, r, bs), t)
    if new_stop and te - t > GRAZING_STICK * T:
        acc[ACC_STOPS] += 1.0
    tb = min(te, T)
    acc[ACC_STUCK] += tb - t
    if measure:
        measure_stick(acc, q, t, tb, r, p.c)
    return te
