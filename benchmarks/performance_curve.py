"""The speed target of issue 32: a performance curve of 100 friction levels, each level's resonance peak
refined to 1e-10 in r on the exact solver (friction_sweep.design.peak), in one process.

    python benchmarks/performance_curve.py [--excitation joined] [--grid 101] [--repeat 3]
    python benchmarks/performance_curve.py --structure [--grid 41] [--levels 20] [--repeat 1]

Scene: undamped, rigid contact, method event; r from 0.5 to 3 (--grid points), beta from 0.8 to 2.0 for
joined (0.5 to 1.0 for base and force). With --structure: the 2-mass blade and damper of
benchmarks/structures.py (BLADE, one rigid contact, zeta 0.002), the blade's peak over the angular frequency
0.5 to 2 (the free and the stuck first modes, 0.95 and 1.73, lie in it) at friction_scale 0.5 to 10. Prints
the CPU time (process time: user + sys of this process, which a loaded machine inflates less than wall time)
and the wall time of the best of --repeat curves, after one curve has compiled (or loaded) the kernels, and
how many points were solved.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.design import peak
from friction_sweep.design.structure import StructureProblem

#: points solved since the last reset
SOLVED = [0]


class Counted(peak.Problem):
    """The event problem, counting the points it solves."""

    def solve(self, r, beta):
        SOLVED[0] += np.size(r)
        return super().solve(r, beta)


class CountedStructure(StructureProblem):
    """The structure's problem, counting the points it solves."""

    def solve(self, w, s):
        SOLVED[0] += np.size(w)
        return super().solve(w, s)


def problem_and_axes(args):
    """The problem, its frequency grid and its friction levels."""
    if args.structure:
        from structures import BLADE

        from friction_sweep.structures import assemble

        return (CountedStructure(assemble(BLADE), "blade"), np.linspace(0.5, 2.0, args.grid),
                np.geomspace(0.5, 10.0, args.levels))
    r = np.linspace(0.5, 3.0, args.grid)
    beta = np.linspace(0.8, 2.0, args.levels) if args.excitation == "joined" else np.linspace(0.5, 1.0, args.levels)
    return Counted("event", args.excitation), r, beta


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--excitation", default="joined", choices=("force", "base", "joined"))
    ap.add_argument("--structure", action="store_true", help="the 2-mass blade and damper instead of one mass")
    ap.add_argument("--grid", type=int, default=None, help="frequency points (default 101, 41 with --structure)")
    ap.add_argument("--levels", type=int, default=None, help="friction levels (default 100, 20 with --structure)")
    ap.add_argument("--repeat", type=int, default=None, help="curves timed (default 3, 1 with --structure)")
    args = ap.parse_args()
    for name, one, several in (("grid", 101, 41), ("levels", 100, 20), ("repeat", 3, 1)):
        if getattr(args, name) is None:
            setattr(args, name, several if args.structure else one)
    problem, r, beta = problem_and_axes(args)
    peak.peaks(problem, r[:3], beta[:1])  # compile or load the kernels
    best_cpu = best_wall = np.inf
    for _ in range(args.repeat):
        SOLVED[0] = 0
        cpu, wall = time.process_time(), time.perf_counter()
        curve = peak.peaks(problem, r, beta)
        best_cpu = min(best_cpu, time.process_time() - cpu)
        best_wall = min(best_wall, time.perf_counter() - wall)
    maxima = int(np.count_nonzero(np.isfinite(curve.value) & ~curve.at_edge))
    what = "2-mass blade and damper" if args.structure else args.excitation
    print(f"{what}: {args.levels} friction levels x {args.grid} frequencies, {maxima} maxima refined to 1e-10 "
          f"in frequency, {SOLVED[0]} points solved: CPU {best_cpu:.3f} s ({best_cpu / args.levels * 1e3:.0f} ms "
          f"a level), wall {best_wall:.3f} s (best of {args.repeat})")


if __name__ == "__main__":
    main()
