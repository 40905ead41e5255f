"""The harmonic-balance peer side by side with fsweep (issue 32 item 5): pyHarm (`pyharm-os`, Safran's
open-source harmonic-balance code; the extra `peers`: pip install -e '.[peers]') on fsweep's 1-DoF force
scene, with a rigid contact and with a Jenkins contact, and on a 2-mass chain with one rigid contact, at
H = 1, 3, 5, 9, 15, 21 harmonics: the error of its first harmonic against fsweep's exact `event` solution at
the same points, and the time per frequency point of each, in one run.

    python benchmarks/peer_pyharm.py [--points 31] [--harmonics 1 3 5 9 15 21] [-o results/bench/peer_pyharm.md]

Without pyHarm it prints one line saying so and exits 0 (make bench goes on).

The scene: q'' + 2 zeta q' + q + f = cos(r t) (force, kernel units: F0/k), zeta = 0.05, friction beta = 0.5
of the forcing; the rigid contact (Coulomb), and the Jenkins contact of stiffness kappa = 10; r from 0.5 to 2
(--points, through the resonance and the stick-slip near it). The chain: the blade and its platform damper
of benchmarks/structures.py (masses 1 and 0.1, springs ground-blade 1 and blade-damper 2, a dashpot 0.004 at
the blade, a rigid contact of friction 0.3 from the damper to the ground, the force cos(w t) on the blade),
w from 0.2 to 3 (--points), friction_scale 1; its error is the larger of the two masses'.

pyHarm is set up as its documentation and its own defaults have it (pyHarm/Maestro.py's input dictionary:
"system" Base with nh harmonics and nti time samples, a "substructure" of one dof per node with fsweep's
matrices (1-DoF: M = 1, C = 2 zeta, K = 1), "connectors" CosinusForcing amp 1 and the contact to the ground):
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
friction_sweep.methods.event.solve_flat (1-DoF) and friction_sweep.structures.solve_points (the chain); time
per point of the best of 3 (kernels compiled first).

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


def one_dof_model() -> dict:
    """The 1-DoF force scene's matrices (kernel units), its forced node and its contact's node and friction."""
    return {"M": np.array([[1.0]]), "C": np.array([[2 * ZETA]]), "K": np.array([[1.0]]), "forced": 0, "contact_at": 0,
            "mu": BETA}


def chain_model():
    """The 2-mass chain of benchmarks/structures.py (the issue's blade and its platform damper: a rigid contact
    from the damper to the ground, force on the blade), assembled by fsweep, with the same matrices for pyHarm."""
    from structures import BLADE  # benchmarks/structures.py, beside this script

    from friction_sweep.structures import assemble

    a = assemble(BLADE)
    return a, {"M": a.M, "C": a.C, "K": a.K, "forced": 0, "contact_at": 1, "mu": BLADE.contacts[0].friction}


def best_of_3(solve) -> tuple[np.ndarray, float]:
    solve()  # compiles or loads the kernels
    best, out = np.inf, None
    for _ in range(3):
        t = time.perf_counter()
        out = solve()
        best = min(best, time.perf_counter() - t)
    return out, best


def fsweep_points(r: np.ndarray, kappa: float) -> tuple[np.ndarray, float]:
    """fsweep event's first-harmonic amplitude at each r (r x 1), and its time per point (best of 3)."""
    from friction_sweep.kernels import steady
    from friction_sweep.methods import event

    effects = {"viscous_damping": ZETA, **({"contact_stiffness": kappa} if kappa else {})}
    beta = np.full(r.shape, BETA)
    rows, spent = best_of_3(lambda: event.solve_flat("force", r, beta, effects))
    return rows[:, steady.OUT_TRANSMISSIBILITY, None], spent / r.size


def fsweep_chain(assembled, w: np.ndarray) -> tuple[np.ndarray, float]:
    """fsweep's multi-DoF engine (method event): each mass's first-harmonic amplitude (w x 2), time per point."""
    from friction_sweep.structures import solve_points

    res, spent = best_of_3(lambda: solve_points(assembled, w, np.ones_like(w)))
    return res["amplitude"], spent / w.size


