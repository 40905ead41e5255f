"""Issue 31 item 6: can the multi-DoF engine replace the dedicated 1-DoF Jenkins kernels (make bench)?

The 1-DoF Jenkins contact has its own stack of kernels (kernels/jenkins.py, jenkins_rk4.py,
jenkins_steady.py); the issue retires it if the multi-DoF engine (kernels/structure), run on the same
scene written as a one-mass structure, costs at most 2x as much per point. Side by side in one process, on
paper-like planes of the force scene (frequency ratio r x force ratio beta) at kappa = 10, 100, 1000:

- CPU microseconds per point of each, the whole plane solved in one call (each engine's batch path, one
  thread), after a first call that compiles or loads both;
- their agreement where both converge: the largest |T_engine - T_1dof| and the share of points whose
  regime differs.

Usage: python benchmarks/one_engine.py [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.codes import SteadyState
from friction_sweep.kernels import steady as one_dof
from friction_sweep.methods import event
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

KAPPAS = (10.0, 100.0, 1000.0)


def one_mass(kappa: float) -> StructureDef:
    """The 1-DoF force scene x'' + x + (Jenkins contact of stiffness kappa, friction beta) = cos r t as a
    structure: unit mass and spring to ground, the contact to ground, unit forcing (friction_scale = beta)."""
    contact = ContactDef("c", ("m", "ground"), 1.0, kappa)
    return StructureDef("force", {"m": 1.0}, (("ground", "m", 1.0),), (), (contact,), {"m": 1.0})


def cpu(fn) -> tuple[float, object]:
    t = time.process_time()
    out = fn()
    return time.process_time() - t, out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="a 20 x 5 plane instead of 60 x 15")
    quick = ap.parse_args().quick
    nr, nb = (20, 5) if quick else (60, 15)
    R, B = np.meshgrid(np.linspace(0.2, 3.0, nr), np.geomspace(0.05, 2.0, nb), indexing="ij")
    r, beta = R.ravel(), B.ravel()
    print(f"1-DoF force scene with a Jenkins contact, {nr} x {nb} (r x beta) points, CPU us per point, one thread")
    print("| kappa | multi-DoF engine | dedicated Jenkins kernels | ratio | max abs T difference | regimes differing |")
    print("|---|---|---|---|---|---|")
    for kappa in KAPPAS:
        a = assemble(one_mass(kappa))
        effects = {"contact_stiffness": kappa}
        # compile (or load from the cache) both before timing
        solve_points(a, r[:1], beta[:1])
        event.solve_flat("base", r[:1], beta[:1], effects)
        t_engine, got = cpu(lambda: solve_points(a, r, beta))  # noqa: B023 (called at once)
        # the 1-DoF force scene is the base scene's equation in the kernels (x'' + x + f = cos r t)
        t_one, ref = cpu(lambda: event.solve_flat("base", r, beta, effects))  # noqa: B023
        converged = SteadyState.CONVERGED
        both = (got["steady_state"] == converged) & (ref[:, one_dof.OUT_STEADY_STATE] == converged)
        diff = np.max(np.abs(got["amplitude"][both, 0] - ref[both, one_dof.OUT_TRANSMISSIBILITY]), initial=0.0)
        differ = np.mean(got["regime"][both, 0] != ref[both, one_dof.OUT_REGIME].astype(np.int8)) if both.any() \
            else np.nan
        e, o = t_engine / r.size * 1e6, t_one / r.size * 1e6
        print(f"| {kappa:g} | {e:.0f} | {o:.0f} | {e / o:.1f}x | {diff:.1e} | {differ:.1%} |")


if __name__ == "__main__":
    main()
