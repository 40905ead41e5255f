"""An integrator for the tests that shares no code with the kernels: SciPy's DOP853 on the slip
equation, the stops and the stick exits as events, static friction deciding at every stop; optionally
a dashpot 2 zeta q' and the steady orbit's energies per period by quadrature (orbit_energies)."""

import warnings

import numpy as np
from scipy.integrate import IntegrationWarning, quad, solve_ivp


def independent(A, r, bk, bs, q, v, c=0.0, max_periods=400, tol=1e-11):
    """March q'' + q + f = A cos(r t) from (q, v) at t = 0 until (q, v) repeats from one period to the
    next; returns (first-harmonic amplitude of x = q + c cos(r t), stops per period, stuck at the end)."""
    amplitude, stops, stuck_now, _ = _steady(A, r, bk, bs, q, v, c, max_periods, tol, 0.0)
    return amplitude, stops, stuck_now


def orbit_energies(A, r, bk, bs, q, v, zeta=0.0, max_periods=400, tol=1e-11):
    """The steady orbit of q'' + 2 zeta q' + q + f = A cos(r t) reached from (q, v), over its last
    period: a dict of `friction` (bk x the distance q slides, from the slip pieces' ends), `forcing`
    (the forcing's work, the integral of A cos(r t) q' by quadrature) and `viscous` (2 zeta times the
    integral of q'^2 by quadrature)."""
    return _steady(A, r, bk, bs, q, v, 0.0, max_periods, tol, zeta)[3]


def _steady(A, r, bk, bs, q, v, c, max_periods, tol, zeta):
    T = 2 * np.pi / r

    def decide(t, q):
        d = A * np.cos(r * t) - q
        return 0 if abs(d) <= bs else int(np.sign(d))

    def period(t0, q, v):
        mode = int(np.sign(v)) if v != 0 else decide(t0, q)
        t, t_end, pieces, stops = t0, t0 + T, [], 0
        while t < t_end - 1e-13:
            if mode == 0:
                def band(tt, y, qs=q):
                    return (A * np.cos(r * tt) - qs) ** 2 - bs ** 2
                band.terminal, band.direction = True, 1
                sol = solve_ivp(lambda tt, y: [0.0], (t, t_end), [q], events=band, rtol=1e-12, atol=1e-13,
                                max_step=T / 512)
                t_new = sol.t_events[0][0] if sol.t_events[0].size else t_end
                pieces.append((t, t_new, lambda tt, qs=q: qs, None))
                t = t_new
                if t < t_end:
                    mode = 1 if A * np.cos(r * t) - q > 0 else -1
            else:
                sig = mode

                def rhs(tt, y, sig=sig):  # bound now: this piece's direction
                    return [y[1], A * np.cos(r * tt) - y[0] - 2.0 * zeta * y[1] - sig * bk]

                def stop(tt, y):
                    return y[1]
                stop.terminal, stop.direction = True, -sig
                sol = solve_ivp(rhs, (t, t_end), [q, v], method="DOP853", events=stop, rtol=1e-12, atol=1e-13,
                                dense_output=True, first_step=1e-9)
                pieces.append((t, sol.t[-1], lambda tt, s=sol.sol: s(tt)[0], lambda tt, s=sol.sol: s(tt)[1]))
                q, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
                if sol.status == 1:
                    v = 0.0
                    mode = decide(t, q)
                    stops += mode == 0
        return q, v, pieces, stops

    t = 0.0
    for _ in range(max_periods):
        q1, v1, pieces, stops = period(t, q, v)
        done = abs(q1 - q) + abs(v1 - v) <= tol * max(1.0, abs(q))
        q, v, t = q1, v1, t + T
        if done:
            break
    else:
        raise AssertionError("no steady state")
    a = b = 0.0
    energies = {"friction": 0.0, "forcing": 0.0, "viscous": 0.0}
    with warnings.catch_warnings():  # quad's roundoff notice where a piece's integral is ~0
        warnings.simplefilter("ignore", IntegrationWarning)
        for lo, hi, f, fv in pieces:
            if hi > lo:
                a += quad(lambda s, f=f: (f(s) + c * np.cos(r * s)) * np.cos(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
                b += quad(lambda s, f=f: (f(s) + c * np.cos(r * s)) * np.sin(r * s), lo, hi, epsabs=1e-14, limit=200)[0]
                if fv is not None:  # a slip piece: q is monotone on it (it ends at the first velocity zero)
                    energies["friction"] += bk * abs(f(hi) - f(lo))
                    energies["forcing"] += quad(lambda s, fv=fv: A * np.cos(r * s) * fv(s), lo, hi, epsabs=1e-14,
                                                limit=200)[0]
                    energies["viscous"] += 2.0 * zeta * quad(lambda s, fv=fv: fv(s) ** 2, lo, hi, epsabs=1e-14,
                                                             limit=200)[0]
    stuck_now = v == 0.0 and abs(A * np.cos(r * t) - q) <= bs
    return 2 / T * np.hypot(a, b), stops, stuck_now, energies
