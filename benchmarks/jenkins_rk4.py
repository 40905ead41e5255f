"""Method rk4 with the Jenkins contact against the exact method event, side by side in one run: microseconds
per point, the largest relative transmissibility error against event, unsettled points and labels that
differ. Base, kappa = 100, r 0.1-3 step 0.1, beta 0.05-0.95 step 0.1 (300 points), one process, one core.

    python benchmarks/jenkins_rk4.py [--kappa 100] [--steps 128 512] [--repeat 3]

Each timing is the best of --repeat solves of the whole grid, after one point of each has compiled (or
loaded) the kernels. steps_per_period below the catalogue's 256 is allowed here (event.solve_flat takes
it unchecked) to show the trend.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.codes import Regime
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import event


def solve(r, beta, effects, steps):
    if steps is None:
        return event.solve_flat("base", r, beta, effects)
    return event.solve_flat("base", r, beta, effects, kernel=KERNEL_RK4, steps_per_period=steps)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kappa", type=float, default=100.0)
    ap.add_argument("--steps", type=int, nargs="+", default=[128, 512])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    r_axis = np.round(np.arange(1, 31) * 0.1, 10)
    beta_axis = np.round(0.05 + 0.1 * np.arange(10), 10)
    R, B = np.meshgrid(r_axis, beta_axis)
    r, beta = R.ravel(), B.ravel()
    effects = {"contact_stiffness": args.kappa}
    runs: list[int | None] = [None, *args.steps]
    for steps in runs:  # compile or load the kernels outside the timings
        solve(r[:1], beta[:1], effects, steps)
    rows, times = {}, {}
    for steps in runs:
        best = np.inf
        for _ in range(args.repeat):
            t = time.perf_counter()
            rows[steps] = solve(r, beta, effects, steps)
            best = min(best, time.perf_counter() - t)
        times[steps] = best
    ref = rows[None]
    print(f"base, kappa = {args.kappa:g}, {r.size} points (r 0.1-3 step 0.1, beta 0.05-0.95 step 0.1)")
    print(f"{'method':>12} {'us/point':>10} {'unsettled':>9} {'unbounded':>9} {'max rel err T':>14} "
          f"{'at (r, beta)':>14} {'labels differ':>13}")
    for steps in runs:
        row = rows[steps]
        regime = row[:, steady.OUT_REGIME]
        name = "event" if steps is None else f"rk4 {steps}"
        head = (f"{name:>12} {1e6 * times[steps] / r.size:10.1f} {int(np.sum(regime == Regime.UNSETTLED)):9d} "
                f"{int(np.sum(regime == Regime.UNBOUNDED)):9d}")
        if steps is None:
            print(head)
            continue
        # transmissibility where both have a bounded steady orbit; labels where both settled
        both = np.isfinite(row[:, steady.OUT_TRANSMISSIBILITY]) & np.isfinite(ref[:, steady.OUT_TRANSMISSIBILITY])
        err = np.abs(row[both, steady.OUT_TRANSMISSIBILITY] / ref[both, steady.OUT_TRANSMISSIBILITY] - 1.0)
        worst = int(np.flatnonzero(both)[np.argmax(err)])
        settled = (regime != Regime.UNSETTLED) & (ref[:, steady.OUT_REGIME] != Regime.UNSETTLED)
        same = ((regime == ref[:, steady.OUT_REGIME])
                & np.isclose(row[:, js.JOUT_SLIPS], ref[:, js.JOUT_SLIPS], rtol=0, atol=0, equal_nan=True)
                & np.isclose(row[:, steady.OUT_STOPS_PER_PERIOD], ref[:, steady.OUT_STOPS_PER_PERIOD], rtol=0,
                             atol=0, equal_nan=True))
        differ = settled & ~same
        print(f"{head} {err.max():14.2e} {f'({r[worst]:.1f}, {beta[worst]:.2f})':>14} {int(differ.sum()):13d}")
        for i in np.flatnonzero(differ):
            print(f"{'':>12} differs at r = {r[i]:.1f}, beta = {beta[i]:.2f}: "
                  f"regime {Regime(int(regime[i])).name} / {Regime(int(ref[i, steady.OUT_REGIME])).name}, "
                  f"slips {row[i, js.JOUT_SLIPS]:g} / {ref[i, js.JOUT_SLIPS]:g}, "
                  f"stops {row[i, steady.OUT_STOPS_PER_PERIOD]:g} / {ref[i, steady.OUT_STOPS_PER_PERIOD]:g}")
        for i in np.flatnonzero(regime == Regime.UNSETTLED):
            print(f"{'':>12} unsettled at r = {r[i]:.1f}, beta = {beta[i]:.2f} (event: "
                  f"{Regime(int(ref[i, steady.OUT_REGIME])).name})")
    for i in np.flatnonzero(ref[:, steady.OUT_REGIME] == Regime.UNSETTLED):
        print(f"event unsettled at r = {r[i]:.1f}, beta = {beta[i]:.2f}")

if __name__ == "__main__":
    main()
