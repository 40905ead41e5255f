"""The reference paper's numerical method, kept as a baseline: adaptive RK45 on the naive sgn, then FFT.

Marino, Cicirello & Hills (2019) integrated their Eqs. (49)/(55) with MATLAB's ode45 (Dormand-Prince
Runge-Kutta 4(5), rtol 1e-3, atol 1e-6 by default) using sgn(velocity) as it stands: there is no stick
mode, so while the mass should be stuck the velocity chatters around zero and the step size collapses.
They sampled the solution at a fixed output step, dropped the transient and took the FFT of the
response x and of the excitation y: transmissibility |X(r)| / |Y(r)| at the forcing frequency.

This module does exactly that with SciPy, from rest (q = q' = 0 at tau = 0), docs/equations.md §1:

    force / base:  q'' + q + beta sgn(q') = cos(r tau),        x = q
    joined:        z'' + z + beta sgn(z') = r^2 cos(r tau),    x = z + cos(r tau)

with `scipy.integrate.solve_ivp(method="RK45", rtol, atol, t_eval=...)` and `np.sign` for sgn
(sgn(0) = 0, so a point starting from rest is always pushed off by the force at tau = 0).
`periods` whole forcing periods are simulated and sampled `samples_per_period` times per period;
the first floor(transient_fraction * periods) periods are discarded, so the retained window holds a
whole number K of periods and the forcing frequency falls exactly on rfft bin K.

Outputs (the meanings every method shares):

- transmissibility = |X_K| / |Y_K|; phase = angle(Y_K) - angle(X_K) (lag, wrap_lag_degrees).
- peak_transmissibility = max |x| over the retained window.
- peak_phase = r t_x where t_x is the sample time of the largest x in the last retained period
  (the excitation peaks at r tau = 0 mod 2 pi); quantised to 360 / samples_per_period degrees.
- stuck_fraction, stops_per_period: the method has no stick mode, so they are read off the samples:
  a sample is stuck when |q'| (or |z'|) <= stick_velocity * max |q'| over the window; a stop is a
  maximal run of >= 2 consecutive stuck samples (runs are counted cyclically, the window being whole
  periods), averaged per retained period.
- regime: STUCK when the relative motion never leaves the integrator's chatter noise,
  max |q| <= stuck_displacement_per_atol * atol over the window (the chatter wanders by 20-100 atol,
  measured, so an absolute 1e-6 would call a stuck point moving); then UNBOUNDED when max |x| in
  the last retained period exceeds that in the first retained period by more than 10 % and exceeds
  10 (the four numeric outputs are NaN there); then STICK_SLIP when stops_per_period >= 0.5;
  else CONTINUOUS. For STUCK force/base points the phases are NaN (no motion, phase undefined, as in
  the theory); the transmissibilities are the measured chatter (about atol-sized, not exactly 0).
- steady_state: the paper's method never checks for a steady state, it runs the fixed number of
  periods: PERIOD_CAP for every point that finished. A point whose integration fails (solve_ivp
  status < 0) or goes non-finite is UNSETTLED with NONFINITE; one that exhausts the evaluation budget
  is UNSETTLED with EVENT_BUDGET. Numeric outputs are NaN for both; nothing raises for a grid point.
- periods: forcing periods actually simulated (fewer than asked when the budget ran out).

Cost: smooth slip is cheap (0.1-0.5 s a point at the defaults). Chatter is not: while stuck, the
step size is about atol / beta, so a stuck or stick-slip point costs roughly 0.3-0.5 beta / atol
right-hand-side evaluations per unit of tau (measured 8 s per forcing period at r = 0.3, beta = 0.5
and 23-52 s at r = 0.5, beta = 1.2-2, so a whole 200-period run takes from half an hour to hours).
At rtol 1e-8, atol 1e-10 even a continuous point that stops once in its transient is that costly.
`max_evaluations` (not in the paper) caps that per point; pass None for the unbounded paper run.
"""

from __future__ import annotations

import math

import numpy as np

from friction_sweep import catalogue
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.methods import theory
from friction_sweep.theory import scenes
from friction_sweep.theory.phase import wrap_lag_degrees

CATALOGUE = catalogue.method("paper")  # plain Coulomb friction only, as in the paper; defaults: ode45's

#: growth test for UNBOUNDED: last/first retained period peak ratio, and the least peak
GROWTH_RATIO = 1.1
GROWTH_MIN_PEAK = 10.0

