"""The Jenkins contact (effect contact_stiffness) against its harmonic-balance describing function (issue 19).

The element (contact spring kappa in series with a slider of force beta, docs/equations.md §7) driven by
q = a cos(theta) passes on, in its first harmonic, f1 = N(a) a with N = k_eq + i d_eq (the elastic-perfectly
plastic loop; Caughey 1960):

    kappa a <= beta:  N = kappa                                   (the slider never slips)
    kappa a >  beta:  k_eq = (kappa / pi) (psi - sin(2 psi) / 2),  psi = arccos(1 - 2 beta / (kappa a))
                      d_eq = 4 beta (a - beta / kappa) / (pi a^2)

d_eq from the loop's area: the energy per cycle 4 beta (a - beta/kappa) = pi a^2 d_eq (the parallelogram of
height 2 beta and width 2 (a - beta/kappa)); kappa -> oo gives the rigid Coulomb d_eq = 4 beta / (pi a) and
k_eq -> 0 like kappa^-1/2. The single-harmonic response of q'' + 2 zeta q' + q + f = A cos(r t) then solves

    |(1 + k_eq(a) - r^2) + i (d_eq(a) + 2 zeta r)| a = A

(root-found here by scanning a on a log grid and bisecting each sign change: near resonance there may be
more than one; the table uses the root nearest the simulation and counts them). The simulation's
first-harmonic amplitude of q (x for force and base, where c = 0; z = x - cos for joined) is compared
with it, and the response's third harmonic relative to the first is measured by the independent DOP853
integrator (tests/independent_jenkins.py), not the kernels.

Found (the numbers: README, "The Jenkins contact"; run this file as a script for the whole table): exact
where the slider never slips; elsewhere the describing function's error grows with the friction's share of
the forcing times the response's distortion, and it is within 2 % where h3 is below 0.5 %, not wherever h3
is below 5 %: the third harmonic of q understates how far the reversals (where the slider's force flips)
move from a sinusoid's.
"""

import sys

import numpy as np
import pytest
from independent_jenkins import jenkins_orbit
from scipy.optimize import brentq

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady
from friction_sweep.methods import event

KAPPAS = (1.0, 10.0, 100.0)
R = (0.3, 0.5, 0.8, 1.2, 1.6, 2.2, 3.0)
#: force ratios per scene: base (= force, the same kernel equation A = 1, c = 0 without damping) and
#: joined (A = r^2), from well below to above the continuous limits
BETAS = {"base": (0.1, 0.3, 0.6), "joined": (0.3, 0.8, 1.5)}
GRID = [(exc, r, beta, kappa) for exc, betas in BETAS.items() for kappa in KAPPAS for beta in betas for r in R]


def describing_function(a, beta, kappa):
    """N(a) = k_eq + i d_eq of the Jenkins element at slider-displacement amplitude a (module docstring)."""
    a = np.asarray(a, dtype=float)
    u = np.minimum(beta / (kappa * a), 1.0)  # 2u = 2 beta / (kappa a) <= 2 where the slider slips
    psi = np.arccos(1.0 - 2.0 * u)
    k_eq = kappa / np.pi * (psi - np.sin(2.0 * psi) / 2.0)  # = kappa at u = 1 (psi = pi): continuous
    d_eq = 4.0 * beta * (a - beta / kappa) / (np.pi * a * a)  # = 0 at u = 1
    held = kappa * a <= beta
    return np.where(held, kappa, k_eq) + 1j * np.where(held, 0.0, d_eq)


def balance(a, A, r, beta, kappa, zeta=0.0):
    """|(1 + k_eq - r^2) + i (d_eq + 2 zeta r)| a - A: zero at a single-harmonic response."""
    return np.abs(1.0 - r * r + 2j * zeta * r + describing_function(a, beta, kappa)) * a - A


def df_amplitudes(A, r, beta, kappa, zeta=0.0):
    """Every root a of the amplitude equation in [1e-6, 1e4] (log scan, then brentq on each sign change)."""
    grid = np.geomspace(1e-6, 1e4, 4000)
    g = balance(grid, A, r, beta, kappa, zeta)
    return [brentq(balance, grid[i], grid[i + 1], args=(A, r, beta, kappa, zeta), xtol=1e-15, rtol=1e-13)
            for i in np.nonzero(np.sign(g[1:]) != np.sign(g[:-1]))[0]]


