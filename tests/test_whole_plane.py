"""Every point of the (r, beta) plane answered right (issue: whole plane).

Regression tests for the classes found on the paper's full planes: fake steady states at resonance,
ties broken by rounding, points left unsettled that have an answer, the r = 1/(2n) family, motion that
never repeats under static friction; and the whole-plane consistency rules of `fsweep check` on
coarse planes of every scene and effect.
"""

import numpy as np
import pytest
from conftest import OUTPUTS, STATIC

from friction_sweep import consistency, ties
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import event as ev
from friction_sweep.kernels import measure as rec
from friction_sweep.kernels.point import Point
from friction_sweep.methods import event, rk4, theory
from friction_sweep.storage import cube, provenance
from friction_sweep.theory import den_hartog as dh

DAMPED = {"viscous_damping": 0.05}


def tile(excitation, r, beta, effects=None, method=event, **settings):
    return method.compute_tile(excitation, np.atleast_1d(np.asarray(r, float)), np.atleast_1d(np.asarray(beta, float)),
                               OUTPUTS, effects, settings)


def amplitude(excitation, r):
    return r * r if excitation == "joined" else 1.0


# --- fake steady states at resonance -----------------------------------------------------------------

R_ONE = [1.0, float(np.nextafter(1.0, 2.0)), float(np.nextafter(1.0, 0.0))]  # r = 1 and within rounding


@pytest.mark.parametrize("effects", [None, pytest.param(STATIC, marks=pytest.mark.nojit_slow)], ids=["plain", "static"])
@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_at_resonance_every_moving_point_below_pi_over_4_is_unbounded(excitation, effects):
    """Newton used to leap to states of size 1e15..1e68 whose O(1) drift per period is lost in rounding
    and report them `continuous` (9 of 79 points per paper plane). Every beta, not only those."""
    beta = np.concatenate([np.linspace(0.0, 0.78, 40), [np.pi / 4]])
    out = tile(excitation, R_ONE, beta, effects)
    mu = (effects or {}).get("static_friction_ratio", 1.0)
    moves = ~ties.never_moves(amplitude(excitation, 1.0), mu * beta)
    code = out["regime"][moves]
    assert np.all(code == Regime.UNBOUNDED), beta[np.any(out["regime"] != Regime.UNBOUNDED, axis=1) & moves]
    assert np.all(np.isnan(out["transmissibility"][moves]))
    assert np.all(out["regime"][~moves] == Regime.STUCK)


def test_the_rk4_map_has_no_resonance_orbit_either():
    """RK4's map detunes the resonance by its truncation error and has a bounded orbit of size ~1e8 at
    r = 1; the acceptance weighs the map's own error, so it is refused like a rounding artefact."""
    out = tile("base", 1.0, [0.0, 0.2, 0.5, 0.78], method=rk4)
    assert np.all(out["regime"] == Regime.UNBOUNDED)


def test_damped_resonance_stays_finite_and_within_the_proven_bound():
    beta = np.array([0.0, 0.2, 0.5, 0.78])
    out = tile("base", 1.0, beta, DAMPED)
    assert np.all(out["steady_state"] == SteadyState.CONVERGED)
    assert np.all(np.isin(out["regime"], [Regime.CONTINUOUS, Regime.STICK_SLIP]))
    # at beta = 0 the linear damped response 1/(2 zeta); friction only lowers it here
    assert out["transmissibility"][0, 0] == pytest.approx(1 / (2 * 0.05), rel=1e-9)
    bound = (1 + 4 * beta / np.pi) / (2 * 0.05)
    assert np.all(out["transmissibility"][:, 0] <= bound * (1 + 1e-14))  # at beta = 0 the bound is the answer


def test_damped_linear_response_is_found_at_once_and_exact():
    """beta = 0 with a dashpot to ground: |X| = 1/|1 - r^2 + 2i zeta r|, found by the first shooting
    solve; a damped slip piece starts as a Taylor series, which must join its closed form seamlessly."""
    r = np.array([0.3, 0.9, 1.27, 1.31, 1.38, 2.0, 5.0])
    out = tile("base", r, 0.0, DAMPED)
    exact = 1 / np.abs(1 - r * r + 2j * 0.05 * r)
    np.testing.assert_allclose(out["transmissibility"][0], exact, rtol=1e-10)
    # every period counted: the one marched, Newton's step from it confirmed by one measured period
    assert np.all(out["periods"][0] <= 3) and np.all(out["orbit_period"][0] == 1)


