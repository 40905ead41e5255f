"""Exact harmonics of a structure's steady orbits (outputs: harmonics; issue 32): each mass's absolute
displacement and each contact's force as one-sided complex Fourier coefficients k = 0..H of the forcing
frequency, integrated in closed form over the exact flow's steps (kernels.structure.harmonics), from the
orbit's state at the section (t = 0, the excitation's maximum)."""

from __future__ import annotations

import numpy as np

from friction_sweep.structures.model import Assembled
from friction_sweep.structures.solve import engine_arguments, replay_orbits, solve_points


def orbit_harmonics(a: Assembled, frequency, friction_scale, H: int, settings: dict | None = None,
                    solved: dict | None = None) -> dict[str, np.ndarray]:
    """The harmonics k = 0..H of the points (frequency[i], friction_scale[i]) from their solve (solved:
    solve_points' arrays for these points, else solved here): displacement (P, H + 1, n) complex, in the
    amplitudes' unit (x_i(t) = Re sum_k X_ik e^{i k w t}, so |X_i1| is `amplitude` and -arg X_i1 `phase`), and
    contact_force (P, H + 1, m), in the time histories' unit; NaN where a point has no steady state or its
    replay fails. A period-k orbit's coefficients are over its k periods (harmonics of w; its subharmonics are
    not among them)."""
    from friction_sweep.kernels.structure.harmonics import harmonics_batch

    w = np.ascontiguousarray(np.asarray(frequency, dtype=float).ravel())
    s = np.ascontiguousarray(np.asarray(friction_scale, dtype=float).ravel())
    if solved is None:
        solved = solve_points(a, w, s, settings)
    n, m = len(a.dof_names), len(a.contact_names)
    out = np.full((w.size, int(H) + 1, n + m), np.nan, dtype=complex)
    args = engine_arguments(a, settings)
    harmonics_batch(*args[:7], w, s, args[8], np.ascontiguousarray(solved["end_state"]), replay_orbits(solved), out)
    return {"displacement": out[:, :, :n] / a.amplitude_unit, "contact_force": out[:, :, n:]}