VARIABLES = {
    "transmissibility": ("transmissibility", "peak_transmissibility"),
    "phase": ("phase", "peak_phase"),
    "regime": ("regime", "stops_per_period", "stuck_fraction", "periods", "steady_state"),
}
_INTEGER = ("regime", "steady_state")
_NUMERIC = ("transmissibility", "peak_transmissibility", "phase", "peak_phase")


class _BudgetExhausted(Exception):
    def __init__(self, t):
        super().__init__(t)
        self.t = t


def variables_for(excitation: str, outputs) -> tuple[str, ...]:
    """Per-point variable names this method writes for the requested output groups."""
    names: list[str] = []
    for group in outputs:
        names.extend(VARIABLES.get(group, ()))
    return tuple(names)


def resolve_settings(settings=None, **overrides) -> dict:
    """The catalogue's defaults updated with `settings` and keyword overrides, checked (ValueError/KeyError
    if bad)."""
    values: dict = CATALOGUE.defaults
    given = {**(settings or {}), **overrides}
    unknown = set(given) - set(values)
    if unknown:
        raise KeyError(f"unknown paper settings: {sorted(unknown)} (known: {sorted(values)})")
    values.update(given)
    periods = values["periods"]
    spp = values["samples_per_period"]
    if int(periods) != periods or periods < 1:
        raise ValueError(f"periods must be a positive integer, got {periods!r}")
    if int(spp) != spp or spp < 4:
        raise ValueError(f"samples_per_period must be an integer >= 4, got {spp!r}")
    values["periods"], values["samples_per_period"] = int(periods), int(spp)
    if not 0.0 <= values["transient_fraction"] < 1.0:
        raise ValueError(f"transient_fraction must lie in [0, 1), got {values['transient_fraction']!r}")
    for key in ("rtol", "atol"):
        if not values[key] > 0.0:
            raise ValueError(f"{key} must be positive, got {values[key]!r}")
    for key in ("stick_velocity", "stuck_displacement_per_atol"):
        if not values[key] >= 0.0:
            raise ValueError(f"{key} must be >= 0, got {values[key]!r}")
    budget = values["max_evaluations"]
    if budget is not None and (int(budget) != budget or budget < 1):
        raise ValueError(f"max_evaluations must be a positive integer or None, got {budget!r}")
    return values


def _window(settings):
    """(discarded periods, retained periods); at least one period is retained."""
    periods = settings["periods"]
    n_transient = min(int(math.floor(settings["transient_fraction"] * periods)), periods - 1)
    return n_transient, periods - n_transient


def _failed(code, periods_done) -> dict:
    out = {name: math.nan for name in _NUMERIC}
    out.update(stops_per_period=math.nan, stuck_fraction=math.nan, periods=float(periods_done),
               regime=int(Regime.UNSETTLED), steady_state=int(code))
    return out


def _count_stops(stuck) -> int:
    """Maximal runs of >= 2 consecutive True samples, the sequence read cyclically."""
    if stuck.all() or not stuck.any():
        return 0
    s = np.roll(stuck, -int(np.argmin(stuck)))  # start on a moving sample: no run wraps around
    edges = np.diff(np.concatenate(([0], s.astype(np.int8), [0])))
    lengths = np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)
    return int(np.count_nonzero(lengths >= 2))


