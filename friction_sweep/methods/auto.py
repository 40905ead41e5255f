"""method: auto -- Den Hartog's closed form where the mass provably slides without stops, the
exact event simulation everywhere else. The cube records which produced each point (`method_used`).

"Provably" means the theory's continuous forecast with a margin from its boundary:
b < (1 - margin) beta*(r), b the friction ratio against the force amplitude (beta, or beta/r^2 for
joined), and r != 1 (to the tie tolerance of friction_sweep.ties). On the boundary itself the
theory and the simulation agree only in the limit, so those points are simulated.
"""

from __future__ import annotations

import numpy as np

from friction_sweep import catalogue, ties
from friction_sweep.codes import MethodUsed, Regime, SteadyState
from friction_sweep.kernels import steady
from friction_sweep.methods import event, theory

CATALOGUE = catalogue.method("auto")  # no effects: the theory models none; a scene with them uses `event`

def time_histories(excitation: str, points, samples_per_period: int, effects=None, settings=None):
    """Every time history is simulated (the theory has no orbit to sample): event's, without auto's own
    theory_margin."""
    settings = {k: v for k, v in (settings or {}).items() if k != "theory_margin"}
    return event.time_histories(excitation, points, samples_per_period, effects, settings)


def variables_for(excitation: str, outputs) -> tuple[str, ...]:
    return event.variables_for(excitation, outputs) + ("method_used",)


def theory_mask(th, r, beta, margin):
    """Points (beta x r) where the theory is used, from the theory's own tile `th` (its regime
    forecast and its continuous limit in the scene's convention, so beta*(r) is computed once)."""
    R, B = np.meshgrid(r, beta)
    limit = th["continuous_limit"][None, :]
    return (th["regime"] == Regime.CONTINUOUS) & (B < (1.0 - margin) * limit) & ~ties.at_resonance(R)


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None) -> dict[str, np.ndarray]:
    if effects:
        raise ValueError(f"method auto models no effects (got {sorted(effects)}); use event")
    settings = event.for_outputs(settings, outputs)
    margin = float(settings.pop("theory_margin", CATALOGUE.defaults["theory_margin"]))
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    modelled = (o for o in outputs if o in theory.CATALOGUE.outputs)  # the theory has no orbit to take harmonics of
    th = theory.compute_tile(excitation, r, beta, tuple(dict.fromkeys((*modelled, "regime"))))
    use_theory = theory_mask(th, r, beta, margin)
    names = variables_for(excitation, outputs)
    shape = use_theory.shape
    out = {name: np.full(shape, np.nan) for name in names}
    out["method_used"] = np.where(use_theory, MethodUsed.THEORY, MethodUsed.EVENT).astype(np.int8)

    for name in names:
        if name in th:
            out[name][use_theory] = th[name][use_theory]
    if "regime" in outputs:
        out["stuck_fraction"][use_theory] = 0.0
        out["periods"][use_theory] = 0.0
        out["orbit_period"][use_theory] = 1.0
        out["steady_state"] = np.where(use_theory, SteadyState.NOT_SIMULATED, SteadyState.CONVERGED).astype(np.int8)

    R, B = np.meshgrid(r, beta)
    sim = ~use_theory
    if "harmonics" in outputs:
        # the harmonics need the orbit, which the theory does not give: every point is simulated for them (the
        # theory's points by one exact period from Den Hartog's orbit), its other variables as without them
        H = int(settings.get("harmonics", CATALOGUE.defaults["harmonics"]))
        everywhere = event.solve_flat(excitation, R.ravel(), B.ravel(), None, **settings)
        out.update({name: values.reshape(H + 1, *shape) for name, values in
                    event.harmonics(excitation, R.ravel(), B.ravel(), everywhere, H, None, settings).items()})
    if np.any(sim):
        raw = everywhere[sim.ravel()] if "harmonics" in outputs else \
            event.solve_flat(excitation, R[sim], B[sim], None, **settings)
        for name in names:
            if name in steady.OUT or name == "transmitted_force":
                out[name][sim] = event.kernel_variable(name, raw, excitation, R[sim])
    for name, dtype in (("regime", np.int8), ("steady_state", np.int8)):
        if name in out:
            out[name] = out[name].astype(dtype)
    out["continuous_limit"] = th["continuous_limit"]
    return out
