"""Work against precision on structures (issue 31 item 3): method rk4 (kernels/structure/rk4.py) at several
steps_per_period, and method event at its defaults, against event at steady_tol 1e-13, on two structures:

- blade: 2 masses, 1 rigid contact (the issue's blade and under-platform damper, benchmarks/structures.py);
- jenkins3: 3 masses in a chain, a Jenkins contact (k_t 5) on the middle one (tests/test_structure_rk4.py).

Each on a plane of frequency x friction_scale whose points are grouped by the reference's regime of the
contact (stuck, stick_slip, continuous). Error: the largest over a group's points of max_i |A_i - A_i,ref| /
max_i A_i,ref (A_i: each mass's first-harmonic amplitude; a point whose steady state or regime differs counts
as an infinite error). Cost: CPU microseconds a point (time.process_time over the plane, compiled before).

Usage: python benchmarks/structure_rk4.py [--quick]   (prints a markdown table)
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.codes import Regime
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

BLADE = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 0.3),),
                     {"blade": 1.0})
JENKINS3 = StructureDef("force", {"a": 1.0, "b": 0.5, "c": 1.0},
                        (("ground", "a", 1.0), ("a", "b", 1.0), ("b", "c", 1.0)),
                        (("ground", "a", 0.02), ("ground", "c", 0.02)),
                        (ContactDef("mid", ("b", "ground"), 0.3, 5.0),), {"c": 1.0})
STRUCTURES = {"blade": BLADE, "jenkins3": JENKINS3}
REFERENCE = {"steady_tol": 1e-13}
ROWS = [("event", {}), *(("rk4", {"steps_per_period": n}) for n in (64, 128, 256, 512, 1024))]
GROUPS = (Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS)


def measure(definition: StructureDef, quick: bool) -> list[tuple[str, str, dict, float]]:
    """Per row: (method, label, {regime: worst error}, us a point)."""
    a = assemble(definition)
    W, S = np.meshgrid(np.linspace(0.3, 2.8, 6 if quick else 16), np.geomspace(0.1, 20.0, 4 if quick else 8),
                       indexing="ij")
    w, s = W.ravel(), S.ravel()
    ref = solve_points(a, w, s, REFERENCE)
    scale = ref["amplitude"].max(axis=1)
    regime = ref["regime"][:, 0]
    out = []
    for method, settings in ROWS:
        solve_points(a, w[:1], s[:1], settings, method=method)  # compiled before timing
        t = time.process_time()
        r = solve_points(a, w, s, settings, method=method)
        us = (time.process_time() - t) / w.size * 1e6
        err = np.abs(r["amplitude"] - ref["amplitude"]).max(axis=1) / scale
        wrong = (r["steady_state"] != ref["steady_state"]) | (r["regime"] != ref["regime"]).any(axis=1)
        err = np.where(wrong | ~np.isfinite(err), np.inf, err)
        worst = {g.name.lower(): float(err[regime == g].max()) if (regime == g).any() else np.nan for g in GROUPS}
        out.append((method, ", ".join(f"{k}={v}" for k, v in settings.items()) or "defaults", worst, us))
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="a 6 x 4 plane instead of 16 x 8")
    quick = ap.parse_args().quick
    heads = [g.name.lower() for g in GROUPS]
    print("| structure | method | setting | " + " | ".join(heads) + " | us a point |")
    print("|---|---|---|" + "---|" * len(heads) + "---|")
    for name, definition in STRUCTURES.items():
        for method, label, worst, us in measure(definition, quick):
            cells = " | ".join("-" if np.isnan(worst[h]) else f"{worst[h]:.0e}" for h in heads)
            print(f"| {name} | {method} | {label} | {cells} | {us:.0f} |")


if __name__ == "__main__":
    main()
