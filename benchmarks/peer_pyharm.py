"""The harmonic-balance peer side by side with fsweep (issue 32 item 5): pyHarm (`pyharm-os`, Safran's
open-source harmonic-balance code; the extra `peers`: pip install -e '.[peers]') on fsweep's 1-DoF force
scene, with a rigid contact and with a Jenkins contact, at H = 1, 3, 5, 9, 15, 21 harmonics: the error of
its first harmonic against fsweep's exact `event` solution at the same points, and the time per frequency
point of each, in one run.

    python benchmarks/peer_pyharm.py [--points 31] [--harmonics 1 3 5 9 15 21] [-o results/bench/peer_pyharm.md]

Without pyHarm it prints one line saying so and exits 0 (make bench goes on).

The scene: q'' + 2 zeta q' + q + f = cos(r t) (force, kernel units: F0/k), zeta = 0.05, friction beta = 0.5
of the forcing; the rigid contact (Coulomb), and the Jenkins contact of stiffness kappa = 10; r from 0.5 to 2
(--points, through the resonance and the stick-slip near it).

pyHarm is set up as its documentation and its own defaults have it (pyHarm/Maestro.py's input dictionary:
"system" Base with nh harmonics and nti time samples, a 1-dof "substructure" with matrices M = 1,
C = 2 zeta, K = 1, "connectors" CosinusForcing amp 1 and the contact to the ground):
  - rigid contact: element DLFTFriction (the Dynamic Lagrangian Frequency-Time method, pyHarm's element for
    the Coulomb contact without a tangential spring), mu = beta, N0 = 1, penalty eps = 100. pyHarm's answer
    moves with eps (it should not, at convergence): eps = 1, the structure's stiffness, as the DLFT
    literature (Nacivet et al. 2003) suggests, is 60-70 % off; 100 was the best of 1, 10, 100, 1e3, 1e4, 1e5
    on 7 points (from 1e3 up more points fail, and from 1e4 up some are accepted at q = 0). The table's
    last rows show eps = 1 and 1000, and nti = 512, at the largest H;
  - Jenkins contact: element Jenkins (AFT: a spring k = kappa in series with the slider), mu = beta, N0 = 1;
  - nti = 128 time samples per period, pyHarm's default (>= 2H + 1 for H <= 63);
  - analysis: study "frf" with the "nocontinuation" corrector (pyHarm's fixed-frequency solve), each point
    solved from pyHarm's default start (x0 None: the linear solution at that frequency) by its default
    solver ("scipyroot", MINPACK hybr, accepted at residual 1e-4), through the analysis' initialise();
    the system is built once per H, each frequency point re-solved in it.
A point pyHarm does not accept (flag_accepted False) is a failure: counted, and left out of the error.

fsweep: method event (the exact event-driven orbit, first start), the same points, through
friction_sweep.methods.event.solve_flat; time per point of the best of 3 (kernels compiled first).

Error: |Q1_pyHarm / Q1_event - 1|, Q1 the first-harmonic amplitude of q (pyHarm's from its harmonic
coefficients through its own DFT operators and an FFT of the resulting time series); median and max over
the accepted points.
"""

from __future__ import annotations

import argparse
import logging
import os
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ZETA, BETA, KAPPA = 0.05, 0.5, 10.0
HARMONICS = (1, 3, 5, 9, 15, 21)
NTI = 128


def fsweep_points(r: np.ndarray, kappa: float) -> tuple[np.ndarray, float]:
    """fsweep event's first-harmonic amplitude at each r, and its time per point (best of 3)."""
    from friction_sweep.kernels import steady
    from friction_sweep.methods import event

    effects = {"viscous_damping": ZETA, **({"contact_stiffness": kappa} if kappa else {})}
    beta = np.full(r.shape, BETA)
    rows = event.solve_flat("force", r, beta, effects)  # compiles or loads the kernels
    best = np.inf
    for _ in range(3):
        t = time.perf_counter()
        rows = event.solve_flat("force", r, beta, effects)
        best = min(best, time.perf_counter() - t)
    return rows[:, steady.OUT_TRANSMISSIBILITY], best / r.size


def pyharm_input(contact: dict, harmonics: int, r0: float, nti: int = NTI) -> dict:
    """pyHarm's input dictionary (module docstring)."""
    return {
        "analysis": {"point": {"study": "frf", "corrector": "nocontinuation", "puls_inf": r0, "puls_sup": r0,
                               "puls_start": r0, "verbose": False}},
        "system": {"type": "Base", "nh": harmonics, "nti": nti},
        "substructures": {"mass": {"matrix": {"M": np.array([[1.0]]), "C": np.array([[2 * ZETA]]),
                                              "K": np.array([[1.0]]), "G": np.array([[0.0]])}, "ndofs": 1}},
        "connectors": {"loading": {"type": "CosinusForcing", "connect": {"mass": [0]}, "dirs": [0], "amp": 1.0},
                       "contact": {"connect": {"mass": [0]}, "dirs": [0], "mu": BETA, "N0": 1.0, **contact}},
    }