@pytest.mark.parametrize("detuning", [1e-8, 1e-6, 1e-4])
def test_large_true_amplitudes_next_to_resonance_are_kept(detuning):
    """A correct amplitude ~1/(2|1 - r|) is no fake: it matches the closed form."""
    r = np.array([1 - detuning, 1 + detuning])
    out = tile("base", r, 0.3)
    th = theory.compute_tile("base", r, np.array([0.3]), OUTPUTS)
    assert np.all(out["regime"] == Regime.CONTINUOUS)
    np.testing.assert_allclose(out["transmissibility"], th["transmissibility"], rtol=1e-13 / detuning)


# --- ties ----------------------------------------------------------------------------------------------

# decimal points on the joined no-motion boundary beta = r^2, where r*r rounds an ulp above beta
JOINED_TIES = [(0.1, 0.01), (0.2, 0.04), (0.4, 0.16), (0.8, 0.64), (1.1, 1.21), (0.3, 0.09), (0.7, 0.49)]


@pytest.mark.parametrize("effects", [None, DAMPED], ids=["plain", "damped"])
def test_joined_no_motion_ties_are_stuck_however_r_times_r_rounds(effects):
    r, beta = np.array(JOINED_TIES).T
    assert np.any(r * r > beta)  # the trap: some products round above
    for ri, bi in JOINED_TIES:
        out = tile("joined", ri, bi, effects)
        assert out["regime"][0, 0] == Regime.STUCK, (ri, bi)
        assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["periods"][0, 0] <= 2
        assert out["transmissibility"][0, 0] == 1.0  # rides with the wall
        assert theory.compute_tile("joined", np.array([ri]), np.array([bi]), OUTPUTS)["regime"][0, 0] == Regime.STUCK


def test_static_friction_ties_are_stuck_too():
    # 1.5 * beta = r^2 on paper: r = 0.3, beta = 0.06; r = 0.6, beta = 0.24; base: 1.5 * beta = 1 at beta = 2/3
    for excitation, r, beta in (("joined", 0.3, 0.06), ("joined", 0.6, 0.24), ("base", 0.7, 1 / 1.5),
                                ("base", 2.0, np.nextafter(1 / 1.5, 0))):
        out = tile(excitation, r, beta, STATIC)
        assert out["regime"][0, 0] == Regime.STUCK, (excitation, r, beta)


def test_resonance_ties_within_rounding_of_one():
    for r in R_ONE:
        for beta, expected in ((0.5, Regime.UNBOUNDED), (np.pi / 4, Regime.UNBOUNDED), (0.9, Regime.STICK_SLIP)):
            th = theory.compute_tile("base", np.array([r]), np.array([beta]), OUTPUTS)["regime"][0, 0]
            assert th == expected and tile("base", r, beta)["regime"][0, 0] == expected, (r, beta)


@pytest.mark.parametrize("effects", [pytest.param(None, marks=pytest.mark.nojit_slow), STATIC,
                                     pytest.param(DAMPED, marks=pytest.mark.nojit_slow)],
                         ids=["plain", "static", "damped"])
@pytest.mark.parametrize("excitation", ["base", "joined"])
def test_just_below_the_no_motion_threshold_the_tiny_motion_settles(excitation, effects):
    """beta = A (1 - e): the force leaves the band by e and moves the mass by ~e^1.5 per half period,
    far below the forcing; the search used to stall (event_budget) or creep for every e from 1e-15 to
    1e-6. Inside the tie (e <= 1e-12) the mass is stuck; outside it the tiny motion is answered, as
    stick-slip, or as stuck where it moves the mass by less than steady_tol of the excitation (the
    resolution of a steady state: e^1.5 times a factor that falls with r below 1e-10)."""
    mu = (effects or {}).get("static_friction_ratio", 1.0)
    for r in (0.3, 1.0, 3.0):
        A = amplitude(excitation, r)
        for e in (1e-15, 1e-13, 3e-12, 1e-10, 1e-8, 1e-6, 1e-4):
            beta = A * (1 - e) / mu
            out = tile(excitation, r, beta, effects)
            code = out["regime"][0, 0]
            if e < ties.TIE_RTOL:
                expected = {Regime.STUCK}
            elif r == 1.0 and effects != DAMPED and beta / A <= ties.RESONANCE_FRICTION_LIMIT:
                expected = {Regime.UNBOUNDED}  # static friction 1.5: once moving, kinetic b = 2/3 < pi/4
            else:
                expected = {Regime.STICK_SLIP} if e >= 1e-4 else {Regime.STUCK, Regime.STICK_SLIP}
            assert code in expected, (r, e, code, out["steady_state"][0, 0])
            if code == Regime.STUCK:  # no motion: exactly the no-motion values
                assert out["transmissibility"][0, 0] == (1.0 if excitation == "joined" else 0.0)
            if code != Regime.UNBOUNDED:
                assert out["steady_state"][0, 0] == SteadyState.CONVERGED, (r, e, out["steady_state"][0, 0])


