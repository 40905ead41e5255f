"""An integrator of the Jenkins contact for the tests that shares no code with the kernels: SciPy's DOP853
on each mode's equation in the original time and variables, the mode changes as events.

    q'' + 2 zeta q' + q + fc = A cos(r t),   fc = kappa (q - w)
    slider slipping in direction s: fc = s bk, w = q - s bk / kappa; ends where q' = 0 (the slider sticks)
    slider stuck: w fixed; ends where fc reaches +-bs (slips that way, w jumping to q -+ bk / kappa)

Labels as docs/equations.md §7 defines them: a stick becomes a stop at the first zero of q' inside it; a
slip begun from a held stick during which the load never exceeds the kinetic friction (sig q'' <= 0
throughout, watched by an event on q'' = 0: a creep) leaves the next stick held from its start, no new
stop.
"""

import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad, solve_ivp

RTOL, ATOL = 1e-12, 1e-14
#: how long a stick begun on a band edge runs before that edge's event is armed (see period)
SKIP = 1e-6


def jenkins_orbit(A, r, bk, bs, kappa, q, v, w, mode, c=0.0, zeta=0.0, max_periods=200, tol=1e-11, kmax=8,
                  harmonics=()):
    """March periods from (q, v, w, mode) at t = 0 (mode +-1 slipping, 0 stuck, 2 stuck and held) until the
    state repeats to tol, k <= kmax periods back (not counting the first period, whose labels may lack the
    creep anchor carried from before t = 0); returns, per period of those k, the first-harmonic amplitude of
    x = q + c cos(r t), its lag (degrees), slips and stops, and the energy friction dissipated (bk x slide +
    the jumps), and the orbit's period k; with harmonics = (n, ...) also "harmonics": {n: the amplitude of q
    at the frequency n r}, (2 / kT) |int_0^kT q e^(-i n r t) dt| (q, not x: the c cos(r t) of x is all first
    harmonic)."""
    T = 2 * np.pi / r

    def period(q, v, w, mode, anchor):
        t, pieces, slips, stops, energy = 0.0, [], 0, 0, 0.0
        on_edge = 0
        while t < T - 1e-12:
            if mode in (1, -1):
                s = mode

                def rhs(tt, y, s=s):
                    return [y[1], A * np.cos(r * tt) - y[0] - 2 * zeta * y[1] - s * bk]

                def stop(tt, y):
                    return y[1]

                def driven(tt, y, s=s):
                    return s * (A * np.cos(r * tt) - y[0] - 2 * zeta * y[1] - s * bk)
                stop.terminal, stop.direction = True, -s
                driven.direction = 1
                if anchor is not None and driven(t, [q, v]) > 0:
                    anchor = None  # the load drives the slip from its start: no creep
                sol = solve_ivp(rhs, (t, T), [q, v], method="DOP853", events=[stop, driven], rtol=RTOL,
                                atol=ATOL, dense_output=True, first_step=1e-10)
                if sol.t_events[1].size:
                    anchor = None
                pieces.append((t, sol.t[-1], sol.sol))
                energy += bk * abs(sol.y[0, -1] - q)
                q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
                w = q - s * bk / kappa
                if sol.status == 1:
                    v = 0.0
                    on_edge = s if bs == bk else 0  # the slider sticks with fc = s bk: on that edge if bs = bk
                    mode = 0 if anchor is None else 2
                    anchor = None
            else:
                ws = w

                def rhs(tt, y, ws=ws):
                    return [y[1], A * np.cos(r * tt) - y[0] - 2 * zeta * y[1] - kappa * (y[0] - ws)]

                def upper(tt, y, ws=ws):
                    return kappa * (y[0] - ws) - bs

                def lower(tt, y, ws=ws):
                    return kappa * (y[0] - ws) + bs

                def turn(tt, y):
                    return y[1]
                upper.terminal, upper.direction = True, 1
                lower.terminal, lower.direction = True, -1
                events = [upper, lower]
                if mode == 0:
                    # the velocity's return to zero, not the zero it starts from (a stick after a slip)
                    a = A * np.cos(r * t) - q - 2 * zeta * v - kappa * (q - ws)
                    turn.terminal, turn.direction = True, -np.sign(v if v != 0.0 else a)
                    events.append(turn)
                if on_edge:
                    # the stick begins where the slip stopped, fc = s bk = s bs on the edge the slip pushed it
                    # to; the force turns inwards there (the slip decelerated to rest), but rounding can put
                    # the first step across that edge: a zero-length exit, then a zero-length slip, forever.
                    # So the first SKIP of the stick runs without that edge's event (nothing else can
                    # happen so soon: the other edge is 2 bs / kappa away, the turn half a swing away)
                    edge, on_edge = on_edge, 0
                    span = (t, min(t + SKIP, T))
                    events = [lower] if edge == 1 else [upper]
                    sol = solve_ivp(rhs, span, [q, v], method="DOP853", events=events, rtol=RTOL, atol=ATOL,
                                    dense_output=True, first_step=1e-10)
                    assert sol.status == 0, "an event within the skip"
                    pieces.append((t, sol.t[-1], sol.sol))
                    q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
                    continue
                sol = solve_ivp(rhs, (t, T), [q, v], method="DOP853", events=events, rtol=RTOL, atol=ATOL,
                                dense_output=True, first_step=1e-10, max_step=0.5 / np.sqrt(1 + kappa))
                pieces.append((t, sol.t[-1], sol.sol))
                q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
                if sol.status == 1:
                    if mode == 0 and sol.t_events[2].size:
                        assert sol.t_events[2][0] > pieces[-1][0] + 1e-12, "a turn at the stick's start"
                        mode, stops = 2, stops + 1  # the mass turned within the stick: a stop
                        continue
                    assert sol.t_events[0].size + sol.t_events[1].size == 1
                    e = 1 if sol.t_events[0].size else -1
                    anchor = w if mode == 2 else None
                    energy += 0.5 * (bs - bk) * (bs + bk) / kappa
                    w = q - e * bk / kappa
                    mode, slips = e, slips + 1
        return q, v, w, mode, anchor, pieces, slips, stops, energy

    def stuck(m):
        return m in (0, 2)

    states, records, anchor, k = [(q, v, w, mode)], [], None, 0
    for n in range(1, max_periods + 1):
        q, v, w, mode, anchor, *record = period(q, v, w, mode, anchor)
        states.append((q, v, w, mode))
        records.append(record)
        for j in range(1, min(kmax, n - 1) + 1):
            qh, vh, wh, mh = states[n - j]
            if (mh == mode or stuck(mh) and stuck(mode)) and \
                    abs(q - qh) + abs(v - vh) + abs(w - wh) <= tol * max(1.0, abs(q)):
                k = j
                break
        if k:
            break
    else:
        raise AssertionError("no steady state")
    a = b = energy = 0.0
    slips = stops = 0
    proj = {n: [0.0, 0.0] for n in harmonics}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        for pieces, n_slips, n_stops, n_energy in records[-k:]:
            slips, stops, energy = slips + n_slips, stops + n_stops, energy + n_energy
            for lo, hi, f in pieces:
                if hi > lo:
                    a += quad(lambda s, f=f: (f(s)[0] + c * np.cos(r * s)) * np.cos(r * s), lo, hi,
                              epsabs=1e-15, limit=400)[0]
                    b += quad(lambda s, f=f: (f(s)[0] + c * np.cos(r * s)) * np.sin(r * s), lo, hi,
                              epsabs=1e-15, limit=400)[0]
                    for n, ab in proj.items():
                        ab[0] += quad(lambda s, f=f, n=n: f(s)[0] * np.cos(n * r * s), lo, hi, epsabs=1e-15,
                                      limit=400)[0]
                        ab[1] += quad(lambda s, f=f, n=n: f(s)[0] * np.sin(n * r * s), lo, hi, epsabs=1e-15,
                                      limit=400)[0]
    amplitude = 2 / (k * T) * np.hypot(a, b)
    lag = (np.degrees(np.arctan2(b, a)) + 90.0) % 360.0 - 90.0
    return {"amplitude": amplitude, "lag": lag, "slips": slips / k, "stops": stops / k, "friction_energy": energy / k,
            "orbit_period": k, "harmonics": {n: 2 / (k * T) * np.hypot(*ab) for n, ab in proj.items()}}
