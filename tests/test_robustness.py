"""Hard cases stay numerically stable, and the answer is the physically right one (issue: robustness).

Each test asserts an outcome, not only the absence of a crash.
"""

import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import OUTPUTS
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import event as ev
from friction_sweep.kernels import measure as rec
from friction_sweep.kernels import steady, stick
from friction_sweep.kernels.point import Point
from friction_sweep.methods import event, theory
from friction_sweep.theory import den_hartog as dh


def point(excitation, r, beta, **settings_):
    out = event.compute_tile(excitation, np.array([r]), np.array([beta]), OUTPUTS, settings=settings_)
    return {k: v.ravel()[0] for k, v in out.items()}


# --- next to resonance ------------------------------------------------------------------------------

EPS = np.array([1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-3])
R_NEAR = np.sort(np.concatenate([1 - EPS, [1.0], 1 + EPS]))


def test_near_resonance_is_finite_or_labelled_and_never_overflows():
    beta = np.array([0.3, 0.7, np.pi / 4, 0.8, 1.2])
    with np.errstate(over="raise", invalid="ignore"):
        e = event.compute_tile("base", R_NEAR, beta, OUTPUTS)
    th = theory.compute_tile("base", R_NEAR, beta, OUTPUTS)
    code = e["regime"]
    for name, valid in (("transmissibility", [Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS]),
                        ("peak_transmissibility", [Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS]),
                        ("phase", [Regime.STICK_SLIP, Regime.CONTINUOUS])):  # no motion, no phase
        v = e[name]
        assert not np.any(np.isinf(v))
        assert np.all(np.isfinite(v) == np.isin(code, valid)), name
    at_one = R_NEAR == 1.0
    # exactly at resonance: unbounded up to pi/4 included, finite stick-slip above, stuck from 1
    np.testing.assert_array_equal(code[:, at_one].ravel(), [Regime.UNBOUNDED] * 3 + [Regime.STICK_SLIP, Regime.STUCK])
    # below pi/4, 1e-8 <= |r - 1| <= 1e-3: the finite continuous steady state (amplitude up to 5e7),
    # accurate to the conditioning of the stroboscopic map, about 1e-15 / |1 - r|
    far = np.abs(R_NEAR - 1) >= 1e-8
    for i in (0, 1):
        sel = far
        assert np.all(code[i, sel] == Regime.CONTINUOUS)
        rel = np.abs(e["transmissibility"][i, sel] / th["transmissibility"][i, sel] - 1)
        assert np.all(rel <= 1e-13 / np.abs(R_NEAR[sel] - 1)), rel
    # above pi/4 the resonance is finite stick-slip on both sides
    assert np.all(code[3] == Regime.STICK_SLIP)
    assert np.all(np.isfinite(e["transmissibility"][3]))


def test_no_nan_leaks_into_neighbouring_points():
    r = np.array([0.9, 1.0, 1.1])
    beta = np.array([0.3])
    together = event.compute_tile("base", r, beta, OUTPUTS)
    assert together["regime"][0, 1] == Regime.UNBOUNDED
    for j in (0, 2):
        alone = event.compute_tile("base", r[j:j + 1], beta, OUTPUTS)
        for name in OUTPUTS[:2] + ("peak_transmissibility", "peak_phase"):
            assert together[name][0, j] == alone[name][0, 0]  # bit for bit


# --- far from resonance -----------------------------------------------------------------------------


def test_very_low_frequency_many_stops():
    p = point("base", 0.01, 0.3)
    assert p["regime"] == Regime.STICK_SLIP and p["steady_state"] == SteadyState.CONVERGED
    assert p["stops_per_period"] >= 20 and p["stops_per_period"] % 2 == 0
    # quasi-static limit: the first harmonic tends to a finite value, close to its r = 0.02 value
    assert p["transmissibility"] == pytest.approx(point("base", 0.02, 0.3)["transmissibility"], rel=5e-3)


@pytest.mark.parametrize("excitation", ["base", "joined"])
@pytest.mark.parametrize("r", [50.0, 100.0])
def test_high_frequency_tiny_amplitudes_are_accurate_relative_to_their_size(excitation, r):
    p = point(excitation, r, 0.3)
    th = theory.compute_tile(excitation, np.array([r]), np.array([0.3]), OUTPUTS)
    assert p["transmissibility"] < 1e-3
    assert p["transmissibility"] == pytest.approx(th["transmissibility"][0, 0], rel=1e-9)
    if excitation == "base":
        assert p["peak_transmissibility"] == pytest.approx(th["peak_transmissibility"][0, 0], rel=1e-9, abs=0)
    else:
        # joined: the state is z = x - cos(r t), of the wall's size 1 while x is 1e-4, and its velocity
        # carries the wall's r sin(r t): the fixed point is pinned to ~1e-12 of the wall amplitude (the
        # map's rounding over |eig(J - I)| ~ 2 pi / r), which the peak of x inherits absolutely (the
        # first harmonic, above, does not: a free-oscillation offset barely projects onto frequency r)
        assert p["peak_transmissibility"] == pytest.approx(th["peak_transmissibility"][0, 0], rel=0, abs=1e-11)


