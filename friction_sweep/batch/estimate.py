"""What a run will cost before it starts: wall time and memory, from a measured cost model.

Seconds on one core, summed over the run's tiles (fixed blocks of frequency ratios, batch.layout):

    every method    0.3 ms x max(1, 0.07/r) per frequency ratio (the theory's continuity limit S(r),
                    which the simulations write beside their results)
    theory, auto    per tile: 0.6 ms + 6e-11 n^3 (Gauss-Legendre nodes, n = 40 + pi (1 + r_min)/r_min);
                    per point: 2 us + 0.03 us n, and for joined 1 us per peak sample
                    (64 + 16 (1 + r)/r of them)
    event, auto     per point: base/force 8 us x max(1, (0.66/r)^1.5), joined 6 us x max(1, (0.035/r)^0.6);
                    x3 with static above kinetic friction and two starts (three solves)
    rk4             per point: 1.2 us x steps_per_period
    paper           per point: 5.7 us per right-hand side, up to max_evaluations, + 0.2 us a sample
    structure       per point: 2.5 ms x max(1, (n/2)^3) x m for n masses and m contacts (the engine on
                    the issue's 2-mass, 2-contact spec: 12.2 CPU s for its 2,244 points, loaded 2 cores)

Measured on 2 cores, each column's mean over 151 force ratios (the event rows again after issue 16's
shooting, which made them 10-30x cheaper), and checked on the paper plane (74,896 points, serial).
Single points vary more than column means (at r < 0.1 a small force ratio can cost 3-5x its
column's mean), so a grid of only such points can take longer than `seconds`. `worst` bounds a grid
whose every point runs into its budget: work_budget events at 0.3 us, or max_periods periods at
21 us + 13 ns x max_orbit_period, whichever comes first.

Effects and settings: with static above kinetic friction each point is solved three times (two
starts); viscous damping costs nothing more (measured: 18-24 us a point at zeta 1e-6 to 0.8 against 30
undamped, 150 points r 0.2-3, beta 0.05-0.9); with a Jenkins contact (contact_stiffness kappa) a mass
that sticks swings on the contact spring sqrt(1 + kappa) times per natural period: a point costs about
300 sqrt(1 + kappa) events of 0.1 us more, never more than its work_budget (a plane's mean, README's
cost table: 309 us a point at kappa 1e2, 1,798 at 1e4; one stick-slip point, r = beta = 0.3: 5.7e3
events at kappa 1e2, 7.4e4 at 1e4, 1.5e6 at 1e6, the budget at 1e8; 8 x 8 points at kappa 1e8: 6.6 s),
and about 2 in 1,000 points never settle and use all of it; rk4 sub-steps its sticks ceil(sqrt(1 +
kappa)) times (README: 201 -> 1,026 us a point at kappa 100).

Executors: workers never outnumber tiles, nor (on this machine) cores (executors.workers); a worker
process (processes, a Dask LocalCluster) holds its own Python, numba and kernels, and a Dask worker
starts as a fresh Python that imports them.

Compile: where numba's cache holds no valid entry for a kernel the run calls (batch/kernel_cache.py: its
index file beside the source, or under NUMBA_CACHE_DIR, for this source and numba, with a signature for
the run's integrator), the first call compiles it; that time (COMPILE_SECONDS, CPU seconds that make bench
measures on the 2-core reference machine) is added, and fsweep run shows it as a step of its own.
Numba-free: `fsweep validate` prints the estimate without loading any kernel or numba.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from friction_sweep.batch.executors import capped, cores, local_workers
from friction_sweep.batch.layout import layout
from friction_sweep.catalogue import METHODS, effect_value

#: a grid is "huge" (run only with --yes) past either: the refusal says how much
HUGE_SECONDS = 1800.0
HUGE_BYTES = 4 * 2**30
#: a run's process before its grid: Python with numba, xarray and h5py loaded (peak RSS of a 1-point run)
BASE_BYTES = 300 * 2**20
#: memory per grid point while a run holds its outputs and the cube's serialised copy
POINT_BYTES = 1000
#: the output harmonics: a point's cost with them over without (benchmarks/harmonics.py measured 1.75-1.85 at
#: H = 50), and the float64 values each harmonic of a point stores (the response's and friction's, complex)
HARMONICS_COST = 2.0
HARMONIC_VALUES = 4
#: loading the compiled kernels from numba's cache, once per run (the simulation methods; make bench:
#: numba's first call of any cached kernel alone costs ~0.4 s)
KERNEL_LOAD_SECONDS = 0.4
#: a point that sticks on a Jenkins contact: events per sqrt(1 + kappa), and seconds an event
JENKINS_EVENTS = 300.0
EVENT_SECONDS = 0.1e-6
#: points on a Jenkins contact that never settle and so use their whole work budget (README: 1-2 of
#: 1,121 at kappa 1e2-1e4)
JENKINS_UNSETTLED = 2e-3
#: rk4 with the contact: the sticks' sub-steps per sqrt(1 + kappa), relative to a rigid point's steps
RK4_JENKINS_STEPS = 0.4
#: a worker process's own memory (Python, numba, the kernels): -j 32 processes peaked at 4.1 GB
WORKER_BYTES = 120 * 2**20
#: starting one worker: a forked process inherits the loaded kernels; a Dask worker is a fresh Python
#: that imports numba and loads them (-j 24 on 2 cores: 34.8 s for one point)
WORKER_START_SECONDS = {"processes": 0.2, "dask": 2.5}
#: seconds to compile a family of kernels that numba's cache does not hold (first run of a version):
#: CPU seconds of the first call with an empty NUMBA_CACHE_DIR on the 2-core reference machine (make bench's
#: "The first run on a machine" measures them; steady: configs/demo.yaml quiet (load 0.2), cold 13.3 s CPU
#: against warm 2.0 s; jenkins_steady from runs under load scaled by main's quiet 25 s, 59 s; the structure
#: engine, method rk4's stepper with it: the blade's first point (benchmarks/structures.py's BLADE), quiet (load
#: 1.0: the run alone), 87.7, 94.8 s CPU, and 87.9, 91.5 s before its start rule and tie (its Newton step's
#: least squares and the repelling check had brought it up from 68 s); the median, rounded)
COMPILE_SECONDS = {"steady": 11.0, "jenkins_steady": 37.0, "structure.steady": 90.0, "structure.harmonics": 19.0,
                   "structure.history": 7.0}
#: the structure's harmonics replay and its time-history sampler (outputs harmonics, time_history), each compiled
#: where a run asks for it: the blade's first point after the engine's compile, 18.6 and 7.0 s CPU
STRUCTURE_HARMONICS_KERNEL = ("structure.harmonics", "harmonics_batch")
STRUCTURE_HISTORY_KERNEL = ("structure.history", "sample_orbit")
#: what a run says while it compiles them (fsweep run)
COMPILING = "compiling the simulation kernels (first run on this machine; cached afterwards)"
#: the structure engine's compiled entry point (kernel module, function): every structure calls it
STRUCTURE_KERNEL = ("structure.steady", "solve_batch")
#: a point of a structure of 2 masses, per contact (structure_point_seconds scales it; measured above)
STRUCTURE_POINT_SECONDS = 2.5e-3
#: method rk4's point over event's, a + b x steps_per_period / 256 (benchmarks/structure_rk4.py, the blade's
#: plane: 4.1, 7.4 and 14.2 at 256, 512 and 1024 steps)
STRUCTURE_RK4_COST = (0.7, 3.35)


def _frequency_seconds(r: np.ndarray) -> np.ndarray:
    return 3e-4 * np.maximum(1.0, 0.07 / r)


def _theory_seconds(r: np.ndarray, n_beta: int, joined: bool) -> float:
    n = 40 + math.ceil((1.0 + r.min()) * math.pi / r.min())
    per_point = 2e-6 + 3e-8 * n + (1e-6 * (64 + 16 * (1.0 + r) / r) if joined else 0.0)
    return 6e-4 + 6e-11 * n**3 + float(np.sum(np.broadcast_to(per_point, r.shape))) * n_beta


def _event_point_seconds(r: np.ndarray, joined: bool) -> np.ndarray:
    if joined:
        return 6e-6 * np.maximum(1.0, (0.035 / r) ** 0.6)
    return 8e-6 * np.maximum(1.0, (0.66 / r) ** 1.5)


def _tile_seconds(method: str, r: np.ndarray, n_beta: int, joined: bool, solves: int, knobs: dict,
                  kappa: float = 0.0) -> float:
    """Typical seconds for one tile of frequency ratios `r` by all `n_beta` force ratios (`kappa`: the
    Jenkins contact's stiffness, 0 for the rigid contact)."""
    seconds = float(_frequency_seconds(r).sum())
    if method in ("theory", "auto"):
        seconds += _theory_seconds(r, n_beta, joined)
    if method in ("event", "auto"):
        seconds += float(_event_point_seconds(r, joined).sum()) * n_beta * solves
        if kappa > 0.0:
            seconds += _jenkins_point_seconds(kappa, knobs) * r.size * n_beta * solves
    if method == "rk4":
        steps = 1.0 + (RK4_JENKINS_STEPS * math.sqrt(1.0 + kappa) if kappa > 0.0 else 0.0)
        per_point = min(1.2e-6 * knobs["steps_per_period"] * steps, _worst_point_seconds(method, knobs, 1))
        seconds += per_point * r.size * n_beta * solves
    if method == "paper":  # a smooth point; stick-slip runs into max_evaluations (`worst`)
        seconds += (5.7e-6 * 2e4 + 0.2e-6 * knobs["periods"] * knobs["samples_per_period"]) * r.size * n_beta
    return seconds


def _jenkins_point_seconds(kappa: float, knobs: dict) -> float:
    """What a point that sticks adds on a Jenkins contact of stiffness `kappa`: its swings on the
    contact spring, up to the point's work budget."""
    return min(JENKINS_EVENTS * math.sqrt(1.0 + kappa), float(knobs["work_budget"])) * EVENT_SECONDS


def _worst_point_seconds(method: str, knobs: dict, solves: int, kappa: float = 0.0) -> float:
    """A point that runs into its budget."""
    if method == "theory":
        return 0.0
    if kappa > 0.0:  # a period's swings on the contact spring: the work budget is the bound
        return solves * 0.3e-6 * knobs["work_budget"]
    if method == "paper":
        return 5.7e-6 * knobs["max_evaluations"] + 0.2e-6 * knobs["periods"] * knobs["samples_per_period"]
    per_period = 21e-6 + 13e-9 * knobs["max_orbit_period"]
    if method == "rk4":
        per_period += 1.2e-6 * knobs["steps_per_period"]
    return solves * min(0.3e-6 * knobs["work_budget"], knobs["max_periods"] * per_period)


@dataclass(frozen=True)
class Estimate:
    points: int
    seconds: float  # wall time, typical
    worst: float  # wall time if every point ran its whole budget
    bytes: int
    workers: int
    compile: float = 0.0  # of `seconds`: compiling kernels that numba's cache does not hold
    jobs: int = 1  # the workers asked for (-j)
    why_fewer: str = ""  # why `workers` is below `jobs`

    def describe(self) -> str:
        text = f"about {duration(self.seconds)} with {self.workers} worker(s)"
        if self.workers < self.jobs:
            text += f" (not {self.jobs}: {self.why_fewer})"
        if self.compile > 0:
            text += f", {duration(self.compile)} of it compiling the simulation kernels (first run)"
        if self.worst > 2 * self.seconds:
            text += f" (at most {duration(self.worst)} if every point used its whole budget)"
        return text + f" and {self.bytes / 2**30:.2g} GiB of memory"


def estimate(spec, settings: dict | None = None, *, jobs: int, executor: str, scheduler: str | None = None,
             cache: bool = True) -> Estimate:
    """The cost of running `spec` with `jobs` workers on `executor` (dask: on a LocalCluster, or on
    `scheduler`), with the run's `settings` (those `accuracy:` chose included; default: the spec's).
    cache: look at numba's cache for the kernels the run calls (False: count them as compiled)."""
    from friction_sweep.spec.structure import StructureSpec

    if isinstance(spec, StructureSpec):
        return _structure_estimate(spec, settings, jobs=jobs, executor=executor, scheduler=scheduler, cache=cache)
    r, n_beta = spec.frequency_ratio, spec.force_count
    knobs = {**METHODS[spec.method].defaults, **(spec.settings if settings is None else settings)}
    joined = spec.scene.excitation == "joined"
    kappa = effect_value(spec.scene.effects, "contact_stiffness") if spec.method != "theory" else 0.0
    solves = 3 if _two_starts(spec, knobs) else 1
    sweep = spec.sweep.direction if spec.sweep is not None else None
    parts = layout(r.size, n_beta, sweep)
    if sweep:  # tiles of force ratios, each over every frequency ratio
        serial = sum(_tile_seconds(spec.method, r, p.stop - p.start, joined, solves, knobs, kappa) for p in parts)
    else:
        serial = sum(_tile_seconds(spec.method, r[p], n_beta, joined, solves, knobs, kappa) for p in parts)
    points = r.size * n_beta
    harmonic_bytes = 0
    if "harmonics" in spec.outputs:  # a replay of each orbit (benchmarks/harmonics.py: below 2x a plain point)
        serial *= HARMONICS_COST
        harmonic_bytes = points * HARMONIC_VALUES * (int(knobs["harmonics"]) + 1) * 8 * 2  # run and cube copy
    if spec.method != "theory":
        serial += KERNEL_LOAD_SECONDS
    worst_point = _worst_point_seconds(spec.method, knobs, solves, kappa)
    history = 0
    if spec.time_history is not None:
        n = len(spec.time_history.points)
        history = n * spec.time_history.samples_per_period * 8 * 8  # eight float64 variables
        serial += n * worst_point
    if kappa > 0.0:  # the few points that never settle on the contact run their whole budget
        serial += JENKINS_UNSETTLED * points * worst_point
    worst = serial + points * worst_point
    n_workers = local_workers(executor, jobs, len(parts), scheduler)
    # worker processes of this machine (executors.execute): each its own memory, and start-ups that
    # the cores share
    own = (executor == "processes" and n_workers > 1) or (executor == "dask" and scheduler is None)
    processes = n_workers if own else 0
    start = processes * WORKER_START_SECONDS.get(executor, 0.0) / min(max(processes, 1), cores())
    compiling = _compile_seconds(spec, solves > 1, kappa) if cache else 0.0
    return Estimate(points=points, seconds=serial / n_workers + start + compiling,
                    worst=worst / n_workers + start + compiling,
                    bytes=BASE_BYTES + processes * WORKER_BYTES + points * POINT_BYTES * solves + history
                    + harmonic_bytes,
                    workers=n_workers, compile=compiling, jobs=jobs,
                    why_fewer=capped(executor, jobs, n_workers, len(parts), scheduler))


def structure_point_seconds(n: int, m: int) -> float:
    """Typical seconds of one point of a structure of n masses and m contacts (the engine's flow works on
    states of 2n + 3: its matrix products grow like n^3, its events like m)."""
    return STRUCTURE_POINT_SECONDS * max(1.0, (n / 2.0) ** 3) * max(1.0, m / 1.0)


def _structure_estimate(spec, settings: dict | None, *, jobs: int, executor: str, scheduler: str | None,
                        cache: bool) -> Estimate:
    """The cost of a structure spec (spec.structure): its points at structure_point_seconds, a worst case of
    work_budget events a point, tiles of frequencies by every friction scale, and the engine's compile where
    numba's cache does not hold it (one compilation serves every structure)."""
    from friction_sweep.batch import kernel_cache

    n, m = len(spec.structure.dofs), len(spec.structure.contacts)
    knobs = {**METHODS[spec.method].defaults, **(spec.settings if settings is None else settings)}
    n_f, n_s = spec.frequency.size, spec.friction_scale.size
    points = n_f * n_s
    n_tiles = len(layout(n_f, n_s, spec.sweep.direction if spec.sweep is not None else None))
    per_point = structure_point_seconds(n, m)
    if spec.method == "rk4":
        a, b = STRUCTURE_RK4_COST
        per_point *= a + b * knobs["steps_per_period"] / 256.0
    # two starts (spec.two_starts): the kinetic seed and the solve from its state beside the solve from rest
    solves = 3 if spec.two_starts else 1
    harmonics = "harmonics" in spec.outputs
    if harmonics:  # one replay of each orbit (benchmarks/harmonics.py --structure: 1.52 at H = 50)
        per_point *= HARMONICS_COST
    serial = KERNEL_LOAD_SECONDS + solves * points * per_point
    history_bytes = 0
    if spec.time_history is not None:  # each point solved again from rest, then its orbit sampled
        n_history = len(spec.time_history.points)
        serial += n_history * structure_point_seconds(n, m)
        # the samples (time, each mass, each contact's force and relative displacement), run and cube copy
        history_bytes = n_history * spec.time_history.samples_per_period * (1 + n + 2 * m) * 8 * 2
    worst = serial + solves * points * 0.3e-6 * knobs["work_budget"] * max(1.0, (n / 2.0) ** 2)
    n_workers = local_workers(executor, jobs, n_tiles, scheduler)
    own = (executor == "processes" and n_workers > 1) or (executor == "dask" and scheduler is None)
    processes = n_workers if own else 0
    start = processes * WORKER_START_SECONDS.get(executor, 0.0) / min(max(processes, 1), cores())
    compiling = 0.0
    kernels = (STRUCTURE_KERNEL, *((STRUCTURE_HARMONICS_KERNEL,) if harmonics else ()),
               *((STRUCTURE_HISTORY_KERNEL,) if spec.time_history is not None else ()))
    for module, entry in kernels:
        compiling += COMPILE_SECONDS[module] if cache and not kernel_cache.warm(module, entry) else 0.0
    # the harmonics' values: H + 1 complex numbers per mass and contact, in the run and the cube's copy
    harmonic_bytes = points * (int(knobs["harmonics"]) + 1) * (n + m) * 16 * 2 * solves if harmonics else 0
    return Estimate(points=points, seconds=serial / n_workers + start + compiling,
                    worst=worst / n_workers + start + compiling,
                    bytes=(BASE_BYTES + processes * WORKER_BYTES + points * POINT_BYTES * (n + m) + harmonic_bytes
                           + history_bytes),
                    workers=n_workers, compile=compiling, jobs=jobs,
                    why_fewer=capped(executor, jobs, n_workers, n_tiles, scheduler))


def _two_starts(spec, knobs: dict) -> bool:
    """Whether each point is solved from a moving start too (methods.event.two_starts)."""
    return (effect_value(spec.scene.effects, "static_friction_ratio") > 1.0 and spec.sweep is None
            and knobs.get("starts", 1) == 2)


def kernels_called(spec, two_starts: bool, kappa: float) -> list[tuple[str, str, tuple[str, ...]]]:
    """The compiled entry points (kernel module, function, the names of its last argument types) that a run
    of `spec` calls: numba compiles each with everything it calls, so these are what its cache must hold.
    The rigid drivers are compiled per integrator, their last argument (kernels.period_map.integrator:
    None, numba's "none", for the event kernel, True, "bool", for RK4)."""
    if spec.method in ("theory", "paper"):
        return []
    module, suffix = ("jenkins_steady", "_jenkins") if kappa > 0.0 else ("steady", "")
    names = [f"solve_sweep{suffix}"] if spec.sweep is not None else [f"solve_points{suffix}"]
    if two_starts:
        names.append(f"solve_points{suffix}_from")
    last: tuple[str, ...] = ("bool",) if spec.method == "rk4" else ("none",)
    if module != "steady":
        last = ()
    called: list[tuple[str, str, tuple[str, ...]]] = [(module, name, last) for name in names]
    if spec.time_history is not None:
        called.append((module, f"sample_orbit{suffix}", ()))
    return called


def _compile_seconds(spec, two_starts: bool, kappa: float) -> float:
    """What compiling the run's kernels costs where numba's cache does not hold them: a family's compile
    once (its entry points share what they call)."""
    from friction_sweep.batch import kernel_cache

    cold = {module for module, name, last in kernels_called(spec, two_starts, kappa)
            if not kernel_cache.warm(module, name, last)}
    return sum(COMPILE_SECONDS[module] for module in cold)


def duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s" if seconds >= 1 else f"{seconds:.1g} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 172800:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"
