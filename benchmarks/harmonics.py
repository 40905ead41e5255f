"""The speed target of issue 32 item 4: exact harmonics up to H = 50 at no more than 2x the cost of a plain point.

    python benchmarks/harmonics.py [--excitation base] [--highest 50] [--repeat 3]

Scene: undamped, rigid contact, method event, a plane of r from 0.2 to 3 (60 values) by beta from 0.05 to
0.95 (20 values) for base and force (beta times r^2 ... for joined: 0.1 to 1.9): the plain outputs
(transmissibility, phase, regime), then the same with `harmonics` at H = --highest. Prints the CPU time
(process time: user + sys of this process) of the best of --repeat planes of each, after one plane of each
has compiled (or loaded) the kernels, and their ratio.
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--excitation", default="base", choices=("force", "base", "joined"))
    ap.add_argument("--highest", type=int, default=50)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    r = np.linspace(0.2, 3.0, 60)
    beta = np.linspace(0.1, 1.9, 20) if args.excitation == "joined" else np.linspace(0.05, 0.95, 20)
    plain = best_cpu(args.excitation, r, beta, PLAIN, {}, args.repeat)
    harm = best_cpu(args.excitation, r, beta, (*PLAIN, "harmonics"), {"harmonics": args.highest}, args.repeat)
    n = r.size * beta.size
    print(f"{args.excitation}: {n} points, plain {plain / n * 1e6:.1f} us/point, with harmonics up to "
          f"H = {args.highest} {harm / n * 1e6:.1f} us/point: ratio {harm / plain:.2f} (CPU, best of {args.repeat})")


if __name__ == "__main__":
    main()
