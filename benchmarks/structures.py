"""Per-point cost of the multi-DoF engine (issue 30), side by side in one process (make bench):

- 2 masses, 1 rigid contact (the issue's blade and platform damper) over a 200 x 20 (frequency x
  friction_scale) plane spanning every regime: median and quartiles of CPU us per point;
- a 10-mass chain with 2 Jenkins contacts: CPU ms per point over a small plane;
- the engine at n = 1 beside the dedicated 1-DoF kernels (methods.event) on the same points;
- one compilation serves every size: the dispatcher's signatures after n = 1, 2, 10;
- the cold compile: run with an empty NUMBA_CACHE_DIR to see it (printed: CPU seconds of the first call).

CPU time (time.process_time) per point, each point timed alone, so the figures hold on a loaded machine.
Usage: python benchmarks/structures.py [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.kernels import steady as one_dof
from friction_sweep.methods import event
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

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
    """CPU seconds of each point, solved alone."""
    out = np.empty(w.size)
    for i in range(w.size):
        t = time.process_time()
        solve_points(a, w[i:i + 1], s[i:i + 1])
        out[i] = time.process_time() - t
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="a 40 x 5 plane instead of 200 x 20")
    quick = ap.parse_args().quick
    t = time.process_time()
    solve_points(assemble(BLADE), np.array([1.0]), np.array([1.0]))
    print(f"first call (compile, or load from the numba cache): {time.process_time() - t:.1f} s CPU")
    nw, ns = (40, 5) if quick else (200, 20)
    W, S = np.meshgrid(np.linspace(0.2, 3.0, nw), np.geomspace(0.05, 20.0, ns), indexing="ij")
    a = assemble(BLADE)
    cost = per_point(a, W.ravel(), S.ravel())
    res = solve_points(a, W.ravel(), S.ravel())
    regimes = np.bincount(res["regime"].ravel(), minlength=5)
    q = np.percentile(cost, [25, 50, 75]) * 1e6
    print(f"2 masses, 1 rigid contact, {nw} x {ns}: median {q[1]:.0f} us/point (quartiles {q[0]:.0f}, {q[2]:.0f}; "
          f"max {cost.max() * 1e3:.1f} ms); regimes stuck/stick_slip/continuous/unbounded/unsettled {regimes}")
    c = assemble(chain10())
    W2, S2 = np.meshgrid(np.linspace(0.1, 2.0, 10 if quick else 20), [0.5, 1.0, 2.0], indexing="ij")
    cost2 = per_point(c, W2.ravel(), S2.ravel())
    print(f"10-mass chain, 2 Jenkins contacts: median {np.median(cost2) * 1e3:.2f} ms/point "
          f"(max {cost2.max() * 1e3:.1f} ms)")
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
    from friction_sweep.kernels.structure.steady import solve_batch

    print(f"compiled signatures of the engine after n = 1, 2, 10: {len(solve_batch.signatures)}")


if __name__ == "__main__":
    main()
