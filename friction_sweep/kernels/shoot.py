"""Newton shooting for a period-k orbit of the period map, and the tests that make one a steady state.

Solves F(x) = P^k(x) - x with the event kernel's exact monodromy matrix where it is valid (k = 1, a
period where the map is smooth, sticks included) and forward differences elsewhere. Newton finds
unstable orbits as readily as stable ones, so a solution counts only if it attracts (spectral radius
of the monodromy matrix below 1), if the map's own error cannot move it far (resolvable) and if it
obeys the bound the equation proves for the first harmonic (within the forced bound).
"""

from __future__ import annotations

import math

from friction_sweep.kernels.jit import jit
from friction_sweep.kernels.measure import ACC_IC, ACC_IS, ACC_JAC, ACC_JAC_OK, ACC_QMAX, ACC_STOPS, ACC_STUCK
from friction_sweep.kernels.period_map import map_error, map_k


@jit
def spectral_radius(m11, m12, m21, m22):
    """Largest |eigenvalue| of a 2 x 2 matrix."""
    half = 0.5 * (m11 + m22)
    disc = half * half - (m11 * m22 - m12 * m21)
    if disc >= 0.0:
        return abs(half) + math.sqrt(disc)
    return math.sqrt(m11 * m22 - m12 * m21)


#: a solution of P(x) = x is accepted only if the error that the map's own error (rounding, or RK4's
#: truncation: period_map.map_error) can cause, |(J - I)^-1| times it, is below this relative: near
#: r = 1, |(J - I)^-1| ~ 0.23/|1 - r|, so orbits are resolved down to |1 - r| ~ 2e-11; a "solution" of
#: size 1e15 or more at r = 1, where the map's O(1) drift per period is lost in rounding, has
#: |(J - I)^-1| ~ its size and is refused
RESOLVABLE = 1e-4


@jit
def _inverse_norm(b11, b12, b21, b22):
    """|B^-1| (Frobenius: |B| / |det B| for 2 x 2); inf where B is singular."""
    det = b11 * b22 - b12 * b21
    if det == 0.0 or not math.isfinite(det):
        return math.inf
    return math.sqrt(b11 * b11 + b12 * b12 + b21 * b21 + b22 * b22) / abs(det)


@jit
def _rounding_step(scale, c, step_noise):
    """The Newton step that is at the floor of double precision (ROUNDING_STEP of the response, the
    larger of the orbit and c, or ROUNDING_NOISE times what the map's own error leaves in a step)."""
    return max(ROUNDING_STEP * max(scale, c), ROUNDING_NOISE * step_noise)


@jit
def _resolvable(b11, b12, b21, b22, error):
    """Whether a fixed point of P with Jacobian J = I + B is pinned down by the map despite its own
    error: |B^-1| times that error (relative to the larger of the orbit and the forcing) is below
    RESOLVABLE."""
    return _inverse_norm(b11, b12, b21, b22) * error <= RESOLVABLE


@jit
def _within_forced_bound(acc, k, p, landing):
    """The orbit's first harmonic Q1 (of q over its k measured periods, from the slots ic, is) obeys the
    bound that the equation itself proves: projecting q'' + 2 zeta q' + q + f = A cos(r t) onto the forcing
    frequency gives (1 - r^2 + 2i zeta r) Q1 = A - F1, and a friction force |f| <= max(bk, bs) has
    |F1| <= 4 max(bk, bs)/pi. Only a spurious orbit breaks it (always true at r = 1 without damping).
    Slack: 1e-9, plus `landing`, the relative error the acceptance leaves in the state (without friction
    the linear orbit sits on the bound: damped, next to resonance, Newton lands within 7e-9 of it)."""
    A, r, bk, bs, zeta, _ = p
    q1 = r / math.pi * math.hypot(acc[ACC_IC], acc[ACC_IS]) / k
    gain = math.hypot((1.0 - r) * (1.0 + r), 2.0 * zeta * r)
    return q1 * gain <= (A + 4.0 / math.pi * max(bk, bs)) * (1.0 + 1e-9 + landing)


@jit
def _landing(b11, b12, b21, b22, tol):
    """The relative error an accepted state may carry: its residual |P(x) - x| <= tol |x| (shoot's
    acceptance, `settled`) times |(J - I)^-1|. Not the map's own error: the rk4 map's truncation moves
    its orbits off the exact bound, and those are left to the march (rk4 results unchanged)."""
    return min(_inverse_norm(b11, b12, b21, b22), 1e300) * tol


