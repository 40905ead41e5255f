"""Sweeps at scale (make bench): the paper cube's wall time and memory, the speed-up over the paper's
method at equal or better accuracy, and how the cost grows. Writes results/bench/scale.md.

Every figure is measured here, side by side, in one run: python benchmarks/scale.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from friction_sweep.catalogue import MODEL_OUTPUTS as OUTPUTS
from friction_sweep.methods import event, paper, theory

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "bench"


def run_cube(spec: Path, executor: str, jobs: int, out: Path | None = None) -> tuple[float, float, float]:
    """Wall seconds, compute seconds as `fsweep run` prints them, and peak RSS (MiB) of one run in a
    fresh process."""
    out = out or OUT / f"{spec.stem}.{executor}.nc"
    cmd = [sys.executable, "-m", "friction_sweep", "run", str(spec), "-o", str(out), "--overwrite", "--quiet",
           "-j", str(jobs), "--executor", executor]
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t = time.perf_counter()
    done = subprocess.run(cmd, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    compute = float(re.search(r"points in ([0-9.]+) s", done.stdout).group(1))
    return wall, compute, max(peak, before) / 1024


def paper_planes(quick: bool) -> list[str]:
    """The paper's two planes: compute as printed, whole process, memory; periods integrated per point."""
    rows = ["| executor | base compute s | base whole s | joined compute s | joined whole s | both whole s | "
            "peak RSS MiB |", "|---|---|---|---|---|---|---|"]
    cubes = {}
    for executor in ("threads",) if quick else ("threads", "processes"):
        runs = {}
        for scene in ("base", "joined"):
            spec = ROOT / f"configs/bench/paper_cube_{scene}.yaml"
            cubes[scene] = OUT / f"{spec.stem}.{executor}.nc"
            runs[scene] = run_cube(spec, executor, 2, cubes[scene])
        (wb, cb, mb), (wj, cj, mj) = runs["base"], runs["joined"]
        rows.append(f"| {executor} | {cb:.2f} | {wb:.2f} | {cj:.2f} | {wj:.2f} | {wb + wj:.2f} | {max(mb, mj):.0f} |")
    rows += ["", "Forcing periods integrated per point (marched, shooting's evaluations, measured), mean by regime:",
             "", "| scene | stick-slip | continuous | stuck | all points |", "|---|---|---|---|---|"]
    from friction_sweep.codes import Regime
    from friction_sweep.storage.cube import open_cube

    for scene, path in cubes.items():
        ds = open_cube(path)
        reg, per = ds["regime"].values, ds["periods"].values
        mean = {k: per[reg == k].mean() for k in (Regime.STICK_SLIP, Regime.CONTINUOUS, Regime.STUCK)}
        rows.append(f"| {scene} | {mean[Regime.STICK_SLIP]:.2f} | {mean[Regime.CONTINUOUS]:.2f} | "
                    f"{mean[Regime.STUCK]:.2f} | {np.nanmean(per):.2f} |")
    return rows


FLOOR = "import xarray, numba, h5py, h5netcdf, pydantic, ruamel.yaml, click"
ONE_POINT = """\
scene: {excitation: base}
grid: {frequency_ratio: [1.5], force_ratio: [0.3]}
method: event
"""


TRIVIAL_KERNEL = """\
import numba


@numba.njit(cache=True)
def f(x):
    return x + 1.0
"""


def one_point(quick: bool) -> tuple[list[str], list[str]]:
    """A one-point `event` run, whole process, against the import floor of its own dependencies and
    against that floor plus one call of a trivial cached numba kernel (numba's own fixed cost: its
    typing registries load on the first call of any compiled function), alternating, median of each;
    and where the time above the floor goes (-X importtime)."""
    spec = OUT / "one_point.yaml"
    spec.write_text(ONE_POINT)
    (OUT / "trivial_kernel.py").write_text(TRIVIAL_KERNEL)
    out = OUT / "one_point.nc"
    run = [sys.executable, "-m", "friction_sweep", "run", str(spec), "-o", str(out), "--overwrite"]
    floor = [sys.executable, "-c", FLOOR]
    numba_floor = [sys.executable, "-c", f"{FLOOR}; import sys; sys.path.insert(0, {str(OUT)!r}); "
                   "import trivial_kernel; trivial_kernel.f(1.0)"]
    for cmd in (run, numba_floor):
        subprocess.run(cmd, check=True, capture_output=True)  # numba's caches are warm from here on
    times: dict[str, list[float]] = {"floor": [], "numba": [], "run": []}
    for _ in range(3 if quick else 7):
        for name, cmd in (("floor", floor), ("numba", numba_floor), ("run", run)):
            t = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True)
            times[name].append(time.perf_counter() - t)
    f, n, r = (np.median(times[k]) for k in ("floor", "numba", "run"))
    rows = ["| import floor s | floor + one trivial cached numba call s | one-point run s | run above the floor s |",
            "|---|---|---|---|", f"| {f:.2f} | {n:.2f} | {r:.2f} | {r - f:.2f} |", "",
            f"Floor: `python -c \"{FLOOR}\"`; run: `fsweep run` of a one-point `event` spec (r = 1.5, "
            "β = 0.3, progress and summary as by default), medians of alternating runs. The middle column is "
            "what calling any compiled kernel costs: numba loads its typing registries on the first call."]
    return rows, import_table(run, floor)


