"""Sweeps at scale (make bench): the paper cube's wall time and memory, the speed-up over the paper's
method at equal or better accuracy, and how the cost grows. Writes results/bench/scale.md.

Every figure is measured here, side by side, in one run: python benchmarks/scale.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from friction_sweep.catalogue import GRID_OUTPUTS as OUTPUTS
from friction_sweep.methods import event, paper, theory

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "bench"


def run_cube(spec: Path, executor: str, jobs: int) -> tuple[float, float]:
    """Wall seconds and peak RSS (MiB) of one `fsweep run` in a fresh process."""
    out = OUT / f"{spec.stem}.{executor}.h5"
    cmd = [sys.executable, "-m", "friction_sweep", "run", str(spec), "-o", str(out), "--overwrite", "--quiet",
           "-j", str(jobs), "--executor", executor]
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, max(peak, before) / 1024


def per_point_event(excitation, r, beta, repeat=200):
    rr = np.full(repeat, r)
    event.solve_flat(excitation, rr[:1], beta)
    t = time.perf_counter()
    out = event.solve_flat(excitation, rr, np.full(repeat, beta))
    return (time.perf_counter() - t) / repeat, out[0]


def speedup_table(quick: bool) -> list[str]:
    points = [("base", 1.5, 0.3), ("base", 2.0, 0.5), ("base", 0.8, 0.3), ("joined", 2.0, 1.0), ("joined", 1.5, 0.5)]
    if quick:
        points = points[:2]
    rows = ["| point (scene, r, β) | paper s/point | event s/point | speed-up | paper error | event error |",
            "|---|---|---|---|---|---|"]
    ratios = []
    for exc, r, b in points:
        th = float(theory.compute_tile(exc, np.array([r]), np.array([b]), OUTPUTS)["transmissibility"][0, 0])
        t = time.perf_counter()
        p = paper.solve_point(exc, r, b)
        t_paper = time.perf_counter() - t
        t_event, raw = per_point_event(exc, r, b)
        e_paper = abs(p["transmissibility"] / th - 1)
        e_event = abs(raw[0] / th - 1)
        ratios.append(t_paper / t_event)
        rows.append(f"| {exc}, {r:g}, {b:g} | {t_paper:.3f} | {t_event * 1e6:.1f} µs | {t_paper / t_event:,.0f}× "
                    f"| {e_paper:.1e} | {e_event:.1e} |")
    rows.append(f"\nGeometric mean speed-up {np.exp(np.mean(np.log(ratios))):,.0f}×, smallest {min(ratios):,.0f}×.")
    return rows


def growth_tables(quick: bool) -> list[str]:
    rows = ["| points | seconds (event, 1 thread) | µs/point |", "|---|---|---|"]
    sizes = (1_000, 4_000, 16_000) if quick else (1_000, 4_000, 16_000, 64_000)
    for n in sizes:
        nr = int(np.sqrt(n * 496 / 151))
        nb = max(1, n // nr)
        r = np.linspace(0.05, 5.0, nr)
        b = np.linspace(0.0, 1.5, nb)
        event.compute_tile("base", r[:2], b[:2], OUTPUTS)
        t = time.perf_counter()
        event.compute_tile("base", r, b, OUTPUTS)
        dt = time.perf_counter() - t
        rows.append(f"| {nr * nb} | {dt:.2f} | {dt / (nr * nb) * 1e6:.0f} |")
    rows += ["", "| point (base) | periods marched | µs/point | with shooting off: periods | µs/point |",
             "|---|---|---|---|---|"]
    cases = [(2.0, b) for b in (0.3, 0.03, 0.003, 3e-4)] + [(1 + e, 0.3) for e in (1e-2, 1e-4, 1e-6)]
    for r, b in cases:
        t1, raw1 = per_point_event("base", r, b, repeat=20)
        rr = np.full(5, r)
        event.solve_flat("base", rr[:1], b, shoot_after=10**9, max_periods=200_000)
        t = time.perf_counter()
        raw2 = event.solve_flat("base", rr, np.full(5, b), shoot_after=10**9, max_periods=200_000)[0]
        t2 = (time.perf_counter() - t) / 5
        rows.append(f"| r = {r:.7g}, β = {b:g} | {raw1[7]:.0f} | {t1 * 1e6:.0f} | {raw2[7]:.0f} | {t2 * 1e6:,.0f} |")
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    lines = [f"# Sweeps at scale ({platform.processor() or platform.machine()}, {os.cpu_count()} cores)", "",
             f"Command: `python benchmarks/scale.py{' --quick' if args.quick else ''}` (`make bench`)", ""]
    if not args.quick:
        lines += ["## The paper cube: both scenes, r 0.05–5 step 0.01, β 0–1.5 step 0.01 (149,792 points), "
                  "method event, 2 workers", "", "| executor | base s | joined s | total s | peak RSS MiB |",
                  "|---|---|---|---|---|"]
        for executor in ("threads", "processes"):
            wb, mb = run_cube(ROOT / "configs/bench/paper_cube_base.yaml", executor, 2)
            wj, mj = run_cube(ROOT / "configs/bench/paper_cube_joined.yaml", executor, 2)
            lines.append(f"| {executor} | {wb:.1f} | {wj:.1f} | {wb + wj:.1f} | {max(mb, mj):.0f} |")
        lines.append("")
    lines += ["## Per point against the paper's method (200 periods, 64 samples a period, ode45 tolerances)",
              "", *speedup_table(args.quick), "", "Errors: relative error of the first-harmonic transmissibility "
              "against Den Hartog's closed form (continuous region).", "", "## How cost grows", "",
              *growth_tables(args.quick), ""]
    text = "\n".join(lines)
    (OUT / ("scale-quick.md" if args.quick else "scale.md")).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