# --- slow approaches: an answer within the default budgets ------------------------------------------------

# Each steady transmissibility was computed independently (an exact-slip integrator with event
# switching written for this check, not this package's kernels, and Newton on its period map; it
# agreed with bench/reference.py's DOP853 to 1e-10): the march reaches these only after 1e4..1e6 periods
# (multipliers 0.9921..0.99999).
SLOW = [("base", 0.31, 0.09, 1.0880197801), ("base", 0.33, 0.11, 1.1382321930), ("base", 0.36, 0.13, 1.2052101214),
        ("base", 0.48, 0.30, 1.4194927298), ("joined", 0.32, 0.01, 1.1134309308),
        ("joined", 0.37, 0.02, 1.1661688947), ("joined", 0.97, 0.75, 1.0123254040)]


@pytest.mark.parametrize("excitation,r,beta,expected", SLOW)
def test_slowly_approached_orbits_are_solved(excitation, r, beta, expected):
    out = tile(excitation, r, beta)
    assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["regime"][0, 0] == Regime.STICK_SLIP
    assert out["transmissibility"][0, 0] == pytest.approx(expected, rel=2e-10)
    assert out["stops_per_period"][0, 0] == 2


def test_next_to_the_joined_no_motion_boundary_near_resonance():
    for r, beta in ((0.99, 0.98), (1.01, 1.02), (1.02, 1.04)):
        out = tile("joined", r, beta)
        assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["regime"][0, 0] == Regime.STICK_SLIP
        assert out["transmissibility"][0, 0] == pytest.approx(1.0, abs=1e-8)  # z moves by ~3e-8


@pytest.mark.parametrize("excitation,r,beta,k", [("base", 0.11, 0.01, 16), ("base", 0.22, 0.05, 10),
                                                 ("base", 0.33, 0.1, 37), ("base", 0.37, 0.11, 253),
                                                 ("joined", 0.45, 0.05, 17)])
def test_static_friction_locks_onto_long_periods(excitation, r, beta, k):
    """Periods found independently (see SLOW), except 253, found by the tool and checked by its march."""
    out = tile(excitation, r, beta, STATIC)
    assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["orbit_period"][0, 0] == k


@pytest.mark.slow
def test_motion_that_never_repeats_has_its_own_flag_and_it_is_chaos():
    """Static above kinetic friction: at base (0.4, 0.15) nearby motions separate (Lyapunov exponent
    +0.065 per period, measured independently). The flag is `aperiodic`, with averages over 256
    periods; an independent DOP853 integration confirms the sensitivity: a change of beta by 1e-9
    (1.5e-10 absolute) grows a thousandfold within 150 periods, while next to a period-10 orbit
    (0.22, 0.05) it shrinks."""
    from friction_sweep.bench.reference import simulate

    out = tile("base", 0.4, 0.15, STATIC)
    assert out["steady_state"][0, 0] == SteadyState.APERIODIC and out["regime"][0, 0] == Regime.STICK_SLIP
    assert out["orbit_period"][0, 0] == 256
    assert out["transmissibility"][0, 0] == pytest.approx(1.2865, abs=0.01)  # independent mean +- spread

    def end_state(r, beta, periods):
        pieces, _, t_end = simulate(1.0, r, beta, 1.5 * beta, periods)
        kind, a, b, data = pieces[-1]
        return data if kind == "stick" else data(t_end)[0]

    assert abs(end_state(0.4, 0.15 * (1 + 1e-9), 150) - end_state(0.4, 0.15, 150)) > 1.5e-7
    assert abs(end_state(0.22, 0.05 * (1 + 1e-9), 60) - end_state(0.22, 0.05, 60)) < 1e-10


def test_plain_friction_is_never_aperiodic():
    """With static = kinetic friction the period map does not expand distances: no chaos to flag."""
    out = tile("base", np.linspace(0.1, 0.6, 26), np.linspace(0.01, 0.3, 6))
    assert not np.any(out["steady_state"] == SteadyState.APERIODIC)