def _import_times(cmd) -> dict[str, int]:
    err = subprocess.run([cmd[0], "-X", "importtime", *cmd[1:]], check=True, capture_output=True, text=True).stderr
    own = {}
    for line in err.splitlines():
        m = re.match(r"import time:\s+(\d+) \|\s+\d+ \|\s*(\S+)", line)
        if m:
            own[m.group(2)] = int(m.group(1))
    return own


def import_table(run, floor) -> list[str]:
    """Self import time of the modules the run imports beyond the floor, by top-level package."""
    in_floor = _import_times(floor)
    beyond = {k: v for k, v in _import_times(run).items() if k not in in_floor}
    packages: dict[str, int] = {}
    for name, us in beyond.items():
        packages[name.split(".")[0]] = packages.get(name.split(".")[0], 0) + us
    rows = ["| package | ms |", "|---|---|"]
    rows += [f"| {k} | {v / 1e3:.0f} |" for k, v in sorted(packages.items(), key=lambda kv: -kv[1]) if v >= 2000]
    rows.append(f"| all beyond the floor | {sum(packages.values()) / 1e3:.0f} |")
    return rows


#: the first run on a machine: the kernels of each family, compiled from an empty numba cache
COLD_SPECS = {"steady": ROOT / "configs/demo.yaml",
              "jenkins_steady": ROOT / "configs/numerical/jenkins_base_kappa100.yaml"}