#: a Newton step below this fraction of the response's size (the larger of the orbit and the
#: excitation's share c of x = q + c cos(r t): joined responses cancel down to a quarter of z), or below
#: ROUNDING_NOISE times the step that the map's own error causes, is at the floor of double precision:
#: the state it starts from is the fixed point, as far as the map can tell (measured on the paper
#: planes: every transmissibility within 1e-12 of its error before, relative, but where that floor
#: is the map's own rounding next to resonance)
ROUNDING_STEP = 3e-13
ROUNDING_NOISE = 4.0
#: through sticks, a Newton step is at most this multiple of the larger of the orbit and the forcing
TRUST = 1.0
#: evaluations of P^k a shooting solve may take
NEWTON_ITERATIONS = 40
#: how far above 1 the computed spectral radius of a closed-form stick-free orbit may lie and still be
#: read as the multiplier <= 1 that a non-expansive map has: next to r = 1/(2n) the two multipliers are
#: 1 and 1 - O(beta), and spectral_radius's square root of (trace/2)^2 - det, a difference of numbers
#: near 1, carries sqrt(rounding) ~ 1.5e-8 (measured: 1 + 1.5e-9 at beta = 1e-9)
NEUTRAL_SLACK = 1e-7


@jit
def _neutral_closed_form(acc, radius):
    """Whether a closed-form start that the map returns to itself (settled) is the steady state although
    Newton cannot resolve it: its period never stops or sticks, and its multiplier is 1 to rounding.

    Where the steady state is unique (static = kinetic friction, something dissipates: the only callers
    of FIRST_MEASURED), the period map does not expand distances in the energy norm, so no fixed point
    repels (|multiplier| <= 1 exactly), and a fixed point that never sticks is the only one: another
    fixed point at a constant energy distance would need the same friction force throughout, so the two
    differ by a free oscillation whose period divides the forcing period, r = 1/m, where U is singular
    (odd m: no closed form) or the stick-free family lies (even m). Next to r = 1/(2n) the multiplier
    tends to 1 (|(J - I)^-1| ~ 1e19 at |2nr - 1| = 2e-12), so _resolvable refuses the orbit and a march
    creeps, stick by stick, ever more slowly (2 x 10^5 periods halve the stuck time) towards the family: a
    creep that the march's per-period test would accept as a stick-slip orbit. The closed form places the
    fixed point; the exact period confirms it."""
    return acc[ACC_STOPS] == 0.0 and acc[ACC_STUCK] == 0.0 and radius <= 1.0 + NEUTRAL_SLACK


#: how shoot's first evaluation goes: integrated plainly; given (the caller's last period, unmeasured,
#: its monodromy matrix in acc); integrated and measured (a start expected on the orbit already)
FIRST_PLAIN, FIRST_GIVEN, FIRST_MEASURED = 0, 1, 2