def solve_point(excitation: str, r: float, beta: float, settings=None, **overrides) -> dict:
    """Integrate one (r, beta) point the paper's way and measure it.

    Returns floats for transmissibility, peak_transmissibility, phase, peak_phase, stops_per_period,
    stuck_fraction, periods, and ints (regimes codes) for regime and steady_state. Never raises for
    a bad point: failures are UNSETTLED with NaN numbers.
    """
    from scipy.integrate import solve_ivp  # imported here: only this method needs SciPy's integrators

    if excitation not in CATALOGUE.excitations:
        raise ValueError(f"unknown excitation {excitation!r} (expected one of {CATALOGUE.excitations})")
    s = resolve_settings(settings, **overrides)
    r, beta = float(r), float(beta)
    spp, periods = s["samples_per_period"], s["periods"]
    n_transient, n_keep = _window(s)
    joined = excitation == "joined"
    amp = scenes.forcing_amplitude(excitation, r)
    period = 2.0 * math.pi / r
    budget = s["max_evaluations"]
    calls = [0, 0.0]  # evaluations, last time seen

    def rhs(t, y):
        calls[0] += 1
        calls[1] = t
        if budget is not None and calls[0] > budget:
            raise _BudgetExhausted(t)
        return (y[1], amp * math.cos(r * t) - y[0] - beta * np.sign(y[1]))

    n_total = periods * spp
    t_eval = np.arange(n_total) * (period / spp)
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (0.0, periods * period), (0.0, 0.0), method="RK45", t_eval=t_eval,
                            rtol=s["rtol"], atol=s["atol"])
    except _BudgetExhausted as stop:
        return _failed(SteadyState.EVENT_BUDGET, stop.t / period)
    except (ArithmeticError, ValueError, RuntimeError):
        return _failed(SteadyState.NONFINITE, calls[1] / period)
    if sol.status < 0 or sol.y.shape[1] != n_total or not np.all(np.isfinite(sol.y)):
        return _failed(SteadyState.NONFINITE, calls[1] / period)

    keep = slice(n_transient * spp, n_total)
    q, v = sol.y[0, keep], sol.y[1, keep]
    # excitation phase r tau at the samples, exactly 2 pi n / spp
    theta = 2.0 * np.pi * (np.arange(n_transient * spp, n_total) % spp) / spp
    y = np.cos(theta)
    x = q + y if joined else q

    X = np.fft.rfft(x)[n_keep]
    Y = np.fft.rfft(y)[n_keep]
    out = {
        "transmissibility": float(abs(X) / abs(Y)),
        "phase": float(wrap_lag_degrees(np.angle(Y) - np.angle(X))),
        "peak_transmissibility": float(np.max(np.abs(x))),
    }
    last = x[-spp:]
    out["peak_phase"] = float(wrap_lag_degrees(2.0 * np.pi * int(np.argmax(last)) / spp))

    vmax = float(np.max(np.abs(v)))
    stuck = np.abs(v) <= s["stick_velocity"] * vmax
    out["stuck_fraction"] = float(np.mean(stuck))
    out["stops_per_period"] = _count_stops(stuck) / n_keep
    out["periods"] = float(periods)
    out["steady_state"] = int(SteadyState.PERIOD_CAP)

    first_peak = float(np.max(np.abs(x[:spp])))
    last_peak = float(np.max(np.abs(last)))
    if float(np.max(np.abs(q))) <= s["stuck_displacement_per_atol"] * s["atol"]:
        out["regime"] = int(Regime.STUCK)
        out["stuck_fraction"], out["stops_per_period"] = 1.0, 0.0  # the velocity is chatter only
        if not joined:
            out["phase"] = out["peak_phase"] = math.nan
    elif last_peak > GROWTH_RATIO * first_peak and last_peak > GROWTH_MIN_PEAK:
        out["regime"] = int(Regime.UNBOUNDED)
        for name in _NUMERIC:
            out[name] = math.nan
    elif out["stops_per_period"] >= 0.5:
        out["regime"] = int(Regime.STICK_SLIP)
    else:
        out["regime"] = int(Regime.CONTINUOUS)
    return out


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None, **overrides) -> dict[str, np.ndarray]:
    """All requested outputs on the tile beta x r, arrays of shape (len(beta), len(r)).

    Returns the per-point variables plus `continuous_limit` (shape (len(r),), from the theory).
    Settings come as a dict (`settings=`, as the sweep runner passes them) and/or keywords.
    """
    if effects:
        raise ValueError(f"method paper models no effects (got {sorted(effects)})")
    if excitation not in CATALOGUE.excitations:
        raise ValueError(f"unknown excitation {excitation!r} (expected one of {CATALOGUE.excitations})")
    s = resolve_settings(settings, **overrides)
    r = np.atleast_1d(np.asarray(r, dtype=float))
    beta = np.atleast_1d(np.asarray(beta, dtype=float))
    names = variables_for(excitation, outputs)
    shape = (beta.size, r.size)
    out = {name: np.empty(shape, dtype=np.int8 if name in _INTEGER else float) for name in names}
    if names:
        for i, b in enumerate(beta):
            for j, rj in enumerate(r):
                point = solve_point(excitation, rj, b, s)
                for name in names:
                    out[name][i, j] = point[name]
    out["continuous_limit"] = theory.continuous_limit(excitation, r)
    return out