def _timed_run(spec: Path, cache: str) -> tuple[float, float, str]:
    """CPU seconds (user + sys) and wall seconds of `fsweep run spec` in a fresh process whose numba cache
    is `cache`, and what it wrote on stderr."""
    cmd = [sys.executable, "-m", "friction_sweep", "run", str(spec), "-o", str(OUT / f"{spec.stem}.cold.h5"),
           "--overwrite"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    done = subprocess.run(cmd, check=True, capture_output=True, text=True, env={**os.environ, "NUMBA_CACHE_DIR": cache})
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, wall, done.stderr


def cold_and_warm(quick: bool) -> list[str]:
    """The first run on a machine against the next: `fsweep run` of each family's spec in a fresh process
    with an empty NUMBA_CACHE_DIR (numba compiles every kernel the run calls, the run says so), then with the
    cache that run filled, side by side; CPU seconds (user + sys, which a loaded machine inflates less than
    wall time) and wall seconds. Their difference is what the estimate counts as the compile
    (batch/estimate.py: COMPILE_SECONDS)."""
    from friction_sweep.batch.estimate import COMPILE_SECONDS, COMPILING

    rows = ["| kernels (spec) | cold CPU s | warm CPU s | compile CPU s | cold wall s | warm wall s | "
            "estimate's compile s | says it compiles |", "|---|---|---|---|---|---|---|---|"]
    for family, spec in COLD_SPECS.items():
        if quick and family != "steady":
            continue
        with tempfile.TemporaryDirectory() as cache:
            cold_cpu, cold_wall, cold_err = _timed_run(spec, cache)
            warm_cpu, warm_wall, warm_err = _timed_run(spec, cache)
        says = "yes" if COMPILING in cold_err and COMPILING not in warm_err else "NO"
        rows.append(f"| {family} (`{spec.relative_to(ROOT)}`) | {cold_cpu:.1f} | {warm_cpu:.1f} | "
                    f"{cold_cpu - warm_cpu:.1f} | {cold_wall:.1f} | {warm_wall:.1f} | {COMPILE_SECONDS[family]:g} | "
                    f"{says} |")
    rows += ["", "Cold: a fresh process with an empty `NUMBA_CACHE_DIR`; warm: the same command again with the "
             "cache the cold run filled. A Dask worker on a fresh node pays the cold column's compile once (a "
             "LocalCluster's workers load the cache the run's own process filled first)."]
    return rows


GRID_SPEC = """\
scene: {excitation: base}
grid:
  frequency_ratio: {start: 0.1, stop: 4.0, num: 200}
  force_ratio: {start: 0.0, stop: 1.2, num: 50}
method: event
"""


def grid_against_paper(paper_times: list[float]) -> list[str]:
    """A 200 x 50 grid, whole process, against the paper's method over as many points, at its time per
    point in the per-point table below (continuous points: where the mass sticks the paper's method
    chatters and takes far longer): their mean, and their fastest."""
    spec = OUT / "grid_200x50.yaml"
    spec.write_text(GRID_SPEC)
    run_cube(spec, "threads", 1)  # warm the cache
    wall, _, _ = run_cube(spec, "threads", 1)
    n = 200 * 50
    rows = ["| grid | event, whole process s | paper's method s/point | paper's method, all points s | speed-up |",
            "|---|---|---|---|---|"]
    for label, t in (("mean", float(np.mean(paper_times))), ("fastest", min(paper_times))):
        rows.append(f"| 200 × 50 base, 1 worker | {wall:.2f} | {t:.3f} ({label} of the table below) | "
                    f"{t * n:,.0f} | {t * n / wall:,.0f}× |")
    return rows


def against_dop853(quick: bool) -> list[str]:
    """The same kernel in-process against the best a SciPy user would write: DOP853 with event
    switching (bench.reference, rtol 1e-9), marching from rest as long as the kernel's own march needs
    to settle; both errors against `event` at stop_tol 1e-13, steady_tol 1e-13."""
    from friction_sweep.bench.reference import measure
    from friction_sweep.kernels import steady

    pts = [("base", 0.5, 0.5), ("base", 1.5, 0.3), ("base", 0.3, 0.3), ("base", 2.5, 0.9),
           ("joined", 0.95, 0.8), ("joined", 1.5, 0.5), ("joined", 0.8, 0.55), ("joined", 3.0, 1.0)]
    if quick:
        pts = pts[:3]
    rows = ["| point (scene, r, β) | DOP853 s/point | event µs/point | speed-up | DOP853 error | event error |",
            "|---|---|---|---|---|---|"]
    ratios = []
    for exc, r, b in pts:
        tight = event.solve_flat(exc, np.array([r]), np.array([b]), stop_tol=1e-13, steady_tol=1e-13)[0]
        settle = event.solve_flat(exc, np.array([r]), np.array([b]), shoot_after=10**9)[0, steady.OUT_PERIODS]
        ref = tight[steady.OUT_TRANSMISSIBILITY]
        A, c = (r * r, 1.0) if exc == "joined" else (1.0, 0.0)
        t = time.perf_counter()
        t_dop, _ = measure(A, r, b, b, int(settle) + 3, c, rtol=1e-9, atol=1e-12)
        dop = time.perf_counter() - t
        t_event, raw = per_point_event(exc, r, b)
        ratios.append(dop / t_event)
        rows.append(f"| {exc}, {r:g}, {b:g} | {dop:.3f} | {t_event * 1e6:.1f} | {dop / t_event:,.0f}× | "
                    f"{abs(t_dop / ref - 1):.1e} | {abs(raw[steady.OUT_TRANSMISSIBILITY] / ref - 1):.1e} |")
    rows.append(f"\nGeometric mean speed-up {np.exp(np.mean(np.log(ratios))):,.0f}×, smallest {min(ratios):,.0f}×.")
    return rows


def per_point_event(excitation, r, beta, repeat=200):
    rr = np.full(repeat, r)
    event.solve_flat(excitation, rr[:1], beta)
    t = time.perf_counter()
    out = event.solve_flat(excitation, rr, np.full(repeat, beta))
    return (time.perf_counter() - t) / repeat, out[0]


def speedup_table(quick: bool) -> tuple[list[str], list[float]]:
    points = [("base", 1.5, 0.3), ("base", 2.0, 0.5), ("base", 0.8, 0.3), ("joined", 2.0, 1.0), ("joined", 1.5, 0.5)]
    if quick:
        points = points[:2]
    rows = ["| point (scene, r, β) | paper s/point | event s/point | speed-up | paper error | event error |",
            "|---|---|---|---|---|---|"]
    ratios, paper_times = [], []
    paper.solve_point(*points[0])  # warm: SciPy's imports and first calls are not the method's cost
    for exc, r, b in points:
        th = float(theory.compute_tile(exc, np.array([r]), np.array([b]), OUTPUTS)["transmissibility"][0, 0])
        t = time.perf_counter()
        p = paper.solve_point(exc, r, b)
        t_paper = time.perf_counter() - t
        t_event, raw = per_point_event(exc, r, b)
        e_paper = abs(p["transmissibility"] / th - 1)
        e_event = abs(raw[0] / th - 1)
        ratios.append(t_paper / t_event)
        paper_times.append(t_paper)
        rows.append(f"| {exc}, {r:g}, {b:g} | {t_paper:.3f} | {t_event * 1e6:.1f} µs | {t_paper / t_event:,.0f}× "
                    f"| {e_paper:.1e} | {e_event:.1e} |")
    rows.append(f"\nGeometric mean speed-up {np.exp(np.mean(np.log(ratios))):,.0f}×, smallest {min(ratios):,.0f}×.")
    return rows, paper_times


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
    rows += ["", "| point (base) | regime | periods | µs/point | with shooting off: periods | µs/point |",
             "|---|---|---|---|---|---|"]
    from friction_sweep.codes import Regime
    from friction_sweep.kernels import steady

    continuous = [(2.0, b) for b in (0.3, 0.03, 0.003, 3e-4)] + [(1 + e, 0.3) for e in (1e-2, 1e-4, 1e-6)]
    # stick-slip: two stops; next to the stick-slip limit (slow approach); many stops at low r
    stick_slip = [(1.5, 0.9), (0.5, 0.5), (0.45, 0.25), (0.3, 0.3), (0.1, 0.5)]
    for r, b in continuous + ([] if quick else stick_slip):
        t1, raw1 = per_point_event("base", r, b, repeat=20)
        rr = np.full(5, r)
        event.solve_flat("base", rr[:1], b, shoot_after=10**9, max_periods=200_000)
        t = time.perf_counter()
        raw2 = event.solve_flat("base", rr, np.full(5, b), shoot_after=10**9, max_periods=200_000)[0]
        t2 = (time.perf_counter() - t) / 5
        regime = Regime(int(raw1[steady.OUT_REGIME])).name.lower()
        rows.append(f"| r = {r:.7g}, β = {b:g} | {regime} | {raw1[steady.OUT_PERIODS]:.0f} | {t1 * 1e6:.0f} | "
                    f"{raw2[steady.OUT_PERIODS]:.0f} | {t2 * 1e6:,.0f} |")
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    lines = [f"# Sweeps at scale ({platform.processor() or platform.machine()}, {os.cpu_count()} cores)", "",
             f"Command: `python benchmarks/scale.py{' --quick' if args.quick else ''}` (`make bench`)", ""]
    one, imports = one_point(args.quick)
    per_point, paper_times = speedup_table(args.quick)
    lines += ["## The paper's planes: r 0.05–5 step 0.01, β 0–1.5 step 0.01 (74,896 points each), method event, "
              "2 workers", "", *paper_planes(args.quick), "",
              "## A one-point run against its import floor", "", *one, "",
              "## The first run on a machine: compiling the kernels (cold) against the cached ones (warm)", "",
              *cold_and_warm(args.quick), "",
              "## A 200 × 50 grid against the paper's method (ode45 tolerances, 200 periods, 64 samples a period)",
              "", *grid_against_paper(paper_times), "",
              "## Per point against the paper's method (200 periods, 64 samples a period, ode45 tolerances)",
              "", *per_point, "", "Errors: relative error of the first-harmonic transmissibility "
              "against Den Hartog's closed form (continuous region).", "",
              "## Per point against SciPy's DOP853 with event switching (rtol 1e-9)", "", *against_dop853(args.quick),
              "", "Errors: relative error of the first-harmonic transmissibility against `event` at stop_tol 1e-13, "
              "steady_tol 1e-13. DOP853 marches from rest as many periods as the kernel's own march (shooting off) "
              "integrates, plus 3.", "",
              "## How cost grows", "", *growth_tables(args.quick), ""]
    text = "\n".join(lines)
    suffix = "-quick" if args.quick else ""
    (OUT / f"scale{suffix}.md").write_text(text)
    (OUT / f"imports{suffix}.md").write_text("\n".join(
        ["# Where a one-point run's time above the import floor goes", "",
         "Self import time (`python -X importtime`) of the modules a one-point `event` run imports beyond "
         "the floor, by package:", "", *imports, ""]))
    print(text)


if __name__ == "__main__":
    main()
