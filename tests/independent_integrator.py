"""An integrator for the tests that shares no code with the kernels: SciPy's DOP853 on the slip
equation, the stops and the stick exits as events, static friction deciding at every stop.

It integrates each model in its own time, the excitation y = cos(r t) at its maximum at t = 0: with a
dashpot 2 zeta q' (to the ground, or relative for joined), and for the base scene's spring-parallel
dashpot (`base_dashpot`) the force k(y - x) + c(y' - x') as it stands, so the forcing carries its
-2 zeta r sin(r t) term; nothing of the kernels' reduction of that term to a phase shift. The steady
orbit's energies per period come by quadrature as well (orbit_energies)."""

import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad, solve_ivp


def independent(A, r, bk, bs, q, v, c=0.0, max_periods=400, tol=1e-11):
    """March q'' + q + f = A cos(r t) from (q, v) at t = 0 until (q, v) repeats from one period to the
    next; returns (first-harmonic amplitude of x = q + c cos(r t), stops per period, stuck at the end)."""
    out = steady_orbit(A, r, bk, bs, q, v, c, max_periods=max_periods, tol=tol)
    return out["amplitude"], out["stops"], out["stuck_now"]


def orbit_energies(A, r, bk, bs, q, v, zeta=0.0, max_periods=400, tol=1e-11):
    """The steady orbit of q'' + 2 zeta q' + q + f = A cos(r t) reached from (q, v), over its last
    period: a dict of `friction` (bk x the distance q slides, from the slip pieces' ends), `forcing`
    (the forcing's work, the integral of A cos(r t) q' by quadrature) and `viscous` (2 zeta times the
    integral of q'^2 by quadrature)."""
    return steady_orbit(A, r, bk, bs, q, v, zeta=zeta, max_periods=max_periods, tol=tol)["energies"]


def one_period(A, r, bk, bs, t0, q, v, zeta=0.0, base_dashpot=False):
    """One forcing period of q'' + 2 zeta q' + q + f = A cos(r t) (- 2 zeta r sin(r t) if base_dashpot) from
    (q, v) at t0. Returns (q, v, pieces, stops, stuck): the state at t0 + 2 pi / r, the slip and stick pieces
    (lo, hi, q(t), q'(t) or None for a stick), the stops (a stop that sticks) and the time stuck."""
    T = 2 * np.pi / r

    def force(t):  # what pushes the mass at rest: spring and dashpot, without the friction
        f = A * np.cos(r * t)
        return f - 2 * zeta * r * np.sin(r * t) if base_dashpot else f

    def decide(t, q):
        d = force(t) - q
        return 0 if abs(d) <= bs else int(np.sign(d))

    mode = int(np.sign(v)) if v != 0 else decide(t0, q)
    t, t_end, pieces, stops, stuck = t0, t0 + T, [], 0, 0.0
    while t < t_end - 1e-13:
        if mode == 0:
            def band(tt, y, qs=q):
                return (force(tt) - qs) ** 2 - bs ** 2
            band.terminal, band.direction = True, 1
            sol = solve_ivp(lambda tt, y: [0.0], (t, t_end), [q], events=band, rtol=1e-12, atol=1e-13,
                            max_step=T / 512)
            t_new = sol.t_events[0][0] if sol.t_events[0].size else t_end
            pieces.append((t, t_new, lambda tt, qs=q: qs + 0.0 * tt, None))
            stuck += t_new - t
            t = t_new
            if t < t_end:
                mode = 1 if force(t) - q > 0 else -1
        else:
            sig = mode

            def rhs(tt, y, sig=sig):  # bound now: this piece's direction
                return [y[1], force(tt) - y[0] - 2 * zeta * y[1] - sig * bk]

            def stop(tt, y):
                return y[1]
            stop.terminal, stop.direction = True, -sig
            sol = solve_ivp(rhs, (t, t_end), [q, v], method="DOP853", events=stop, rtol=1e-12, atol=1e-13,
                            dense_output=True, first_step=min(1e-9, 0.5 * (t_end - t)))
            pieces.append((t, sol.t[-1], lambda tt, s=sol.sol: s(tt)[0], lambda tt, s=sol.sol: s(tt)[1]))
            q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
            if sol.status == 1:
                v = 0.0
                mode = decide(t, q)
                stops += mode == 0
    return q, v, pieces, stops, stuck


