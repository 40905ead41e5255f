"""The speed target of issue 32 item 4: exact harmonics up to H = 50 at no more than 2x the cost of a plain point.

    python benchmarks/harmonics.py [--excitation base | --structure] [--highest 50] [--repeat 3]

Scene: undamped, rigid contact, method event, a plane of r from 0.2 to 3 (60 values) by beta from 0.05 to
0.95 (20 values) for base and force (beta times r^2 ... for joined: 0.1 to 1.9): the plain outputs
(transmissibility, phase, regime), then the same with `harmonics` at H = --highest. Prints the CPU time
(process time: user + sys of this process) of the best of --repeat planes of each, after one plane of each
has compiled (or loaded) the kernels, and their ratio.

--structure: the 2-mass blade and platform damper of benchmarks/structures.py on its 200 x 20 plane (frequency
0.2-3, friction_scale 0.05-20), a plain solve (amplitude, phase, regime), then the same points with their
harmonics (structures.harmonics, one replay of each orbit).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from friction_sweep.methods import event

PLAIN = ("transmissibility", "phase", "regime")


def best_cpu(excitation: str, r, beta, outputs, settings, repeat: int) -> float:
    event.compute_tile(excitation, r[:2], beta[:2], outputs, settings=settings)  # compile or load the kernels
    best = np.inf
    for _ in range(repeat):
        cpu = time.process_time()
        event.compute_tile(excitation, r, beta, outputs, settings=settings)
        best = min(best, time.process_time() - cpu)
    return best


def best_cpu_structure(highest: int, repeat: int) -> tuple[float, float, int]:
    """The blade plane's best CPU time plain, and with its harmonics up to `highest`, and its points."""
    from structures import BLADE

    from friction_sweep.structures import assemble, solve_points
    from friction_sweep.structures.harmonics import orbit_harmonics

    w, s = (g.ravel() for g in np.meshgrid(np.linspace(0.2, 3.0, 200), np.geomspace(0.05, 20.0, 20), indexing="ij"))
    a = assemble(BLADE)
    orbit_harmonics(a, w[:1], s[:1], highest)  # compile or load the kernels
    plain = harm = np.inf
    for _ in range(repeat):
        cpu = time.process_time()
        solve_points(a, w, s)
        plain = min(plain, time.process_time() - cpu)
        cpu = time.process_time()
        orbit_harmonics(a, w, s, highest, solved=solve_points(a, w, s))
        harm = min(harm, time.process_time() - cpu)
    return plain, harm, w.size


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--excitation", default="base", choices=("force", "base", "joined"))
    ap.add_argument("--highest", type=int, default=50)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--structure", action="store_true", help="the blade and damper plane of benchmarks/structures.py")
    args = ap.parse_args()
    if args.structure:
        plain, harm, n = best_cpu_structure(args.highest, args.repeat)
        print(f"structure (blade and damper): {n} points, plain {plain / n * 1e6:.1f} us/point, with harmonics up to "
              f"H = {args.highest} {harm / n * 1e6:.1f} us/point: ratio {harm / plain:.2f} (CPU, best of "
              f"{args.repeat})")
        return
    r = np.linspace(0.2, 3.0, 60)
    beta = np.linspace(0.1, 1.9, 20) if args.excitation == "joined" else np.linspace(0.05, 0.95, 20)
    plain = best_cpu(args.excitation, r, beta, PLAIN, {}, args.repeat)
    harm = best_cpu(args.excitation, r, beta, (*PLAIN, "harmonics"), {"harmonics": args.highest}, args.repeat)
    n = r.size * beta.size
    print(f"{args.excitation}: {n} points, plain {plain / n * 1e6:.1f} us/point, with harmonics up to "
          f"H = {args.highest} {harm / n * 1e6:.1f} us/point: ratio {harm / plain:.2f} (CPU, best of {args.repeat})")


if __name__ == "__main__":
    main()
