"""Solve a batch of (frequency, friction_scale) points of an assembled structure on the exact engine
(friction_sweep.kernels.structure) and turn its rows into the cube's per-dof, per-contact and per-point
arrays (the contract of issue 30)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels.structure.flow import CP_EY, CP_KT, CP_MU, CP_MUS, CP_SIZE, CP_SLOT
from friction_sweep.kernels.structure.steady import (
    PT_FLOQUET,
    PT_ORBIT,
    PT_PERIODS,
    PT_STEADY,
    PT_WORK,
    row_layout,
    row_size,
    solve_batch,
    state_size,
)
from friction_sweep.structures.model import Assembled, rest_state
from friction_sweep.theory import phase as phase_convention

#: a contact stuck for all but this fraction of the period is `stuck`
_STUCK_ALL = 1e-12
#: a mass whose first harmonic is under this fraction of its peak displacement stands still (held by a stuck
#: contact: its harmonic is the quadrature's rounding of a constant, 1e-16 of it, and its phase that rounding's);
#: amplitude 0 and phase NaN there, as for one mass stuck (kernels/steady.py)
_STILL = 1e-12


#: the methods that solve a structure: the exact flow between events, or classical RK4 on a fixed grid with the
#: same modes and switches (kernels/structure/rk4.py)
METHODS = ("event", "rk4")


def engine_settings(settings: dict | None, outputs: Sequence[str], method: str = "event") -> np.ndarray:
    """The kernel settings record: the event method's defaults (and rk4's steps_per_period) under `settings`;
    stability from outputs; the integrator from the method."""
    from friction_sweep.kernels.settings import KERNEL_EVENT, KERNEL_RK4
    from friction_sweep.methods.event import for_outputs, kernel_settings

    if method not in METHODS:
        raise ValueError(f"a structure is solved by method {' or '.join(METHODS)} (got {method!r})")
    kernel = KERNEL_RK4 if method == "rk4" else KERNEL_EVENT
    return kernel_settings({**for_outputs(settings, outputs), "kernel": kernel})


def contact_parameters(a: Assembled) -> np.ndarray:
    """Per contact: base amplitude at its end, kinetic and static friction, Jenkins stiffness, slider slot."""
    m = len(a.contact_names)
    cp = np.zeros((m, CP_SIZE))
    cp[:, CP_EY] = a.e * a.base_amplitude if a.excitation == "base" else 0.0
    cp[:, CP_MU] = a.mu
    cp[:, CP_MUS] = a.mu_s
    cp[:, CP_KT] = a.kt
    cp[:, CP_SLOT] = np.cumsum(a.kt > 0) - 1
    return cp


def engine_arguments(a: Assembled, settings: dict | None = None,
                     outputs: Sequence[str] = ("amplitude", "phase", "regime"), method: str = "event") -> tuple:
    """steady.solve_batch's arguments for structure a, in its order, without the points and the rows:
    (M^-1, K, C, W (m x n), F_cos, F_sin_per_w, contact parameters, rest state, settings record)."""
    n, m = len(a.dof_names), len(a.contact_names)
    return (np.linalg.inv(a.M), a.K, a.C, np.ascontiguousarray(a.W).reshape(m, n), a.F_cos, a.F_sin_per_w,
            contact_parameters(a), rest_state(a), engine_settings(settings, outputs, method))


def replay_orbits(solved: dict) -> np.ndarray:
    """The periods of each solved point's steady orbit, to replay it from its end_state (time histories,
    harmonics): orbit_period where the search converged, 0 where there is no orbit to replay."""
    converged = solved["steady_state"] == SteadyState.CONVERGED
    return np.where(converged, np.nan_to_num(solved["orbit_period"]), 0).astype(np.int64)


def solve_points(a: Assembled, frequency, friction_scale, settings: dict | None = None,
                 outputs: Sequence[str] = ("amplitude", "phase", "regime"), method: str = "event",
                 start=None) -> dict[str, np.ndarray]:
    """Steady state of each point (frequency[i], friction_scale[i]) by `method` (METHODS): per dof (P, n) amplitude,
    peak_amplitude, phase; per contact (P, m) regime, stops_per_period, slips_per_period (NaN for a rigid
    contact), stuck_fraction, friction_energy; per point (P,) steady_state, orbit_period, periods,
    floquet_multiplier (NaN unless outputs has "stability"), work; and end_state (P, state_size), the state
    at the section (t = 0, the excitation's maximum) where the search stopped, the steady orbit's where it
    converged (x, v, each Jenkins slider's position, each contact's status: the engine's, steady.state_size).
    From rest, or from start (P, state_size) where given (a NaN row: from rest): another point's end_state
    follows that orbit here. Pure and deterministic, a point's result depends on its inputs only."""
    w = np.ascontiguousarray(np.asarray(frequency, dtype=float).ravel())
    s = np.ascontiguousarray(np.asarray(friction_scale, dtype=float).ravel())
    if w.shape != s.shape:
        raise ValueError(f"frequency and friction_scale differ in length ({w.size}, {s.size})")
    n, m = len(a.dof_names), len(a.contact_names)
    size = state_size(n, m, int(np.count_nonzero(a.kt > 0)))
    starts = np.full((w.size, size), np.nan) if start is None else np.array(start, dtype=float).reshape(w.size, size)
    rows = np.full((w.size, row_size(n, m)), np.nan)
    ends = np.full((w.size, size), np.nan)
    good = np.isfinite(w) & (w > 0) & np.isfinite(s) & (s >= 0)
    if good.any():
        sub = np.full((int(good.sum()), rows.shape[1]), np.nan)
        sub_end = np.full((int(good.sum()), size), np.nan)
        args = engine_arguments(a, settings, outputs, method)
        solve_batch(*args[:8], w[good], s[good], args[8], sub, np.ascontiguousarray(starts[good]), sub_end)
        rows[good] = sub
        ends[good] = sub_end
    # a contact whose friction is zero at the point exerts no force: the engine leaves it out (INACTIVE)
    active = np.asarray(a.mu)[None, :] * s[:, None] > 0.0
    return {**_arrays(a, rows, good, active), "end_state": ends}


def _arrays(a: Assembled, rows: np.ndarray, good: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]:
    """The cube's arrays from the engine's rows. Labels per contact: a contact without friction (not
    `active`) exerts no force and is `continuous` whatever the engine counted; a Jenkins contact whose slider
    never slips is `stuck` with stuck_fraction 1 (jenkins_steady's rule), otherwise its stuck_fraction is the
    time it holds the mass (period.py's measurement); a rigid contact is `stuck` when stuck all period."""
    n, m = len(a.dof_names), len(a.contact_names)
    lay = row_layout(n, m)
    pt = rows[:, lay["point"]]
    steady = np.where(good, pt[:, PT_STEADY], SteadyState.NONFINITE)
    steady = np.nan_to_num(steady, nan=SteadyState.NONFINITE).astype(np.int8)
    ok = steady == SteadyState.CONVERGED
    unit = a.amplitude_unit
    xc, xs = rows[:, lay["harm_cos"]], rows[:, lay["harm_sin"]]
    peak = rows[:, lay["peak"]]
    amplitude = np.hypot(xc, xs)
    with np.errstate(invalid="ignore"):
        still = amplitude <= _STILL * peak
    stops = rows[:, lay["stops"]]
    slips = rows[:, lay["slips"]]
    stuck = rows[:, lay["stuck_fraction"]]
    regime = np.full(stops.shape, Regime.UNSETTLED, dtype=np.int8)
    jenkins = np.broadcast_to(a.kt > 0, stops.shape)
    with np.errstate(invalid="ignore"):
        slider_held = jenkins & active & (slips == 0)
        never_slips = active & np.where(jenkins, slider_held, stuck >= 1.0 - _STUCK_ALL)
    stuck = np.where(slider_held, 1.0, stuck)
    # a slider that never slips never stops either: the measurement counted one a period at one mass, kappa 10,
    # undamped, beta 2, w 2.12 (force) and 1.32 (joined), where the 1-DoF kernels and the independent integrator
    # count none
    stops = np.where(slider_held, 0.0, stops)
    moving = np.where(stops > 0, Regime.STICK_SLIP, Regime.CONTINUOUS)
    settled = np.where(never_slips, Regime.STUCK, moving).astype(np.int8)
    regime[ok] = settled[ok]
    regime[steady == SteadyState.GROWING] = Regime.UNBOUNDED
    # an orbit with a contact stuck all period is one of a continuum (every stuck position whose force stays in
    # the band is an orbit, multiplier 1 along them): not isolated, no multiplier, as for one mass at rest
    # (docs/equations.md §3)
    floquet = np.where((regime == Regime.STUCK).any(axis=1), np.nan, pt[:, PT_FLOQUET])
    return {
        "amplitude": np.where(still, 0.0, amplitude) / unit,
        "peak_amplitude": peak / unit,
        "phase": np.where(still, np.nan, phase_convention.wrap_degrees(np.degrees(np.arctan2(xs, xc)))),
        "regime": regime,
        "stops_per_period": stops,
        "slips_per_period": slips,
        "stuck_fraction": np.where(ok[:, None], np.minimum(stuck, 1.0), np.nan),
        "friction_energy": rows[:, lay["friction_energy"]],
        "steady_state": steady,
        "orbit_period": pt[:, PT_ORBIT],
        "periods": pt[:, PT_PERIODS],
        "floquet_multiplier": floquet,
        "work": pt[:, PT_WORK],
    }