# --- ties -------------------------------------------------------------------------------------------


def test_ties_are_decided_alike_by_theory_and_simulation():
    # no motion: beta exactly 1 (fixed wall), exactly r*r (joined)
    assert point("base", 0.7, 1.0)["regime"] == Regime.STUCK
    assert theory.compute_tile("base", np.array([0.7]), np.array([1.0]), OUTPUTS)["regime"][0, 0] == Regime.STUCK
    r = 0.7
    assert point("joined", r, r * r)["regime"] == Regime.STUCK
    # the continuous limit: continuous at and just below beta*, stick-slip clearly above
    for rr in (0.8, 1.5, 3.0):
        bstar = float(dh.continuous_limit(rr))
        for b, expected in ((np.nextafter(bstar, 0), Regime.CONTINUOUS), (bstar, Regime.CONTINUOUS),
                            (bstar * (1 + 1e-6), Regime.STICK_SLIP)):
            th = theory.compute_tile("base", np.array([rr]), np.array([b]), OUTPUTS)["regime"][0, 0]
            assert th == expected and point("base", rr, b)["regime"] == expected, (rr, b)


# --- special frequencies --------------------------------------------------------------------------------


def test_quarter_frequency_converges_with_energy_balance():
    p = point("base", 0.25, 0.1)
    assert p["steady_state"] == SteadyState.CONVERGED and p["regime"] == Regime.STICK_SLIP
    _assert_energy_balance(p, 0.1)


@pytest.mark.slow
def test_singular_points_of_u_have_a_stop_free_motion_den_hartog_cannot_describe():
    """At r = 1/3 the friction square wave's third harmonic sits on the natural frequency, so Den
    Hartog's symmetric one-reversal orbit cannot exist for beta > 0 (the theory forecasts stick-slip),
    yet a stop-free orbit with extra velocity reversals does: an independent DOP853 run agrees."""
    from friction_sweep.bench.reference import measure

    p = point("base", 1 / 3, 0.01)
    assert p["regime"] == Regime.CONTINUOUS and p["stops_per_period"] == 0
    assert p["peak_transmissibility"] < p["transmissibility"]  # not a one-reversal shape
    t_ref, peak_ref = measure(1.0, 1 / 3, 0.01, 0.01, 200)
    assert p["transmissibility"] == pytest.approx(t_ref, rel=1e-9)
    assert p["peak_transmissibility"] == pytest.approx(peak_ref, rel=1e-6)
    th = theory.compute_tile("base", np.array([1 / 3, 1 / 5]), np.array([0.01]), OUTPUTS)
    assert np.all(th["regime"] == Regime.STICK_SLIP)


def _assert_energy_balance(p, beta):
    """Per period the force's work, pi |X1| sin(lag), equals the friction's, beta times the distance
    slid, 4 beta peak for an orbit that is monotone between its extremes (fixed wall, A = 1)."""
    work = np.pi * p["transmissibility"] * np.sin(np.radians(p["phase"]))
    assert work == pytest.approx(4 * beta * p["peak_transmissibility"], rel=1e-9)


@pytest.mark.parametrize("r,beta", [(2.0, 0.3), (0.8, 0.2), (0.3, 0.3), (1.2, 0.7), (0.1, 0.5)])
def test_energy_balance_over_a_period(r, beta):
    _assert_energy_balance(point("base", r, beta), beta)


# --- long runs ------------------------------------------------------------------------------------------


@pytest.mark.nojit_slow
def test_hundred_thousand_periods_without_drift():
    """Linear case from rest: the exact state after n periods is q = V (1 - cos nT), v = V sin nT."""
    r = 0.7
    V = 1 / (1 - r * r)
    T = 2 * np.pi / r
    acc = rec.new_accumulator()
    q, v, mode = 0.0, 0.0, stick.decide(0.0, 0.0, 1.0, r, 0.0)
    n = 100_000
    for _ in range(n):
        q, v, mode, status, _ = ev.advance_period(q, v, mode, Point(1.0, r, 0.0, 0.0, 0.0, 0.0), 1e-12, 10**6,
                                                  False, acc, ev.NO_SAMPLES, ev.NO_SAMPLES, ev.NO_SAMPLES)
    nT = n * T
    assert q == pytest.approx(V * (1 - np.cos(nT)), abs=1e-9 * V)
    assert v == pytest.approx(V * np.sin(nT), abs=1e-9 * V)


