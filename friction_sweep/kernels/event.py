"""Event-driven advance over one forcing period, exact between events, with optional measurement.

State at a period boundary: (q, v, mode) with mode +1/-1 slipping and 0 stuck. Time inside the
kernel is period-local (0 <= t <= T = 2 pi / r), so the forcing phase r t never loses precision,
however many periods are marched. At every stop the next mode is decided from the force there
(stick if |A cos(r t) - q| <= bs, else slip towards it), never by re-arming a root finder.

Measurement (only on the periods that are measured) accumulates into `acc`:
    ACC_IC, ACC_IS   integrals of q cos(r t), q sin(r t): Gauss-Legendre on slip pieces, exact on sticks
    ACC_XMAX/TMAX, ACC_XMIN/TMIN   extremes of the response x = q + c cos(r t) and their times
and, always (cheap): ACC_STUCK (time stuck), ACC_STOPS (stick entries of positive duration),
ACC_EVENTS and ACC_QMAX (max |q| at events: the orbit's size, a scale for convergence tests). For c = 0 the extremes sit at events (q is monotone between velocity zeros); for
c != 0 (joined: x = z + cos r t) they are refined by golden-section search inside the piece.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.segments import TWO_PI, find_stop, slip_state, stick_exit

OK = 0
BUDGET = 2  # same code as regimes.EVENT_BUDGET

#: A stick shorter than this fraction of the forcing period is a grazing contact, not a stop: at the
#: continuous limit the exact stick lasts zero time and rounding leaves ~1e-12 of a period, while a
#: friction ratio 1e-9 above the limit already sticks for ~1e-9 of a period.
GRAZING_STICK = 1e-10

_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
GL_X = np.ascontiguousarray(_GL_X)
GL_W = np.ascontiguousarray(_GL_W)

ACC_IC, ACC_IS, ACC_XMAX, ACC_TMAX, ACC_XMIN, ACC_TMIN, ACC_STUCK, ACC_STOPS, ACC_EVENTS, ACC_QMAX = range(10)
# piece that holds the best sample of the max (and of the min): anchor t0, q0, v0, sig, s, lo, hi
ACC_PMAX = 10
ACC_PMIN = 17
ACC_SIZE = 24


NO_SAMPLES = np.empty(0)  # for callers from Python; jitted callers allocate their own


def new_accumulator():
    acc = np.zeros(ACC_SIZE)
    reset_accumulator(acc)
    return acc


@jit
def reset_accumulator(acc):
    acc[:] = 0.0
    acc[ACC_XMAX] = -math.inf
    acc[ACC_XMIN] = math.inf


@jit
def decide(t, q, A, r, bs):
    """Mode at rest at time t: 0 (stick) if the force is inside the static band, else its sign."""
    d = A * math.cos(r * t) - q
    if abs(d) <= bs:
        return 0
    return 1 if d > 0.0 else -1


@jit
def _piece_x(s, t0, q0, v0, sig, A, r, bk, zeta, c):
    """Response x at local time s of a piece (sig = 0: stuck at q0)."""
    if sig == 0:
        q = q0
    else:
        q, _ = slip_state(s, q0, v0, sig, A, r, bk, zeta, math.cos(r * t0), math.sin(r * t0))
    return q + c * math.cos(r * (t0 + s))


@jit
def _candidate(acc, x, t, t0, q0, v0, sig, s, lo, hi):
    if x > acc[ACC_XMAX]:
        acc[ACC_XMAX] = x
        acc[ACC_TMAX] = t
        p = ACC_PMAX
        acc[p], acc[p + 1], acc[p + 2], acc[p + 3] = t0, q0, v0, sig
        acc[p + 4], acc[p + 5], acc[p + 6] = s, lo, hi
    if x < acc[ACC_XMIN]:
        acc[ACC_XMIN] = x
        acc[ACC_TMIN] = t
        p = ACC_PMIN
        acc[p], acc[p + 1], acc[p + 2], acc[p + 3] = t0, q0, v0, sig
        acc[p + 4], acc[p + 5], acc[p + 6] = s, lo, hi


@jit
def _measure_stick(acc, qs, ta, tb, A, r, c):
    acc[ACC_IC] += qs * (math.sin(r * tb) - math.sin(r * ta)) / r
    acc[ACC_IS] += qs * (math.cos(r * ta) - math.cos(r * tb)) / r
    _candidate(acc, qs + c * math.cos(r * ta), ta, ta, qs, 0.0, 0, 0.0, 0.0, tb - ta)
    _candidate(acc, qs + c * math.cos(r * tb), tb, ta, qs, 0.0, 0, tb - ta, 0.0, tb - ta)
    if c != 0.0:
        # x = qs + c cos(r t) peaks where r t is a multiple of pi inside the stick
        k = math.ceil(r * ta / math.pi)
        while k * math.pi < r * tb:
            t = k * math.pi / r
            _candidate(acc, qs + c * math.cos(k * math.pi), t, ta, qs, 0.0, 0, t - ta, 0.0, tb - ta)
            k += 1


@jit
def _measure_slip(acc, t0, q0, v0, sig, s_end, A, r, bk, zeta, c):
    ca = math.cos(r * t0)
    sa = math.sin(r * t0)
    _candidate(acc, q0 + c * ca, t0, t0, q0, v0, sig, 0.0, 0.0, s_end)
    if s_end <= 0.0:
        return
    width = 2.0 / (1.0 + r)  # sub-intervals resolve frequencies up to 1 + 2r to rounding
    n = int(math.ceil(s_end / width))
    h = s_end / n
    for j in range(n):
        a = j * h
        for i in range(GL_X.size):
            s = a + 0.5 * h * (GL_X[i] + 1.0)
            q, _ = slip_state(s, q0, v0, sig, A, r, bk, zeta, ca, sa)
            ph = r * (t0 + s)
            wq = 0.5 * h * GL_W[i] * q
            acc[ACC_IC] += wq * math.cos(ph)
            acc[ACC_IS] += wq * math.sin(ph)
            if c != 0.0:
                _candidate(acc, q + c * math.cos(ph), t0 + s, t0, q0, v0, sig, s, 0.0, s_end)
    q, _ = slip_state(s_end, q0, v0, sig, A, r, bk, zeta, ca, sa)
    _candidate(acc, q + c * math.cos(r * (t0 + s_end)), t0 + s_end, t0, q0, v0, sig, s_end, 0.0, s_end)


@jit
def refine_extremes(acc, A, r, bk, zeta, c):
    """Golden-section refinement of the sampled max and min of x inside their pieces (c != 0)."""
    if c == 0.0:
        return
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for p, sign, slot, tslot in ((ACC_PMAX, 1.0, ACC_XMAX, ACC_TMAX), (ACC_PMIN, -1.0, ACC_XMIN, ACC_TMIN)):
        t0, q0, v0, sig = acc[p], acc[p + 1], acc[p + 2], int(acc[p + 3])
        s, lo, hi = acc[p + 4], acc[p + 5], acc[p + 6]
        delta = 0.3 / (1.0 + r)  # wider than the sample spacing, narrower than a half oscillation
        a = max(lo, s - delta)
        b = min(hi, s + delta)
        x1 = b - g * (b - a)
        x2 = a + g * (b - a)
        f1 = sign * _piece_x(x1, t0, q0, v0, sig, A, r, bk, zeta, c)
        f2 = sign * _piece_x(x2, t0, q0, v0, sig, A, r, bk, zeta, c)
        for _ in range(80):
            if f1 > f2:
                b, x2, f2 = x2, x1, f1
                x1 = b - g * (b - a)
                f1 = sign * _piece_x(x1, t0, q0, v0, sig, A, r, bk, zeta, c)
            else:
                a, x1, f1 = x1, x2, f2
                x2 = a + g * (b - a)
                f2 = sign * _piece_x(x2, t0, q0, v0, sig, A, r, bk, zeta, c)
        sm = 0.5 * (a + b)
        if sig != 0:
            # golden pins the time only to sqrt(eps): finish with Newton on x'(s) = 0
            ca, sa = math.cos(r * t0), math.sin(r * t0)
            for _ in range(4):
                q, v = slip_state(sm, q0, v0, sig, A, r, bk, zeta, ca, sa)
                ph = r * (t0 + sm)
                xd = v - c * r * math.sin(ph)
                xdd = A * math.cos(ph) - q - sig * bk - 2.0 * zeta * v - c * r * r * math.cos(ph)
                if xdd == 0.0:
                    break
                step = xd / xdd
                if not (lo <= sm - step <= hi) or abs(step) > delta:
                    break
                sm -= step
        fm = sign * _piece_x(sm, t0, q0, v0, sig, A, r, bk, zeta, c)
        if fm > sign * acc[slot]:
            acc[slot] = sign * fm
            acc[tslot] = t0 + sm


#: After a slip that could not start (the force touched the band edge tangentially and turned back,
#: a tie that rounding can decide either way), the next stick exit is searched this fraction of a
#: period later, so that time always advances (no Zeno cycle of exit -> no motion -> stick).
TANGENT_SKIP = 1e-13


@jit
def stick_phase(acc, q, t, T, A, r, bs, c, new_stop, measure, skip):
    """A stick from t (exact for every integrator): count a new stop if it lasts longer than a grazing
    contact, add the time stuck, measure it if asked. Returns the exit time (>= T when the mass stays
    stuck to the period end). skip: search the exit only from t + skip."""
    te = max(stick_exit(t + skip, q, A, r, bs), t + skip)
    if new_stop and te - t > GRAZING_STICK * T:
        acc[ACC_STOPS] += 1.0
    tb = min(te, T)
    acc[ACC_STUCK] += tb - t
    if measure:
        _measure_stick(acc, q, t, tb, A, r, c)
    return te


@jit
def slip_direction(t, q, A, r):
    """Direction in which the force sets the mass sliding when it leaves a stick at t."""
    return 1 if A * math.cos(r * t) - q > 0.0 else -1


@jit
def _sample(ts, sq, sv, j, ta, tb, t0, q0, v0, sig, A, r, bk, zeta):
    """Fill the samples with ta <= ts[j] < tb from the piece anchored at t0; returns the next j."""
    while j < ts.size and ts[j] < tb:
        if ts[j] >= ta:
            if sig == 0:
                sq[j], sv[j] = q0, 0.0
            else:
                sq[j], sv[j] = slip_state(ts[j] - t0, q0, v0, sig, A, r, bk, zeta,
                                          math.cos(r * t0), math.sin(r * t0))
        j += 1
    return j


@jit
def advance_period(q, v, mode, A, r, bk, bs, zeta, c, vtol_rel, budget, measure, acc, ts, sq, sv):
    """March one forcing period from t = 0 to T. Returns (q, v, mode, status, work).

    ts: sorted period-local sample times (empty when not sampling); q, v there go to sq, sv.
    """
    T = TWO_PI / r
    hmax = min(1.0, 1.0 / r)
    t = 0.0
    work = 0
    new_stop = False
    from_stick = False
    j = 0
    stalled = False  # the last slip could not start from its stick exit
    while True:
        if mode == 0:
            te = stick_phase(acc, q, t, T, A, r, bs, c, new_stop, measure, TANGENT_SKIP * T if stalled else 0.0)
            new_stop = False
            stalled = False
            if ts.size:
                j = _sample(ts, sq, sv, j, t, te if te < T else math.inf, t, q, 0.0, 0, A, r, bk, zeta)
            if te >= T:
                return q, 0.0, 0, OK, work
            t = te
            v = 0.0
            mode = slip_direction(t, q, A, r)
            work += 1
            from_stick = True
        else:
            vtol = vtol_rel * max(A, math.hypot(q, v))
            s, found, w = find_stop(t, q, v, mode, A, r, bk, zeta, T - t, vtol, hmax, budget - work)
            work += w + 1
            if work > budget:
                return q, v, mode, BUDGET, work
            if found and s == 0.0 and from_stick:
                # the force touched the band edge and turned back: the mass stays stuck
                mode = 0
                stalled = True
                from_stick = False
                continue
            from_stick = False
            if measure:
                _measure_slip(acc, t, q, v, mode, s, A, r, bk, zeta, c)
            if ts.size:
                j = _sample(ts, sq, sv, j, t, t + s if found else math.inf, t, q, v, mode, A, r, bk, zeta)
            q1, v1 = slip_state(s, q, v, mode, A, r, bk, zeta, math.cos(r * t), math.sin(r * t))
            t = t + s
            q = q1
            v = v1
            if not found:
                return q, v, mode, OK, work
            v = 0.0
            acc[ACC_EVENTS] += 1.0
            acc[ACC_QMAX] = max(acc[ACC_QMAX], abs(q))
            mode = decide(t, q, A, r, bs)
            new_stop = mode == 0
            if t >= T:
                return q, v, mode, OK, work
