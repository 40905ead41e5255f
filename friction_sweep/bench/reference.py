"""An independent reference integrator: SciPy's DOP853 with event switching (tests, benchmarks).

Shares no code with the kernels: slip is integrated numerically (rtol 1e-12), stops are events on
the velocity, stick exits are events on |A cos(r t) - q| - bs, all located by SciPy.
"""

import numpy as np
from scipy.integrate import quad, solve_ivp


def simulate(A, r, bk, bs, periods, c=0.0, rtol=1e-12, atol=1e-13, w2=1.0):
    """March `periods` forcing periods from rest; returns a list of dense pieces of the last period.

    Solves q'' + w2 q + b sgn(q') = A cos(r t): w2 = 1 is the dimensionless problem; other values
    let a test integrate in physical units (then r is the forcing's angular frequency)."""
    T = 2 * np.pi / r
    t, q, v = 0.0, 0.0, 0.0

    def decide(t, q):
        d = A * np.cos(r * t) - w2 * q
        return 0 if abs(d) <= bs else int(np.sign(d))

    mode = decide(t, q)
    pieces = []
    t_end = periods * T
    while t < t_end - 1e-14:
        if mode == 0:
            def band(tt, y, qs=q):
                return (A * np.cos(r * tt) - w2 * qs) ** 2 - bs**2
            band.terminal, band.direction = True, 1
            # the force may leave the band for a sliver of a period (2 % at r = 0.1, beta = 0.5):
            # SciPy only sees sign changes between steps, so keep the steps short enough
            sol = solve_ivp(lambda tt, y: [0.0], (t, t_end), [q], events=band, rtol=rtol, atol=atol,
                            max_step=T / 2048)
            t_new = sol.t_events[0][0] if sol.t_events[0].size else t_end
            if t_new > t_end - 2 * T:
                pieces.append(("stick", t, t_new, q))
            t = t_new
            if t < t_end:
                mode = 1 if A * np.cos(r * t) - w2 * q > 0 else -1
                v = 0.0
        else:
            sig = mode

            def rhs(tt, y, sig=sig):  # bound now: the piece's direction
                return [y[1], A * np.cos(r * tt) - w2 * y[0] - sig * bk]

            def stop(tt, y):
                return y[1]
            stop.terminal = True
            stop.direction = -sig
            # nudge past the initial zero of the velocity: never re-arm on a function starting at 0
            sol = solve_ivp(rhs, (t, t_end), [q, v], method="DOP853", events=stop, rtol=rtol, atol=atol,
                            dense_output=True, first_step=1e-9)
            t_new = sol.t[-1]
            if t_new > t_end - 2 * T:
                pieces.append(("slip", t, t_new, sol.sol))
            q, v = sol.y[0, -1], sol.y[1, -1]
            t = t_new
            if sol.status == 1:  # stopped
                v = 0.0
                mode = decide(t, q)
    return pieces, T, t_end


def measure(A, r, bk, bs, periods, c=0.0, w2=1.0, rtol=1e-12, atol=1e-13):
    """First-harmonic amplitude and peak over the last period (response x = q + c cos r t)."""
    pieces, T, t_end = simulate(A, r, bk, bs, periods, c, rtol=rtol, atol=atol, w2=w2)
    t0 = t_end - T

    def x_of(t):
        for kind, a, b, data in pieces:
            if a - 1e-15 <= t <= b + 1e-15:
                q = data if kind == "stick" else data(t)[0]
                return q + c * np.cos(r * t)
        raise ValueError(t)

    ic = is_ = 0.0
    peak = 0.0
    for _kind, a, b, _data in pieces:
        a, b = max(a, t0), min(b, t_end)
        if b <= a:
            continue
        ic += quad(lambda t: x_of(t) * np.cos(r * t), a, b, epsabs=1e-14, epsrel=1e-12, limit=200)[0]
        is_ += quad(lambda t: x_of(t) * np.sin(r * t), a, b, epsabs=1e-14, epsrel=1e-12, limit=200)[0]
        ts = np.linspace(a, b, 4001)
        peak = max(peak, max(abs(x_of(t)) for t in ts))
    a1, b1 = 2 / T * ic, 2 / T * is_
    return np.hypot(a1, b1), peak