@jit
def shoot(q, v, k, p, settings, tol, budget, acc, q1, v1, first, rk4):
    """Newton on F(x) = P^k(x) - x for a period-k orbit, at most NEWTON_ITERATIONS evaluations of P^k
    (finite differences aside). Returns (q, v, ok, work, periods): periods the forcing periods integrated (every
    evaluation of P^k, finite differences included).

    first: FIRST_GIVEN where (q1, v1) = P^k(q, v) is in hand already, unmeasured, with its monodromy
    matrix in `acc` (the march's last period): Newton's first step is taken from it instead of
    integrating it again; FIRST_MEASURED where (q, v) is expected on the orbit (a closed-form guess):
    the first evaluation measures, so that one period settles it if its own Newton step is at rounding.

    The Jacobian is the event kernel's monodromy matrix (exact, with the saltations at reversals,
    sticks and releases) wherever it is valid (k = 1, a smooth period), else forward differences (rk4
    kernel, a period where the map is not smooth). Through a stick that matrix has rank 1 (the stop
    forgets the velocity), which Newton on P - I does not mind. The evaluation that can confirm
    convergence also measures: on success `acc` holds the measurement of the period from the returned
    state, exactly as a separate measured pass would. Newton finds unstable orbits as readily as stable
    ones; only an attracting one (monodromy spectral radius < 1) is a steady state, and only one that
    rounding cannot move far (_resolvable) and that obeys the forced bound.
    """
    work = 0
    periods = 0
    error = map_error(p.r, settings)
    guessed = first == FIRST_MEASURED  # a closed-form start (see _neutral_closed_form)
    # Accept only at Newton's floor, reached by shrinking steps: where the map has no fixed point
    # (r = 1, friction below pi/4) a near-singular Jacobian leaps to a huge state whose relative
    # residual looks tiny.
    last_step = math.inf
    prev_step = math.inf
    radius = math.inf
    b11 = b12 = b21 = b22 = 0.0  # J - I of the latest Jacobian (exact, or forward differences)
    size = max(math.hypot(q, v), acc[ACC_QMAX], 1e-300)
    exact = False  # whether the latest Jacobian was the exact one
    for _ in range(NEWTON_ITERATIONS):
        scale = max(math.hypot(q, v), size)
        # What the map's own error leaves: it is computed to ~map_error of the larger of the orbit and
        # the forcing (an orbit far smaller than A, next to the no-motion threshold, is pinned only
        # absolutely), and Newton's step inherits that times |(J - I)^-1|.
        noise = error * max(scale, p.A)
        step_noise = noise * min(_inverse_norm(b11, b12, b21, b22), 1e300) if last_step < math.inf else 0.0
        # Confirm (and measure) once Newton has hit its floor: a step below 1e-9 of the state, or one
        # below 1e-6 that no longer shrinks quadratically (rounding next to resonance). Stopping at the
        # first step below 1e-6 would leave ~1e-12 of the state, all of it in x = z + cos(r t) when x
        # is tiny (joined scene at high r).
        floor = (last_step <= 1e-9 * scale + step_noise
                 or (last_step <= 1e-6 * scale + step_noise and last_step >= 1e-2 * prev_step))
        # With the exact Jacobian, measure as well where quadratic convergence (from the last two steps)
        # predicts that the step from this state will be at rounding: that step then decides (below).
        predicted = (exact and last_step < 0.5 * prev_step < math.inf
                     and last_step ** 3 <= _rounding_step(scale, p.c, step_noise) * prev_step ** 2)
        measure = floor or predicted or first == FIRST_MEASURED
        if first == FIRST_GIVEN:
            measure = False
        else:
            q1, v1, st, w = map_k(q, v, k, p, settings, budget - work, measure, acc, rk4)
            work += w
            periods += k
            if st != 0 or not (math.isfinite(q1) and math.isfinite(v1)):
                return q, v, False, work, periods
        first = FIRST_PLAIN
        fq = q1 - q
        fv = v1 - v
        sticks = acc[ACC_STOPS] > 0.0 or acc[ACC_STUCK] > 0.0  # of this evaluation (FD below reuse acc)
        settled = measure and abs(fq) + abs(fv) <= tol * scale + noise
        if settled and floor:
            if acc[ACC_JAC_OK] == 1.0:
                radius = spectral_radius(acc[ACC_JAC], acc[ACC_JAC + 1], acc[ACC_JAC + 2], acc[ACC_JAC + 3])
                b11, b12 = acc[ACC_JAC] - 1.0, acc[ACC_JAC + 1]
                b21, b22 = acc[ACC_JAC + 2], acc[ACC_JAC + 3] - 1.0
            ok = (radius < 1.0 and _resolvable(b11, b12, b21, b22, error)
                  and _within_forced_bound(acc, k, p, _landing(b11, b12, b21, b22, tol)))
            return q, v, ok, work, periods
        exact = acc[ACC_JAC_OK] == 1.0
        if exact:
            j11 = acc[ACC_JAC] - 1.0
            j12 = acc[ACC_JAC + 1]
            j21 = acc[ACC_JAC + 2]
            j22 = acc[ACC_JAC + 3] - 1.0
        else:
            # a step of 1e-6 of the orbit, or more where that would drown in the forcing's rounding
            h = max(1e-6 * scale, 1e-8 * math.sqrt(p.A * scale))
            qa, va, st1, w1 = map_k(q + h, v, k, p, settings, budget - work, False, acc, rk4)
            qb, vb, st2, w2 = map_k(q, v + h, k, p, settings, budget - work, False, acc, rk4)
            work += w1 + w2
            periods += 2 * k
            if st1 != 0 or st2 != 0:
                return q, v, False, work, periods
            j11 = (qa - q1) / h - 1.0
            j21 = (va - v1) / h
            j12 = (qb - q1) / h
            j22 = (vb - v1) / h - 1.0
        radius = spectral_radius(j11 + 1.0, j12, j21, j22 + 1.0)
        b11, b12, b21, b22 = j11, j12, j21, j22
        # the closed-form start, settled in its first (measured) period, where Newton cannot resolve it
        if (guessed and periods == k and settled and exact
                and not (radius < 1.0 and _resolvable(b11, b12, b21, b22, error))):
            ok = _neutral_closed_form(acc, radius) and _within_forced_bound(acc, k, p, 0.0)  # no Newton landing
            return q, v, ok, work, periods
        det = j11 * j22 - j12 * j21
        if det == 0.0 or not math.isfinite(det):
            return q, v, False, work, periods
        dq = (j22 * fq - j12 * fv) / det
        dv = (-j21 * fq + j11 * fv) / det
        step = abs(dq) + abs(dv)
        # The state's own Newton step at rounding, with this state's Jacobian: it is the fixed point as
        # far as the map can tell. Measured only where that was predicted from shrinking steps (no leap
        # lands here) or where the start was a closed-form guess.
        if settled and exact and step <= _rounding_step(scale, p.c,
                                                        noise * min(_inverse_norm(b11, b12, b21, b22), 1e300)):
            ok = (radius < 1.0 and _resolvable(b11, b12, b21, b22, error)
                  and _within_forced_bound(acc, k, p, _landing(b11, b12, b21, b22, tol)))
            return q, v, ok, work, periods
        # Through sticks the map is only piecewise smooth: a step longer than the motion itself
        # leaves the piece whose Jacobian proposed it, and Newton wanders between stop patterns
        # (joined, r = 0.79, beta = 0.54: a leap to v = -1.95 from an orbit of size 0.6).
        reach = TRUST * max(scale, p.A)
        if sticks and step > reach:
            dq *= reach / step
            dv *= reach / step
            step = reach
        q -= dq
        v -= dv
        prev_step = last_step
        last_step = step
        if not (math.isfinite(q) and math.isfinite(v)):
            return q, v, False, work, periods
    return q, v, False, work, periods