def pyharm_input(model: dict, contact: dict, harmonics: int, r0: float, nti: int = NTI) -> dict:
    """pyHarm's input dictionary (module docstring): one substructure of one dof per node, the forcing and
    the contact (to the ground) at their nodes."""
    n = model["M"].shape[0]
    return {
        "analysis": {"point": {"study": "frf", "corrector": "nocontinuation", "puls_inf": r0, "puls_sup": r0,
                               "puls_start": r0, "verbose": False}},
        "system": {"type": "Base", "nh": harmonics, "nti": nti},
        "substructures": {"mass": {"matrix": {"M": np.asarray(model["M"], float), "C": np.asarray(model["C"], float),
                                              "K": np.asarray(model["K"], float), "G": np.zeros((n, n))},
                                   "ndofs": 1}},
        "connectors": {"loading": {"type": "CosinusForcing", "connect": {"mass": [model["forced"]]}, "dirs": [0],
                                   "amp": 1.0},
                       "contact": {"connect": {"mass": [model["contact_at"]]}, "dirs": [0], "mu": model["mu"],
                                   "N0": 1.0, **contact}},
    }


def pyharm_points(r: np.ndarray, model: dict, contact: dict, harmonics: int,
                  nti: int = NTI) -> tuple[np.ndarray, float]:
    """pyHarm's first-harmonic amplitude of every node at each r (r x nodes; NaN where it fails) and its time
    per point."""
    from pyHarm.DynamicOperator import compute_DFT
    from pyHarm.Maestro import Maestro

    maestro = Maestro(pyharm_input(model, contact, harmonics, float(r[0]), nti))
    analysis = maestro.nls["point"]
    dft = compute_DFT(maestro.system.nti, maestro.system.nh)["ft"]
    nodes = model["M"].shape[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        dofs = [maestro.getIndex("mass", node, 0) for node in range(nodes)]
    q1 = np.full((r.size, nodes), np.nan)
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
            for k, dof in enumerate(dofs):
                q = sol.x[dof] @ dft
                q1[i, k] = abs(2.0 / q.size * np.fft.rfft(q)[1])
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
    one = one_dof_model()
    assembled, chain = chain_model()
    w = np.linspace(0.2, 3.0, args.points)
    # the title goes (benchmarks/readme_tables.py puts the rest between the README's bench-peer markers)
    lines = ["# pyHarm side by side (benchmarks/peer_pyharm.py)", "",
             f"force scene, ζ = {ZETA}, β = {BETA}, r = 0.5–2 ({args.points} points); 2-mass chain (blade and "
             f"platform damper, benchmarks/structures.py), ω = 0.2–3 ({args.points} points), error the larger "
             f"of the two masses'; {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start", "",
             "| scene, contact | H | pyHarm nti | pyHarm failures | median error | max error | pyHarm ms/point | "
             "fsweep event µs/point |", "|---|---|---|---|---|---|---|---|"]
    top = max(args.harmonics)
    dlft = {"type": "DLFTFriction", "eps": 100.0}
    cases = [("1-DoF, rigid (DLFT, eps 100)", "rigid", one, dlft, h, NTI) for h in args.harmonics]
    cases += [("1-DoF, Jenkins κ = 10", "jenkins", one, {"type": "Jenkins", "k": KAPPA}, h, NTI)
              for h in args.harmonics]
    cases += [("1-DoF, rigid (DLFT, eps 1)", "rigid", one, {"type": "DLFTFriction", "eps": 1.0}, top, NTI),
              ("1-DoF, rigid (DLFT, eps 1000)", "rigid", one, {"type": "DLFTFriction", "eps": 1000.0}, top, NTI),
              ("1-DoF, rigid (DLFT, eps 100)", "rigid", one, dlft, top, 512)]
    cases += [("2-mass chain, rigid (DLFT, eps 100)", "chain", chain, dlft, h, NTI) for h in args.harmonics]
    pyharm_points(r[:2], one, dlft, 1)  # pyHarm's numba functions compiled (or loaded) before timing
    pyharm_points(r[:2], one, {"type": "Jenkins", "k": KAPPA}, 1)
    exact = {"rigid": fsweep_points(r, 0.0), "jenkins": fsweep_points(r, KAPPA), "chain": fsweep_chain(assembled, w)}
    for name, key, model, contact, h, nti in cases:
        points = w if key == "chain" else r
        q1, per_point = pyharm_points(points, model, contact, h, nti)
        ref, ref_time = exact[key]
        ok = np.all(np.isfinite(q1), axis=1)
        err = np.max(np.abs(q1[ok] / ref[ok] - 1.0), axis=1)
        med = f"{100 * statistics.median(err):.3g} %" if err.size else "–"
        worst = f"{100 * err.max():.3g} %" if err.size else "–"
        lines.append(f"| {name} | {h} | {nti} | {int((~ok).sum())} of {points.size} | {med} | {worst} | "
                     f"{1e3 * per_point:.1f} | {1e6 * ref_time:.0f} |")
        print(lines[-1], flush=True)
    text = "\n".join(lines) + "\n"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text + f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