@pytest.mark.nojit_slow
def test_a_converged_orbit_stays_put_for_a_hundred_thousand_periods():
    out = event.solve_flat("base", np.array([0.3]), np.array([0.3]))[0]
    q, v, mode = out[steady.OUT_END_Q], out[steady.OUT_END_V], int(out[steady.OUT_END_MODE])
    acc = rec.new_accumulator()
    for _ in range(100):  # the search stops within steady_tol of the orbit; stick-slip lands on it
        q, v, mode, status, _ = ev.advance_period(q, v, mode, Point(1.0, 0.3, 0.3, 0.3, 0.0, 0.0), 1e-12, 10**6,
                                                  False, acc, ev.NO_SAMPLES, ev.NO_SAMPLES, ev.NO_SAMPLES)
    q0, v0 = q, v
    for _ in range(100_000):
        q, v, mode, status, _ = ev.advance_period(q, v, mode, Point(1.0, 0.3, 0.3, 0.3, 0.0, 0.0), 1e-12, 10**6,
                                                  False, acc, ev.NO_SAMPLES, ev.NO_SAMPLES, ev.NO_SAMPLES)
    assert abs(q - q0) + abs(v - v0) <= 1e-12


# --- properties ---------------------------------------------------------------------------------------------

finite_r = st.floats(0.05, 5.0).filter(lambda r: abs(r - 1) > 1e-3 and abs(r - 0.5) > 1e-3)
betas = st.floats(0.0, 1.5)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(excitation=st.sampled_from(["base", "joined"]), r=finite_r, beta=betas)
def test_every_output_is_finite_or_labelled_and_no_point_stalls(excitation, r, beta):
    p = point(excitation, r, beta)
    assert p["steady_state"] != SteadyState.EVENT_BUDGET  # every event advanced time
    assert p["regime"] in (Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS, Regime.UNSETTLED)
    numbers = [p[k] for k in ("transmissibility", "peak_transmissibility")]
    if p["regime"] == Regime.UNSETTLED:
        assert all(np.isnan(numbers)) and p["steady_state"] in (SteadyState.PERIOD_CAP, SteadyState.NONFINITE)
    else:
        assert all(np.isfinite(numbers)) and all(x >= 0 for x in numbers)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(r=st.floats(0.6, 4.0).filter(lambda r: abs(r - 1) > 0.05), beta=st.floats(0.1, 0.9),
       q0=st.floats(-3, 3), v0=st.floats(-3, 3))
def test_steady_state_does_not_depend_on_where_the_march_starts(r, beta, q0, v0):
    """A start at another state is also a start at rest with another forcing phase, or of the mirror
    image x -> -x (the equation is invariant under q -> -q, t -> t + T/2): all reach one orbit."""
    a = point("base", r, beta)
    b = point("base", r, beta, initial_displacement=q0, initial_velocity=v0)
    c = point("base", r, beta, initial_displacement=-q0, initial_velocity=-v0)
    for p in (b, c):
        assert p["regime"] == a["regime"]
        if a["regime"] != Regime.STUCK:
            assert p["transmissibility"] == pytest.approx(a["transmissibility"], rel=1e-8)
            assert p["phase"] == pytest.approx(a["phase"], abs=1e-6)


@pytest.mark.parametrize("r,beta,m,k,y", [(0.3, 0.3, 2.5, 40.0, 0.02), (0.7, 0.8, 0.3, 7.0, 3.0),
                                          (1.5, 0.8, 12.0, 0.5, 150.0)])
@pytest.mark.slow
def test_scaling_invariance_dimensional_parameters(r, beta, m, k, y):
    """m x'' + k x + muN sgn x' = k Y cos(w t) with w = r sqrt(k/m) and muN = beta k Y, integrated in
    physical units (seconds, metres, newtons) by an independent DOP853 integrator, gives x/Y equal to
    the dimensionless kernel's answer at (r, beta)."""
    from friction_sweep.bench.reference import measure

    p = point("base", r, beta)
    assert p["steady_state"] == SteadyState.CONVERGED and p["regime"] == Regime.STICK_SLIP
    w = r * np.sqrt(k / m)
    mu_n = beta * k * y
    # divide by m: x'' + (k/m) x + (muN/m) sgn = (kY/m) cos(w t); the reference takes q'' + w2 q + ...
    settle = int(point("base", r, beta, shoot_after=10**6)["periods"])  # the march's own count, shooting off
    t_ref, peak_ref = measure(k * y / m, w, mu_n / m, mu_n / m, settle + 5, w2=k / m)
    assert t_ref / y == pytest.approx(p["transmissibility"], rel=1e-7)
    assert peak_ref / y == pytest.approx(p["peak_transmissibility"], rel=1e-6)


