"""Per-point cost of the multi-DoF engine (issue 30), side by side in one process (make bench):

- 2 masses, 1 rigid contact (the issue's blade and platform damper) over a 200 x 20 (frequency x
  friction_scale) plane spanning every regime: median and quartiles of CPU us per point;
- a 10-mass chain with 2 Jenkins contacts: CPU ms per point over a small plane;
- the engine at n = 1 beside the dedicated 1-DoF kernels (methods.event) on the same points;
- one compilation serves every size: the dispatcher's signatures after n = 1, 2, 10;
- the cold compile: run with an empty NUMBA_CACHE_DIR to see it (printed: CPU seconds of the first call);
- against the independent DOP853 integrator of the tests (tests/independent_structure.py) at rtol 1e-9, on
  the points of tests/test_structure_reference.py (2- and 3-mass structures in every regime): the smallest
  and the median ratio of its CPU time per point to the engine's.

CPU time (time.process_time) per point, each point timed alone, so the figures hold on a loaded machine.
Each plane's figures are given twice: through solve_points (what one call for one point costs, with its
Python set-up and the cube's arrays, about 120 us) and of the engine alone (steady.solve_batch on the
arguments solve_points prepares once per call: the per-point cost of a sweep, whose tiles make one call
for many points).
Usage: python benchmarks/structures.py [--quick] [--no-reference]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from friction_sweep.kernels import steady as one_dof
from friction_sweep.kernels.structure.steady import row_size, solve_batch, state_size
from friction_sweep.methods import event
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points
from friction_sweep.structures.solve import engine_arguments

BLADE = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 0.3),),
                     {"blade": 1.0})


def chain10() -> StructureDef:
    names = [f"m{i}" for i in range(10)]
    springs = (("ground", names[0], 1.0), *((names[i], names[i + 1], 1.0) for i in range(9)))
    dampers = tuple(("ground", name, 0.01) for name in names)
    contacts = (ContactDef("c3", (names[3], "ground"), 0.2, 5.0), ContactDef("c9", (names[9], "ground"), 0.3, 5.0))
    return StructureDef("force", dict.fromkeys(names, 1.0), springs, dampers, contacts, {names[9]: 1.0})


def per_point(a, w, s) -> np.ndarray:
    """CPU seconds of each point, solved alone by solve_points."""
    out = np.empty(w.size)
    for i in range(w.size):
        t = time.process_time()
        solve_points(a, w[i:i + 1], s[i:i + 1])
        out[i] = time.process_time() - t
    return out


def engine_per_point(a, w, s, repeat: int = 1) -> np.ndarray:
    """CPU seconds of each point, solved alone by the engine (steady.solve_batch; the least of `repeat`
    runs, a point's result depending on its inputs only)."""
    args = engine_arguments(a)
    n, m = len(a.dof_names), len(a.contact_names)
    row = np.empty((1, row_size(n, m)))
    start = np.full((1, state_size(n, m, int(np.count_nonzero(a.kt > 0)))), np.nan)  # NaN: from rest
    end = np.empty_like(start)
    out = np.full(w.size, np.inf)
    for i in range(w.size):
        for _ in range(repeat):
            t = time.process_time()
            solve_batch(*args[:8], w[i:i + 1], s[i:i + 1], args[8], row, start, end)
            out[i] = min(out[i], time.process_time() - t)
    return out


def against_dop853(rtol: float = 1e-9) -> None:
    """The independent DOP853 integrator's CPU time per point over the engine's, on the reference test's
    points (each timed alone; the engine's the least of 5 runs)."""
    tests = Path(__file__).resolve().parents[1] / "tests"
    sys.path.insert(0, str(tests))
    import independent_structure as ref
    from test_structure_reference import POINTS, STRUCTURES

    ref.RTOL = rtol
    ratios = []
    missed = []
    for point in POINTS:
        name, w, scale = point
        t = time.process_time()
        auto = ref.Automaton(ref.model(STRUCTURES[name], scale), w)
        try:
            # settled to the integrator's own accuracy (its default, 1e-12, is below what rtol 1e-9 repeats)
            z, modes, k = auto.steady(tol=10.0 * rtol)
        except AssertionError:
            missed.append(point)
            continue
        auto.measure(z, modes, k)
        slow = time.process_time() - t
        fast = engine_per_point(assemble(STRUCTURES[name]), np.array([w]), np.array([scale]), repeat=5)[0]
        ratios.append((slow / fast, point))
    r = np.array([q for q, _ in ratios])
    worst = ratios[int(np.argmin(r))][1]
    print(f"against DOP853 (rtol {rtol:g}, steady to {10 * rtol:g}; tests/independent_structure.py) on {r.size} "
          f"points of tests/test_structure_reference.py, engine alone: smallest ratio {r.min():.0f} {worst}, median "
          f"{np.median(r):.0f}" + (f"; no steady state for DOP853 at {missed}" if missed else ""))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="a 40 x 5 plane instead of 200 x 20")
    ap.add_argument("--no-reference", action="store_true", help="without the DOP853 ratio (minutes)")
    opts = ap.parse_args()
    quick = opts.quick
    t = time.process_time()
    solve_points(assemble(BLADE), np.array([1.0]), np.array([1.0]))
    print(f"first call (compile, or load from the numba cache): {time.process_time() - t:.1f} s CPU")
    nw, ns = (40, 5) if quick else (200, 20)
    W, S = np.meshgrid(np.linspace(0.2, 3.0, nw), np.geomspace(0.05, 20.0, ns), indexing="ij")
    a = assemble(BLADE)
    cost = per_point(a, W.ravel(), S.ravel())
    bare = engine_per_point(a, W.ravel(), S.ravel())
    res = solve_points(a, W.ravel(), S.ravel())
    regimes = np.bincount(res["regime"].ravel(), minlength=5)
    q = np.percentile(cost, [25, 50, 75]) * 1e6
    qe = np.percentile(bare, [25, 50, 75]) * 1e6
    print(f"2 masses, 1 rigid contact, {nw} x {ns}: median {q[1]:.0f} us/point through solve_points (quartiles "
          f"{q[0]:.0f}, {q[2]:.0f}; max {cost.max() * 1e3:.1f} ms); engine alone median {qe[1]:.0f} us/point "
          f"(quartiles {qe[0]:.0f}, {qe[2]:.0f}, mean {bare.mean() * 1e6:.0f}); median work "
          f"{np.median(res['work']):.0f}; regimes stuck/stick_slip/continuous/unbounded/unsettled {regimes}")
    c = assemble(chain10())
    W2, S2 = np.meshgrid(np.linspace(0.1, 2.0, 10 if quick else 20), [0.5, 1.0, 2.0], indexing="ij")
    cost2 = per_point(c, W2.ravel(), S2.ravel())
    bare2 = engine_per_point(c, W2.ravel(), S2.ravel())
    print(f"10-mass chain, 2 Jenkins contacts: median {np.median(cost2) * 1e3:.2f} ms/point through solve_points "
          f"(max {cost2.max() * 1e3:.1f} ms); engine alone median {np.median(bare2) * 1e3:.2f} ms/point")
    r = np.linspace(0.2, 3.0, 40)
    beta = np.full(r.size, 0.5)
    one = assemble(StructureDef("base", {"m": 1.0}, (("base", "m", 1.0),), (),
                                (ContactDef("c", ("m", "ground"), 1.0),), {}))
    e1 = per_point(one, r, beta)
    e0 = np.empty(r.size)
    for i in range(r.size):
        t = time.process_time()
        event.solve_flat("base", r[i:i + 1], beta[i:i + 1])
        e0[i] = time.process_time() - t
    print(f"n = 1 (base, beta 0.5, 40 r): engine median {np.median(e1) * 1e6:.0f} us/point, dedicated 1-DoF kernels "
          f"{np.median(e0) * 1e6:.0f} us/point ({one_dof.__name__})")
    print(f"compiled signatures of the engine after n = 1, 2, 10: {len(solve_batch.signatures)}")
    if not opts.no_reference:
        against_dop853()


if __name__ == "__main__":
    main()