def pyharm_points(r: np.ndarray, contact: dict, harmonics: int, nti: int = NTI) -> tuple[np.ndarray, float]:
    """pyHarm's first-harmonic amplitude at each r (NaN where it fails) and its time per point."""
    from pyHarm.DynamicOperator import compute_DFT
    from pyHarm.Maestro import Maestro

    maestro = Maestro(pyharm_input(contact, harmonics, float(r[0]), nti))
    analysis = maestro.nls["point"]
    dft = compute_DFT(maestro.system.nti, maestro.system.nh)["ft"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        dof = maestro.getIndex("mass", 0, 0)
    q1 = np.full(r.shape, np.nan)
    spent = 0.0
    for i, om in enumerate(r):
        analysis.SolList = []
        analysis.analysis_options["puls_start"] = float(om)
        t = time.perf_counter()
        try:
            analysis.initialise()
        except Exception:  # a solve that raises is a failure of that point, as one not accepted
            spent += time.perf_counter() - t
            continue
        spent += time.perf_counter() - t
        sol = analysis.SolList[-1]
        if sol.flag_accepted and abs(sol.x[-1] - om) <= 1e-9 * om:
            q = sol.x[dof] @ dft
            q1[i] = abs(2.0 / q.size * np.fft.rfft(q)[1])
    return q1, spent / r.size


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=31)
    ap.add_argument("--harmonics", type=int, nargs="+", default=list(HARMONICS))
    ap.add_argument("-o", "--output", default="results/bench/peer_pyharm.md")
    args = ap.parse_args()
    out = Path(args.output)
    # pyHarm records its "kernel state" at import, by default in ./.pyHarm/: beside the output instead
    os.environ.setdefault("PYHARM_CONTEXT_FILE", str(out.parent / "pyharm_context.json"))
    try:
        import pyHarm  # noqa: F401
    except ImportError:
        print("peer_pyharm: skipped: pyHarm is not installed (pip install -e '.[peers]')")
        return 0
    logging.disable(logging.CRITICAL)  # pyHarm logs every solve
    warnings.filterwarnings("ignore", module="numba")
    r = np.linspace(0.5, 2.0, args.points)
    scenes = [("rigid (DLFT, eps 100)", 0.0, {"type": "DLFTFriction", "eps": 100.0}),
              ("Jenkins κ = 10", KAPPA, {"type": "Jenkins", "k": KAPPA})]
    lines = [f"force scene, ζ = {ZETA}, β = {BETA}, r = 0.5–2 ({args.points} points)", "",
             "| contact | H | pyHarm nti | pyHarm failures | median error | max error | pyHarm ms/point | "
             "fsweep event µs/point |", "|---|---|---|---|---|---|---|---|"]
    top = max(args.harmonics)
    cases = [(name, kappa, contact, h, NTI) for name, kappa, contact in scenes for h in args.harmonics]
    cases += [("rigid (DLFT, eps 1)", 0.0, {"type": "DLFTFriction", "eps": 1.0}, top, NTI),
              ("rigid (DLFT, eps 1000)", 0.0, {"type": "DLFTFriction", "eps": 1000.0}, top, NTI),
              ("rigid (DLFT, eps 100)", 0.0, {"type": "DLFTFriction", "eps": 100.0}, top, 512)]
    pyharm_points(r[:2], scenes[0][2], 1)  # pyHarm's numba functions compiled (or loaded) before timing
    pyharm_points(r[:2], scenes[1][2], 1)
    exact = {kappa: fsweep_points(r, kappa) for _, kappa, _ in scenes}
    for name, kappa, contact, h, nti in cases:
        q1, per_point = pyharm_points(r, contact, h, nti)
        ref, ref_time = exact[kappa]
        ok = np.isfinite(q1)
        err = np.abs(q1[ok] / ref[ok] - 1.0)
        med = f"{100 * statistics.median(err):.3g} %" if err.size else "–"
        worst = f"{100 * err.max():.3g} %" if err.size else "–"
        lines.append(f"| {name} | {h} | {nti} | {int((~ok).sum())} of {r.size} | {med} | {worst} | "
                     f"{1e3 * per_point:.1f} | {1e6 * ref_time:.0f} |")
        print(lines[-1], flush=True)
    text = "\n".join(lines) + "\n"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text + f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