# --- r = 1/(2n) ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("excitation", ["base", "joined"])
@pytest.mark.parametrize("r", [0.5, 0.25, 0.1])
def test_the_subharmonic_family_is_named_and_its_first_harmonic_is_den_hartogs(excitation, r):
    """At r = 1/(2n) stick-free orbits form a continuum; the tool flags `family` and reports the first
    harmonic (the family's) and the symmetric member's peak, both Den Hartog's closed form there."""
    bstar = float(dh.continuous_limit(r))
    beta = 0.5 * bstar * amplitude(excitation, r)
    out = tile(excitation, r, beta)
    th = theory.compute_tile(excitation, np.array([r]), np.array([beta]), OUTPUTS)
    assert out["steady_state"][0, 0] == SteadyState.FAMILY and out["regime"][0, 0] == Regime.CONTINUOUS
    assert out["transmissibility"][0, 0] == pytest.approx(th["transmissibility"][0, 0], rel=1e-10)
    assert out["phase"][0, 0] == pytest.approx(th["phase"][0, 0], abs=1e-8)
    assert out["peak_transmissibility"][0, 0] == pytest.approx(th["peak_transmissibility"][0, 0], rel=1e-9)


def test_r_quarter_small_friction_is_no_longer_seven_times_too_large():
    out = tile("base", 0.25, 0.01)
    th = theory.compute_tile("base", np.array([0.25]), np.array([0.01]), OUTPUTS)
    assert out["transmissibility"][0, 0] == pytest.approx(th["transmissibility"][0, 0], rel=1e-10)


def test_family_members_share_the_first_harmonic_but_not_the_peak():
    """The family itself, with the exact kernel: the symmetric member plus a free oscillation at the
    natural frequency (2n per forcing period) is again periodic, with the same first harmonic."""
    r, beta = 0.5, 0.1
    q0 = 1 / (1 - r * r)  # Den Hartog's member at U(1/2) = 0: x0 = V, phi = 0
    results = []
    for a in (0.0, 0.05):
        q, v = q0 + a, 0.0  # adds a cos(t): same sign pattern of the velocity for a small a
        acc = rec.new_accumulator()
        q1, v1, _, status, _ = ev.advance_period(q, v, -1, Point(1.0, r, beta, beta, 0.0, 0.0), 1e-13, 10**6, True, acc,
                                                 ev.NO_SAMPLES, ev.NO_SAMPLES, ev.NO_SAMPLES)
        assert status == 0 and acc[rec.ACC_STOPS] == 0
        assert abs(q1 - q) + abs(v1 - v) < 1e-12  # periodic
        results.append((np.hypot(acc[rec.ACC_IC], acc[rec.ACC_IS]) * r / np.pi,
                        max(acc[rec.ACC_XMAX], -acc[rec.ACC_XMIN])))
    assert results[1][0] == pytest.approx(results[0][0], rel=1e-12)  # first harmonic shared
    assert results[1][1] > results[0][1] + 0.04  # peaks differ


def test_with_damping_or_sticks_there_is_no_family():
    assert tile("base", 0.5, 0.1, DAMPED)["steady_state"][0, 0] == SteadyState.CONVERGED
    out = tile("base", 0.5, 0.6)  # beyond beta*(1/2) = 1/3: the orbit sticks
    assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["regime"][0, 0] == Regime.STICK_SLIP


# --- the whole plane ---------------------------------------------------------------------------------

PLANE_R = np.round(np.arange(1, 101) * 0.05, 12)  # 0.05 .. 5, contains r = 1, 1/2, 1/4, 1/10, 1/20
PLANE_BETA = np.round(np.arange(0, 31) * 0.05, 12)  # 0 .. 1.5


def plane(excitation, effects):
    arrays = event.compute_tile(excitation, PLANE_R, PLANE_BETA, OUTPUTS, effects)
    return cube.build_dataset(
        arrays, frequency_ratio=PLANE_R, force_ratio=PLANE_BETA, excitation=excitation, title="plane",
        history=provenance.history_line("test"),
        attrs=provenance.attributes(spec_text="", spec_path="plane.yaml", excitation=excitation, method="event",
                                    settings={**event.CATALOGUE.defaults, "effects": effects or {}}))


@pytest.mark.parametrize("effects", [None, STATIC, DAMPED], ids=["plain", "static", "damped"])
@pytest.mark.parametrize("excitation", ["base", "joined"])
@pytest.mark.slow
def test_a_coarse_plane_passes_every_consistency_rule(excitation, effects):
    ds = plane(excitation, effects)
    findings = {f.rule: f for f in consistency.check(ds)}
    assert not consistency.failed(findings.values()), [f for f in findings.values() if f.status == "failed"]
    assert findings["unsettled"].status == "ok"
    family = int((ds["steady_state"] == SteadyState.FAMILY).sum())
    if effects is None:
        assert findings["resonance"].status == "ok" and findings["theory"].status == "ok"
        assert family > 0  # r = 1/2, 1/4, 1/10, 1/20 below beta*
        r_family = ds["frequency_ratio"].values[(ds["steady_state"] == SteadyState.FAMILY).any("force_ratio").values]
        assert np.all(ties.subharmonic_order(r_family) > 0)
    else:
        assert family == 0
