"""The speed target of issue 32: a performance curve of 100 friction levels, each level's resonance peak
refined to 1e-10 in r on the exact solver (friction_sweep.design.peak), in one process.

    python benchmarks/performance_curve.py [--excitation joined] [--grid 101] [--repeat 3]

Scene: undamped, rigid contact, method event; r from 0.5 to 3 (--grid points), beta from 0.8 to 2.0 for
joined (0.5 to 1.0 for base and force). Prints the CPU time (process time: user + sys of this process,
which a loaded machine inflates less than wall time) and the wall time of the best of --repeat curves,
after one curve has compiled (or loaded) the kernels, and how many points were solved.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.design import peak

#: points solved since the last reset
SOLVED = [0]


class Counted(peak.Problem):
    """The event problem, counting the points it solves."""

    def solve(self, r, beta):
        SOLVED[0] += np.size(r)
        return super().solve(r, beta)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--excitation", default="joined", choices=("force", "base", "joined"))
    ap.add_argument("--grid", type=int, default=101)
    ap.add_argument("--levels", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    r = np.linspace(0.5, 3.0, args.grid)
    beta = np.linspace(0.8, 2.0, args.levels) if args.excitation == "joined" else np.linspace(0.5, 1.0, args.levels)
    problem = Counted("event", args.excitation)
    peak.peaks(problem, r, beta[:2])  # compile or load the kernels
    best_cpu = best_wall = np.inf
    for _ in range(args.repeat):
        SOLVED[0] = 0
        cpu, wall = time.process_time(), time.perf_counter()
        curve = peak.peaks(problem, r, beta)
        best_cpu = min(best_cpu, time.process_time() - cpu)
        best_wall = min(best_wall, time.perf_counter() - wall)
    maxima = int(np.count_nonzero(np.isfinite(curve.value) & ~curve.at_edge))
    print(f"{args.excitation}: {args.levels} friction levels x {args.grid} frequency ratios, {maxima} maxima "
          f"refined to 1e-10 in r, {SOLVED[0]} points solved: CPU {best_cpu:.3f} s, wall {best_wall:.3f} s "
          f"(best of {args.repeat})")


if __name__ == "__main__":
    main()
