"""Where a structure's points start: the second start where static friction exceeds kinetic (the 1-DoF rule of
methods.event, README "Two steady states").

With static above kinetic friction at some contact, a point can hold two steady states (a contact stopped at a
reversal stays stuck where the force there is below its static friction), so each point is also solved from a
moving start: the state at the section of the orbit that kinetic friction alone sustains there (the same
point with every static_friction_ratio 1), or where that motion has no steady state, the state where its
search stopped. Its variables are stored beside those from rest with MOVING_SUFFIX, and `steady_states` counts
the distinct states (methods.event.distinct_states: a lower bound). With static = kinetic friction the
energy of the difference of two motions does not increase (DESIGN §7, uniqueness), and one start suffices.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from friction_sweep.structures.model import Assembled
from friction_sweep.structures.solve import solve_points

#: what `steady_states` compares: per point, the regime and stops of each contact and the amplitude of each mass
_COMPARED = ("regime", "stops_per_period", "amplitude", "steady_state")


def two_starts(a: Assembled) -> bool:
    """Whether a point of the structure can hold two steady states: static above kinetic friction somewhere."""
    return bool(np.any(a.mu_s > a.mu))


def kinetic(a: Assembled) -> Assembled:
    """The structure with each contact's static friction lowered to its kinetic friction."""
    return replace(a, mu_s=a.mu.copy())


def solve_moving(a: Assembled, frequency, friction_scale, settings: dict | None = None,
                 outputs: Sequence[str] = ("amplitude", "phase", "regime"),
                 method: str = "event") -> dict[str, np.ndarray]:
    """solve_points from the moving start: each point started from the end state of the same point with
    kinetic friction only (its steady orbit's, or where it has none the state where its search stopped; a
    state that is not finite: rest)."""
    seed = solve_points(kinetic(a), frequency, friction_scale, settings,
                        tuple(o for o in outputs if o != "stability"), method)  # only its end state is kept
    return solve_points(a, frequency, friction_scale, settings, outputs, method, start=seed["end_state"])


def count_states(rest: dict[str, np.ndarray], moving: dict[str, np.ndarray]) -> np.ndarray:
    """Distinct steady states per point among the solves from rest and from the moving start (solve_points'
    dicts), by the 1-DoF rule (methods.event.distinct_states) over every contact and mass."""
    from friction_sweep.methods.event import distinct_states

    return distinct_states(*((rest[name], moving[name]) for name in _COMPARED))


def solve_sweep(a: Assembled, frequency, friction_scale: float, direction: str, settings: dict | None = None,
                outputs: Sequence[str] = ("amplitude", "phase", "regime"),
                method: str = "event") -> dict[str, np.ndarray]:
    """A stepped-sine sweep at one friction scale, as rigs are run (the 1-DoF `sweep:`): the frequencies in
    sweep order (ascending for `up`, descending for `down`), the first from rest, each next one from the
    state where the one before stopped (its steady orbit's at the section; rest where that is not finite).
    The arrays of solve_points, in the order of `frequency` as given."""
    w = np.asarray(frequency, dtype=float).ravel()
    order = np.argsort(w, kind="stable")
    if direction == "down":
        order = order[::-1]
    out: dict[str, np.ndarray] = {}
    start = None
    for i in order:
        point = solve_points(a, w[i:i + 1], np.array([friction_scale], dtype=float), settings, outputs, method,
                             start=start)
        start = point["end_state"]
        for name, values in point.items():
            if name not in out:
                out[name] = np.empty((w.size, *values.shape[1:]), dtype=values.dtype)
            out[name][i] = values[0]
    return out