def measure(exc, r, beta, kappa):
    """One row: the simulation's |Q1|, its regime, DOP853's h3 = |Q3| / |Q1|, the DF root nearest |Q1|, the
    relative error of that root and the number of roots."""
    effects = {"contact_stiffness": kappa}
    row = event.solve_flat(exc, np.array([r]), np.array([beta]), effects)[0]
    assert row[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    A, c, bk, bs, zeta = (float(p[0]) for p in event.point_parameters(exc, [r], [beta], effects))
    # x's first harmonic as a phasor against the excitation (lag phi): X = T e^(-i phi); q = x - c cos(r t)
    q1 = abs(row[steady.OUT_TRANSMISSIBILITY] * np.exp(-1j * np.radians(row[steady.OUT_PHASE])) - c)
    ind = jenkins_orbit(A, r, bk, bs, kappa, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W],
                        int(row[steady.OUT_END_MODE]), c=c, zeta=zeta, harmonics=(1, 3))
    h = ind["harmonics"]
    roots = df_amplitudes(A, r, beta, kappa, zeta)
    a = min(roots, key=lambda x: abs(x / q1 - 1.0))
    return {"exc": exc, "r": r, "beta": beta, "kappa": kappa, "A": A, "regime": Regime(int(row[steady.OUT_REGIME])),
            "q1": q1, "q1_dop853": h[1], "h3": h[3] / h[1], "df": a, "error": a / q1 - 1.0, "roots": len(roots)}


@pytest.fixture(scope="module")
def table():
    return [measure(*point) for point in GRID]


def slipping(row):
    return row["regime"] != Regime.STUCK


def markdown(rows) -> str:
    lines = ["| scene | r | β | κ | regime | \\|Q1\\| simulated | DF | DF error | h3/h1 (DOP853) | roots |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {x['exc']} | {x['r']:g} | {x['beta']:g} | {x['kappa']:g} | {x['regime'].name.lower()} | "
              f"{x['q1']:.5f} | {x['df']:.5f} | {100 * x['error']:+.2f} % | {100 * x['h3']:.2f} % | {x['roots']} |"
              for x in rows]
    return "\n".join(lines)


def test_the_grid_covers_every_regime(table):
    """The simulation's and DOP853's first harmonics are one orbit's (the kernel's end state continued by
    DOP853), and the grid holds stuck, stick-slip and continuous points."""
    for x in table:
        assert abs(x["q1_dop853"] / x["q1"] - 1.0) <= 1e-8, x
    counts = {reg: sum(x["regime"] == reg for x in table) for reg in Regime}
    assert counts[Regime.STUCK] >= 20 and counts[Regime.CONTINUOUS] >= 60 and counts[Regime.STICK_SLIP] >= 5
    print("\n" + markdown(table))  # the whole table with -s


def test_exact_where_the_slider_never_slips(table):
    """kappa a <= beta: the element is the linear spring kappa and the DF the exact forced response
    A / |1 + kappa - r^2|; the response has no third harmonic."""
    held = [x for x in table if not slipping(x)]
    for x in held:
        assert x["kappa"] * x["q1"] <= x["beta"] * (1 + 1e-9)
        assert abs(x["error"]) <= 1e-9 and x["h3"] <= 1e-9 and x["roots"] == 1, x


def test_within_two_percent_where_the_response_is_nearly_harmonic(table):
    """The harmonic-balance premise: within 2 % where the third harmonic is below 0.5 % of the first (the
    issue's 5 % is too loose: see the next test and the table); enough such points of every kappa."""
    near = [x for x in table if slipping(x) and x["h3"] < 0.005]
    assert len(near) >= 30 and {x["kappa"] for x in near} == set(KAPPAS)
    worst = max(near, key=lambda x: abs(x["error"]))
    assert abs(worst["error"]) <= 0.02, worst


def test_error_grows_with_friction_share_times_distortion(table):
    """On every slipping point (stick-slip with h3 up to 23 % included) the DF's error is below
    12 (beta / A) h3: friction that is a large share of the forcing (beta / A) flips at reversals that the
    response's harmonics (h3) move from the sinusoid's; the factor grows with kappa (README). The issue's
    criterion (2 % where h3 < 5 %) fails on part of the grid: those points are printed (-s)."""
    slips = [x for x in table if slipping(x)]
    ratio = [abs(x["error"]) / (x["beta"] / x["A"] * x["h3"]) for x in slips]
    assert max(ratio) <= 12.0, max(zip(ratio, [str(x) for x in slips], strict=True))
    small = [x for x in slips if x["h3"] < 0.05]
    beyond = [x for x in small if abs(x["error"]) > 0.02]
    print(f"\nh3 < 5 %: {len(small)} slipping points, {len(beyond)} beyond 2 %:\n" + markdown(beyond))
    assert len(small) >= 60


if __name__ == "__main__":
    rows = [measure(*point) for point in GRID]
    print(markdown(rows))
    slips = [x for x in rows if slipping(x)]
    for limit in (0.005, 0.01, 0.02, 0.05):
        sub = [x for x in slips if x["h3"] < limit]
        print(f"h3 < {100 * limit:g} %: {len(sub)} points, max |error| {100 * max(abs(x['error']) for x in sub):.2f} %, "
              f"{sum(abs(x['error']) > 0.02 for x in sub)} beyond 2 %", file=sys.stderr)
