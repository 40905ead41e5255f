"""Time histories of a structure's steady orbits (issue 31): each mass's absolute displacement and each
contact's force over the orbit's periods, sampled uniformly from the excitation's maximum (t = 0), by the
engine's exact flow (kernels.structure.history.sample_orbit) from the orbit's state at the section."""

from __future__ import annotations

import numpy as np

from friction_sweep.structures.model import Assembled
from friction_sweep.structures.solve import engine_arguments, replay_orbits, solve_points


def time_histories(a: Assembled, points, samples_per_period: int = 256, settings: dict | None = None,
                   start=None) -> dict[str, np.ndarray]:
    """The steady orbits of the points (frequency, friction_scale) (P, 2), from rest or from start (P,
    state_size; solve_points' end_state of another solve, e.g. the moving start's), sampled
    samples_per_period times a forcing period over the orbit's orbit_period periods. Returns time (P, L) in
    forcing periods from the excitation's maximum, displacement (P, L, n) and contact_force (P, L, m) (the
    force lambda_j on contact j's relative coordinate u_j, DESIGN §7: the masses feel -w_j lambda_j), with
    L = samples_per_period times the longest orbit among the points (shorter ones padded with NaN, and a
    point without a steady state all NaN), and the solve's arrays (solve_points) under their names."""
    from friction_sweep.kernels.structure.history import SAMPLED, sample_orbit
    from friction_sweep.kernels.structure.steady import point_forces

    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    w, s = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    solved = solve_points(a, w, s, settings, start=start)
    n, m = len(a.dof_names), len(a.contact_names)
    orbit = replay_orbits(solved)
    S = int(samples_per_period)
    length = S * max(1, int(orbit.max(initial=1)))
    time = np.full((w.size, length), np.nan)
    xs = np.full((w.size, length, n), np.nan)
    lams = np.full((w.size, length, m), np.nan)
    Minv, K, C, W, F_cos, F_sin_per_w, cp0, _, sett = engine_arguments(a, settings, ())
    F, cp = np.empty((2, n)), cp0.copy()
    for i in np.flatnonzero(orbit > 0):
        point_forces(F_cos, F_sin_per_w, cp0, w[i], s[i], F, cp)  # the point's, as solve_batch's
        k = orbit[i]
        x = np.empty((k * S, n))
        lam = np.empty((k * S, m))
        if sample_orbit(Minv, K, C, W, F, cp, w[i], sett, np.ascontiguousarray(solved["end_state"][i]), k, S,
                        x, lam) != SAMPLED:
            continue  # the replay ran out of budget: incomplete samples are not shown
        time[i, :k * S] = np.arange(k * S) / S
        xs[i, :k * S] = x
        lams[i, :k * S] = lam
    return {**solved, "time": time, "displacement": xs, "contact_force": lams}
