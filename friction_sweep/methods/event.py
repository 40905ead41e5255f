"""The exact event-driven simulation as a sweep method (kernels in friction_sweep.kernels).

Per grid point: from rest, march the stroboscopic map with closed-form slip and stick segments
until it repeats (or shoot for the periodic orbit), then measure over whole periods. Valid in every
regime; the theory's continuous limit is written alongside for reference.
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels import steady
from friction_sweep.methods import theory

NAME = "event"
#: rough wall time per grid point on one core, for the huge-grid estimate (measured, rounded up)
COST_PER_POINT_S = 5e-4
EXCITATIONS = ("force", "base", "joined")
EFFECTS = ("viscous_damping", "static_friction_ratio")

VARIABLES = {
    "transmissibility": ("transmissibility", "peak_transmissibility"),
    "phase": ("phase", "peak_phase"),
    "regime": ("regime", "stops_per_period", "stuck_fraction", "periods", "steady_state", "orbit_period"),
}
_SLOTS = {
    "transmissibility": steady.OUT_TRANS,
    "peak_transmissibility": steady.OUT_PEAK,
    "phase": steady.OUT_PHASE,
    "peak_phase": steady.OUT_PEAK_PHASE,
    "regime": steady.OUT_REGIME,
    "stops_per_period": steady.OUT_STOPS,
    "stuck_fraction": steady.OUT_STUCK,
    "periods": steady.OUT_PERIODS,
    "steady_state": steady.OUT_STEADY,
    "orbit_period": steady.OUT_ORBIT,
}
_INTEGER = {"regime": np.int8, "steady_state": np.int8}

SETTINGS = {k: v for k, v in steady.DEFAULT_SETTINGS.items() if k not in ("kernel", "steps_per_period")}


def variables_for(excitation: str, outputs) -> tuple[str, ...]:
    names: list[str] = []
    for group in outputs:
        names.extend(VARIABLES.get(group, ()))
    return tuple(names)


def point_parameters(excitation: str, r, beta, effects=None):
    """Kernel parameters per point: forcing amplitude A, response offset c, kinetic and static
    friction, damping ratio (DESIGN.md §1: joined is z'' + z + beta sgn z' = r^2 cos, x = z + cos)."""
    effects = effects or {}
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    joined = excitation == "joined"
    A = r * r if joined else np.ones_like(r)
    c = np.full_like(r, 1.0 if joined else 0.0)
    bk = beta.copy()
    bs = beta * float(effects.get("static_friction_ratio", 1.0))
    zeta = np.full_like(r, float(effects.get("viscous_damping", 0.0)))
    return A, c, bk, bs, zeta


def solve_flat(excitation, r, beta, effects=None, **settings):
    """Raw kernel outputs (n, OUT_SIZE) for 1-D arrays of points."""
    r = np.ascontiguousarray(r, dtype=float)
    beta = np.ascontiguousarray(np.broadcast_to(beta, r.shape), dtype=float)
    A, c, bk, bs, zeta = point_parameters(excitation, r, beta, effects)
    out = np.empty((r.size, steady.OUT_SIZE))
    steady.solve_points(A, r, bk, bs, zeta, c, steady.settings_array(**settings), out)
    return out


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None) -> dict[str, np.ndarray]:
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    R, B = np.meshgrid(r, beta)
    raw = solve_flat(excitation, R.ravel(), B.ravel(), effects, **(settings or {}))
    result = {}
    for name in variables_for(excitation, outputs):
        values = raw[:, _SLOTS[name]].reshape(R.shape)
        if name in _INTEGER:
            values = values.astype(_INTEGER[name])
        result[name] = values
    result["continuous_limit"] = theory.continuous_limit(excitation, r)
    return result


def time_histories(excitation: str, points, samples_per_period: int, effects=None, settings=None):
    """Steady-state orbits of the given (r, beta) points, sampled uniformly in time.

    Returns arrays of shape (n_points, n_samples) with n_samples = samples_per_period times the
    longest orbit period among the points (shorter orbits are padded with NaN): time in forcing
    periods, the response x, the excitation, the relative displacement (the equation's q or z)
    and its velocity; plus per point the orbit period and the regime.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    r, beta = pts[:, 0], pts[:, 1]
    raw = solve_flat(excitation, r, beta, effects, **(settings or {}))
    sett = steady.settings_array(**(settings or {}))
    A, c, bk, bs, zeta = point_parameters(excitation, r, beta, effects)
    orbit = np.where(np.isfinite(raw[:, steady.OUT_ORBIT]), raw[:, steady.OUT_ORBIT], 0).astype(int)
    n = samples_per_period * max(1, int(orbit.max(initial=1)))
    shape = (pts.shape[0], n)
    out = {name: np.full(shape, np.nan) for name in
           ("history_time", "history_displacement", "history_excitation", "history_relative_displacement",
            "history_relative_velocity")}
    frac = np.arange(samples_per_period) / samples_per_period
    for i in range(pts.shape[0]):
        k = orbit[i]
        if k == 0:  # no steady state: nothing honest to show
            continue
        T = 2 * np.pi / r[i]
        ts = frac * T
        sq = np.empty((k, samples_per_period))
        sv = np.empty((k, samples_per_period))
        steady.sample_orbit(raw[i, steady.OUT_Q], raw[i, steady.OUT_V], int(raw[i, steady.OUT_MODE]), A[i], r[i],
                            bk[i], bs[i], zeta[i], c[i], sett[steady.SET_VTOL], int(sett[steady.SET_BUDGET]), k, ts,
                            sq, sv)
        m = k * samples_per_period
        phase = r[i] * np.tile(ts, k)
        out["history_time"][i, :m] = (np.arange(m) / samples_per_period)
        out["history_relative_displacement"][i, :m] = sq.ravel()
        out["history_relative_velocity"][i, :m] = sv.ravel()
        out["history_excitation"][i, :m] = np.cos(phase)
        out["history_displacement"][i, :m] = sq.ravel() + c[i] * np.cos(phase)
    out["history_orbit_period"] = orbit.astype(float)
    out["history_regime"] = raw[:, steady.OUT_REGIME].astype(np.int8)
    return out