# --- the pure-Python and bounds-checked paths ------------------------------------------------------------

SMALL_SPEC = """\
scene: {excitation: base}
grid: {frequency_ratio: [0.3, 1.0, 2.0], force_ratio: [0.3, 0.9]}
method: event
"""


@pytest.mark.parametrize("env", [{"NUMBA_DISABLE_JIT": "1"}, {"NUMBA_BOUNDSCHECK": "1"}], ids=["nojit", "boundscheck"])
@pytest.mark.slow
def test_small_sweep_with_numba_debug_switches(tmp_path, env):
    spec = tmp_path / "s.yaml"
    spec.write_text(SMALL_SPEC)
    ref = tmp_path / "ref.h5"
    out = tmp_path / "out.h5"
    fsweep = [sys.executable, "-m", "friction_sweep", "run", str(spec), "--quiet", "-o"]
    subprocess.run(fsweep + [str(ref)], check=True, capture_output=True)
    environment = {**os.environ, **env, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    res = subprocess.run(fsweep + [str(out)], capture_output=True, text=True, env=environment)
    assert res.returncode == 0, res.stderr
    from friction_sweep.storage import cube

    a, b = cube.open_cube(ref), cube.open_cube(out)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)


@pytest.mark.parametrize("r,beta,stops", [(0.05, 0.3, 8), (0.1, 0.5, 6), (0.03, 0.4, 14)])
@pytest.mark.slow
def test_clustered_stops_are_all_found(r, beta, stops):
    """Many stops per period at low r, some of them brief (at r = 0.1, beta = 0.5 the force leaves
    the band for only 2 % of a period): the independent integrator counts the same sticks."""
    from friction_sweep.bench.reference import simulate

    p = point("base", r, beta)
    settle = int(point("base", r, beta, shoot_after=10**6)["periods"])  # the march's own count, shooting off
    pieces, T, t_end = simulate(1.0, r, beta, beta, settle + 20)
    sticks = [piece for piece in pieces if piece[0] == "stick" and t_end - T - 1e-9 <= piece[1] < t_end
              and piece[2] - piece[1] > 1e-10 * T]
    assert p["stops_per_period"] == len(sticks) == stops


def test_no_zeno_stall_where_the_orbit_creeps_towards_grazing():
    """r = 0.45, beta = 0.25, marching: after ~1000 periods a stop leaves the force 2e-7 beyond the
    band edge and moving back in. The mass slips back for ~6e-6 and sticks; an early version declared
    a stop at once on every restart (the velocity was still below the stop tolerance while rising)
    and crept forward geometrically until the work budget ran out."""
    out = event.solve_flat("base", np.array([0.45]), np.array([0.25]), shoot_after=10**9)[0]
    assert out[steady.OUT_STEADY_STATE] != SteadyState.EVENT_BUDGET
    assert out[steady.OUT_WORK] / out[steady.OUT_PERIODS] < 500  # work per period stays ordinary


@pytest.mark.nojit_slow
def test_shooting_through_sticks_lands_where_the_slow_march_ends():
    """The same point: the march creeps onto a two-stop orbit (its distance falls ~10x per 3,000
    periods, so a march stopped by steady_tol 1e-10 is still 1e-7 away); shooting from the first
    stop-free period (Newton iterates may stick: the exact Jacobian through sticks) finds the orbit at once.
    A march to steady_tol 1e-14 (~27,000 periods) must land on it."""
    shot = event.solve_flat("base", np.array([0.45]), np.array([0.25]))[0]
    march = event.solve_flat("base", np.array([0.45]), np.array([0.25]), shoot_after=10**9, max_periods=60_000,
                             steady_tol=1e-14)[0]
    assert shot[steady.OUT_STEADY_STATE] == march[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    assert shot[steady.OUT_PERIODS] < 20 < 20_000 < march[steady.OUT_PERIODS]  # every period counted
    assert shot[steady.OUT_STOPS_PER_PERIOD] == march[steady.OUT_STOPS_PER_PERIOD] == 2
    assert shot[steady.OUT_TRANSMISSIBILITY] == pytest.approx(march[steady.OUT_TRANSMISSIBILITY], rel=1e-12)
    assert shot[steady.OUT_PEAK_TRANSMISSIBILITY] == pytest.approx(march[steady.OUT_PEAK_TRANSMISSIBILITY], rel=1e-10)