def steady_orbit(A, r, bk, bs, q, v, c=0.0, zeta=0.0, base_dashpot=False, max_periods=400, tol=1e-11):
    """March q'' + 2 zeta q' + q + f = A cos(r t) - (2 zeta r sin(r t) if base_dashpot) from (q, v) at
    t = 0 until (q, v) repeats from one period to the next. Returns a dict: `amplitude` (first harmonic of
    x = q + c cos(r t)), `lag` (its lag behind cos(r t), degrees in [-90, 270)), `peak` (max |x|, sampled),
    `peak_lag` (the sampled maximum of x's lag behind that of cos(r t), degrees),
    `stops` per period, `stuck_fraction`, `stuck_now` (stuck at the period's end) and the state there,
    at a maximum of cos(r t) (`q_end`, `v_end`), and the `energies` of orbit_energies (the forcing's
    work with the whole force that drives the mass, dashpot term included)."""
    T = 2 * np.pi / r

    def force(t):  # the whole force that drives the mass (for the forcing's work below)
        f = A * np.cos(r * t)
        return f - 2 * zeta * r * np.sin(r * t) if base_dashpot else f

    def period(t0, q, v):
        return one_period(A, r, bk, bs, t0, q, v, zeta, base_dashpot)

    t = 0.0
    for _ in range(max_periods):
        q1, v1, pieces, stops, stuck = period(t, q, v)
        done = abs(q1 - q) + abs(v1 - v) <= tol * max(1.0, abs(q))
        q, v, t = q1, v1, t + T
        if done:
            break
    else:
        raise AssertionError("no steady state")
    a = b = 0.0
    peak, top, t_top = 0.0, -np.inf, np.nan
    energies = {"friction": 0.0, "forcing": 0.0, "viscous": 0.0}
    with warnings.catch_warnings():  # quad's roundoff notice where a piece's integral is ~0
        warnings.simplefilter("ignore", IntegrationWarning)
        for lo, hi, f, fv in pieces:
            if hi > lo:
                a += quad(lambda s, f=f: (f(s) + c * np.cos(r * s)) * np.cos(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
                b += quad(lambda s, f=f: (f(s) + c * np.cos(r * s)) * np.sin(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
                s = np.linspace(lo, hi, 4000)
                xs = f(s) + c * np.cos(r * s)
                peak = max(peak, float(np.max(np.abs(xs))))
                if xs.max() > top:
                    top, t_top = float(xs.max()), float(s[np.argmax(xs)])
                if fv is not None:  # a slip piece: q is monotone on it (it ends at the first velocity zero)
                    energies["friction"] += bk * abs(f(hi) - f(lo))
                    energies["forcing"] += quad(lambda s, fv=fv: force(s) * fv(s), lo, hi, epsabs=1e-14,
                                                limit=200)[0]
                    energies["viscous"] += 2.0 * zeta * quad(lambda s, fv=fv: fv(s) ** 2, lo, hi, epsabs=1e-14,
                                                             limit=200)[0]
    stuck_now = v == 0.0 and abs(force(t) - q) <= bs
    amplitude = 2 / T * np.hypot(a, b)
    lag = (np.degrees(np.arctan2(b, a)) + 90.0) % 360.0 - 90.0 if amplitude > 0 else np.nan
    peak_lag = (np.degrees(r * t_top) + 90.0) % 360.0 - 90.0 if peak > 0 else np.nan
    return {"amplitude": amplitude, "lag": lag, "peak": peak, "peak_lag": peak_lag, "stops": stops, "stuck_fraction": stuck / T,
            "stuck_now": stuck_now, "q_end": q, "v_end": v, "energies": energies}
