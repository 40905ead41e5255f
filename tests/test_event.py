"""The exact event-driven method against independent truths (issue: exact stick-slip simulation)."""

import numpy as np
import pytest
from conftest import OUTPUTS

from friction_sweep.codes import MethodUsed, Regime, SteadyState
from friction_sweep.kernels import event as ev
from friction_sweep.kernels import measure as rec
from friction_sweep.kernels import steady
from friction_sweep.kernels.point import Point
from friction_sweep.methods import event, theory
from friction_sweep.theory import den_hartog as dh


def solve(excitation, r, beta, effects=None, **settings):
    return event.compute_tile(excitation, np.atleast_1d(r), np.atleast_1d(beta), OUTPUTS, effects, settings)


# --- continuous region: agreement with Den Hartog to 1e-8 ----------------------------------


@pytest.mark.parametrize("excitation", ["base", "joined", "force"])
def test_continuous_region_matches_theory(excitation):
    r = np.array([0.55, 0.7, 0.85, 0.95, 1.05, 1.2, 1.5, 2.0, 3.0, 5.0])
    beta = np.array([0.05, 0.2, 0.4, 0.6]) if excitation != "joined" else np.array([0.1, 0.4, 0.8, 1.2])
    th = theory.compute_tile(excitation, r, beta, OUTPUTS)
    ev_ = event.compute_tile(excitation, r, beta, OUTPUTS)
    cont = th["regime"] == Regime.CONTINUOUS
    # keep clear of the continuous limit, where the theory's tie is decided by rounding
    margin = (theory.forecast_regime(excitation, *np.meshgrid(r, beta * 1.01), dh.continuous_limit(r)[None, :])
              == Regime.CONTINUOUS)
    sel = cont & margin
    assert sel.sum() >= 20
    assert np.all(ev_["regime"][sel] == Regime.CONTINUOUS)
    assert np.all(ev_["stops_per_period"][sel] == 0)
    for name in ("peak_transmissibility", "transmissibility"):
        rel = np.abs(ev_[name][sel] / th[name][sel] - 1)
        assert rel.max() <= 1e-8, (name, rel.max())
    for name in ("phase", "peak_phase"):
        assert np.abs(ev_[name][sel] - th[name][sel]).max() <= 1e-6, name


def test_just_beyond_the_continuous_limit_the_mass_stops_twice():
    r = np.array([0.7, 0.9, 1.2, 2.0, 3.0])
    bstar = dh.continuous_limit(r)
    for j, rr in enumerate(r):
        below = solve("base", rr, bstar[j] * 0.97)
        beyond = solve("base", rr, bstar[j] * 1.03)
        assert below["regime"][0, 0] == Regime.CONTINUOUS
        assert beyond["regime"][0, 0] == Regime.STICK_SLIP
        assert beyond["stops_per_period"][0, 0] == 2


def test_stops_grow_as_r_goes_to_zero():
    # (r = 1/2 itself is a neutral, grazing case: see test_half_frequency_is_reported_honestly)
    r = np.array([0.05, 0.1, 0.2, 0.3, 0.45])
    out = event.compute_tile("base", r, np.array([0.3]), OUTPUTS)
    stops = out["stops_per_period"][0]
    assert np.all(out["regime"][0] == Regime.STICK_SLIP)
    assert np.all(np.diff(stops) <= 0), stops  # more stops at lower r
    assert stops[0] >= 8 and stops[-1] == 2
    assert np.all(stops % 2 == 0)  # the orbit is symmetric: stops come in pairs


def test_resonance_below_pi_over_4_is_unbounded_and_above_is_finite():
    out = event.compute_tile("base", np.array([1.0]), np.array([0.3, 0.7, 0.85, 1.2]), OUTPUTS)
    np.testing.assert_array_equal(out["regime"][:, 0], [Regime.UNBOUNDED, Regime.UNBOUNDED,
                                                        Regime.STICK_SLIP, Regime.STUCK])
    assert np.all(np.isnan(out["transmissibility"][:2, 0]))
    np.testing.assert_array_equal(out["steady_state"][:2, 0], [SteadyState.GROWING] * 2)
    assert np.isfinite(out["transmissibility"][2, 0])


def test_half_frequency_is_reported_honestly():
    """r = 1/2: two natural periods per forcing period make the free motion neutral on the
    stroboscopic map, so stick-free orbits form a family; the tool names it (`family`) and reports
    its first harmonic, which Den Hartog's closed form gives (U(1/2) = 0: x0 = V, phi = 0)."""
    out = solve("base", 0.5, 0.3)
    assert out["steady_state"][0, 0] == SteadyState.FAMILY and out["regime"][0, 0] == Regime.CONTINUOUS
    th = theory.compute_tile("base", np.array([0.5]), np.array([0.3]), OUTPUTS)
    assert out["transmissibility"][0, 0] == pytest.approx(th["transmissibility"][0, 0], rel=1e-12)
    linear = solve("base", 0.5, 0.0)  # without friction the orbit from rest is periodic at once
    assert linear["periods"][0, 0] == 2  # the period marched and the one measured
    assert linear["transmissibility"][0, 0] == pytest.approx(4 / 3, rel=1e-12)


# --- exact limits -----------------------------------------------------------------------------


@pytest.mark.parametrize("beta", [0.05, 0.3, 1.0])
def test_free_decay_loses_4_beta_per_natural_period(beta):
    acc = rec.new_accumulator()
    q, v, mode = 10.0, 0.0, -1
    r = 1.0  # the map's period is then the natural period 2 pi
    amplitudes = [q]
    for _ in range(200):
        q, v, mode, status, _ = ev.advance_period(q, v, mode, Point(0.0, r, beta, beta, 0.0, 0.0), 1e-13, 10**6,
                                                  False, acc, ev.NO_SAMPLES, ev.NO_SAMPLES, ev.NO_SAMPLES)
        assert status == ev.OK
        amplitudes.append(q)
        if mode == 0:
            break
    moving = [a for a in amplitudes if abs(a) > 3 * beta]
    drops = -np.diff(moving)
    np.testing.assert_allclose(drops, 4 * beta, rtol=1e-12)
    assert mode == 0 and abs(q) <= beta  # stopped inside the band |x| <= beta
    assert v == 0.0


def test_from_rest_with_beta_at_least_one_nothing_moves():
    out = event.compute_tile("base", np.array([0.3, 1.0, 4.0]), np.array([1.0, 1.5]), OUTPUTS)
    assert np.all(out["regime"] == Regime.STUCK)
    assert np.all(out["transmissibility"] == 0.0) and np.all(out["peak_transmissibility"] == 0.0)
    assert np.all(out["stuck_fraction"] == 1.0)


def test_joined_with_beta_at_least_r2_moves_with_the_wall():
    r = np.array([0.3, 0.5, 0.9])
    out = event.compute_tile("joined", r, np.array([0.81, 1.0]), OUTPUTS)
    assert np.all(out["regime"] == Regime.STUCK)
    assert np.all(out["transmissibility"] == 1.0)  # exactly: the relative motion is identically zero
    assert np.all(out["peak_transmissibility"] == 1.0)
    assert np.all(out["phase"] == 0.0)


def test_zero_friction_is_linear():
    r = np.array([0.3, 0.6, 1.4, 2.5])
    out = event.compute_tile("base", r, np.array([0.0]), OUTPUTS)
    np.testing.assert_allclose(out["transmissibility"][0], 1 / np.abs(1 - r**2), rtol=1e-9)


# --- stick-slip: an independent integrator ---------------------------------------------------------


@pytest.mark.parametrize("excitation,r,beta", [("base", 0.5, 0.5), ("base", 0.3, 0.3), ("joined", 0.95, 0.8),
                                               ("base", 1.0, 0.9)])
@pytest.mark.slow
def test_stick_slip_matches_independent_dop853(excitation, r, beta):
    from friction_sweep.bench.reference import measure

    A, c = (r * r, 1.0) if excitation == "joined" else (1.0, 0.0)
    out = solve(excitation, r, beta)
    assert out["regime"][0, 0] == Regime.STICK_SLIP
    # the reference marches from rest as long as the kernel's own march (shooting off) needs to settle
    periods = int(solve(excitation, r, beta, shoot_after=10**6)["periods"][0, 0]) + 3
    t_ref, p_ref = measure(A, r, beta, beta, periods, c)
    assert out["transmissibility"][0, 0] == pytest.approx(t_ref, rel=1e-7)
    assert out["peak_transmissibility"][0, 0] == pytest.approx(p_ref, rel=1e-6)


# --- steady-state machinery -----------------------------------------------------------------------


def test_shooting_and_marching_agree():
    r, beta = np.array([0.8, 1.3, 2.5]), np.array([0.1, 0.4])
    shot = event.compute_tile("base", r, beta, OUTPUTS)
    marched = event.compute_tile("base", r, beta, OUTPUTS, settings={"shoot_after": 10**6, "max_periods": 20000})
    ok = marched["steady_state"] == SteadyState.CONVERGED
    assert ok.sum() >= 4
    np.testing.assert_allclose(shot["transmissibility"][ok], marched["transmissibility"][ok], rtol=1e-8)
    assert np.all(shot["periods"] <= marched["periods"])


def test_small_friction_is_not_labelled_converged_early():
    """beta tiny: the transient barely decays; the answer must still be the steady state."""
    out = solve("base", 2.0, 1e-6)
    th = theory.compute_tile("base", np.array([2.0]), np.array([1e-6]), OUTPUTS)
    assert out["regime"][0, 0] == Regime.CONTINUOUS
    assert out["transmissibility"][0, 0] == pytest.approx(th["transmissibility"][0, 0], rel=1e-8)


def test_period_cap_is_reported_as_unsettled():
    out = solve("base", 2.0, 0.01, shoot_after=10**6, max_periods=5)
    assert out["regime"][0, 0] == Regime.UNSETTLED
    assert out["steady_state"][0, 0] == SteadyState.PERIOD_CAP
    assert np.isnan(out["transmissibility"][0, 0])


def test_work_budget_is_reported():
    out = solve("base", 0.05, 0.3, work_budget=50)
    assert out["regime"][0, 0] == Regime.UNSETTLED
    assert out["steady_state"][0, 0] == SteadyState.EVENT_BUDGET


# --- effects --------------------------------------------------------------------------------------


def test_absent_effects_are_bit_identical_to_plain():
    r, beta = np.array([0.3, 0.9, 2.0]), np.array([0.2, 0.6])
    plain = event.compute_tile("base", r, beta, OUTPUTS)
    neutral = event.compute_tile("base", r, beta, OUTPUTS, effects={"static_friction_ratio": 1.0})
    for name in plain:
        np.testing.assert_array_equal(plain[name], neutral[name])


def test_viscous_damping_alone_is_the_linear_viscous_oscillator():
    r = np.array([0.5, 1.0, 1.5, 3.0])
    zeta = 0.1
    out = event.compute_tile("force", r, np.array([0.0]), OUTPUTS, effects={"viscous_damping": zeta})
    expected = 1 / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
    np.testing.assert_allclose(out["transmissibility"][0], expected, rtol=1e-8)
    lag = np.degrees(np.arctan2(2 * zeta * r, 1 - r**2))
    np.testing.assert_allclose(out["phase"][0], lag, atol=1e-6)


def test_static_friction_above_kinetic_keeps_the_mass_stuck_longer():
    r, beta = np.array([0.4]), np.array([0.4])
    plain = event.compute_tile("base", r, beta, OUTPUTS)
    sticky = event.compute_tile("base", r, beta, OUTPUTS, effects={"static_friction_ratio": 1.5})
    assert sticky["stuck_fraction"][0, 0] > plain["stuck_fraction"][0, 0]
    # static friction 1.5 x 0.7 >= 1: once stopped... from rest it never starts
    never = event.compute_tile("base", r, np.array([0.7]), OUTPUTS, effects={"static_friction_ratio": 1.5})
    assert never["regime"][0, 0] == Regime.STUCK


# --- auto -----------------------------------------------------------------------------------------


def test_auto_uses_theory_only_inside_the_margin_and_agrees_with_event():
    from friction_sweep.methods import auto

    r = np.array([0.3, 0.7, 1.0, 1.5, 3.0])
    beta = np.array([0.1, 0.5, 0.8])
    a = auto.compute_tile("base", r, beta, OUTPUTS)
    e = event.compute_tile("base", r, beta, OUTPUTS)
    used = a["method_used"]
    th_forecast = theory.compute_tile("base", r, beta, OUTPUTS)["regime"]
    assert np.all(th_forecast[used == MethodUsed.THEORY] == Regime.CONTINUOUS)
    assert np.all(used[:, 2] == MethodUsed.EVENT)  # r = 1 is always simulated
    assert (used == MethodUsed.THEORY).sum() >= 5 and (used == MethodUsed.EVENT).sum() >= 5
    np.testing.assert_array_equal(a["regime"], e["regime"])
    ok = np.isfinite(e["transmissibility"])
    np.testing.assert_allclose(a["transmissibility"][ok], e["transmissibility"][ok], rtol=1e-8)
    assert np.all(a["steady_state"][used == MethodUsed.THEORY] == SteadyState.NOT_SIMULATED)


# --- time histories --------------------------------------------------------------------------------


def test_time_histories_are_the_measured_orbits():
    pts = [[2.0, 0.3], [0.3, 0.5], [0.95, 0.8]]
    for excitation in ("base", "joined"):
        h = event.time_histories(excitation, pts, 512)
        grid = [event.compute_tile(excitation, np.array([r]), np.array([b]), OUTPUTS) for r, b in pts]
        for i, g in enumerate(grid):
            m = int(h["history_orbit_period"][i]) * 512
            x = h["history_displacement"][i, :m]
            t = h["history_time"][i, :m] * 2 * np.pi  # forcing phase r t
            a1, b1 = 2 * np.mean(x * np.cos(t)), 2 * np.mean(x * np.sin(t))
            assert np.hypot(a1, b1) == pytest.approx(g["transmissibility"][0, 0], rel=1e-4)
            assert np.max(np.abs(x)) <= g["peak_transmissibility"][0, 0] * (1 + 1e-12)
            assert np.max(np.abs(x)) == pytest.approx(g["peak_transmissibility"][0, 0], rel=1e-3)
            assert h["history_regime"][i] == g["regime"][0, 0]
            # the excitation is cos(r t) with its maximum at the section
            assert h["history_excitation"][i, 0] == 1.0


# --- rk4 as a sweep method ---------------------------------------------------------------------------


def test_rk4_method_converges_to_event_with_order_four():
    from friction_sweep.methods import rk4

    r, beta = np.array([0.8, 2.0]), np.array([0.2])
    exact = event.compute_tile("base", r, beta, OUTPUTS)["transmissibility"]
    errs = []
    for n in (32, 64, 128):
        t = rk4.compute_tile("base", r, beta, OUTPUTS, settings={"steps_per_period": n})["transmissibility"]
        errs.append(np.max(np.abs(t / exact - 1)))
    slopes = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((slopes > 3.5) & (slopes < 4.6)), (errs, slopes)
    stick = rk4.compute_tile("base", np.array([0.3]), np.array([0.3]), OUTPUTS, settings={"steps_per_period": 512})
    ev_ = event.compute_tile("base", np.array([0.3]), np.array([0.3]), OUTPUTS)
    assert stick["regime"][0, 0] == Regime.STICK_SLIP and stick["stops_per_period"][0, 0] == 2
    assert stick["transmissibility"][0, 0] == pytest.approx(ev_["transmissibility"][0, 0], rel=1e-7)


def test_without_any_dissipation_the_steady_state_is_the_forced_response():
    """beta = 0 and no damping: a transient from rest never decays (at r = 3.5 the orbit from rest
    closes only after 7 periods, with a peak far above the forced one); the tool reports the forced
    steady state, the limit of vanishing damping: peak and first harmonic 1/|1 - r^2|, period 1."""
    r = np.array([0.3, 1.7, 3.5])
    for excitation in ("base", "joined"):
        out = event.compute_tile(excitation, r, np.array([0.0]), OUTPUTS)
        linear = 1 / np.abs(1 - r**2)
        np.testing.assert_allclose(out["transmissibility"][0], linear, rtol=1e-12)
        np.testing.assert_allclose(out["peak_transmissibility"][0], linear, rtol=1e-12)
        assert np.all(out["orbit_period"][0] == 1)
    assert solve("base", 1.0, 0.0)["regime"][0, 0] == Regime.UNBOUNDED


# --- kernel internals against independent truths -------------------------------------------------


@pytest.mark.parametrize("excitation, r, beta, zeta", [("base", 1.5, 0.3, 0.0), ("joined", 0.7, 0.3, 0.0),
                                                       ("base", 0.8, 0.2, 0.05), ("force", 3.0, 0.1, 0.0)])
def test_monodromy_matrix_is_the_derivative_of_the_period_map(excitation, r, beta, zeta):
    """The event kernel's Jacobian (flow times saltation at each reversal) against central differences
    of the period map itself, on and off the steady orbit."""
    A, c, bk, bs, z = (float(a[0]) for a in event.point_parameters(excitation, np.array([r]), np.array([beta]),
                                                                   {"viscous_damping": zeta}))
    out = event.solve_flat(excitation, np.array([r]), np.array([beta]), {"viscous_damping": zeta})[0]
    none = np.empty(0)

    def period(q, v):
        acc = rec.new_accumulator()
        mode = 1 if v > 0 else -1
        q1, v1, _, st, _ = ev.advance_period(q, v, mode, Point(A, r, bk, bs, z, c), 1e-12, 10**6, False, acc, none,
                                             none, none)
        assert st == 0 and acc[rec.ACC_STOPS] == 0
        return np.array([q1, v1]), acc

    q0, v0 = out[steady.OUT_END_Q], out[steady.OUT_END_V]
    for q, v in [(q0, v0), (q0 * 1.05, v0 + 0.02 * abs(q0))]:
        _, acc = period(q, v)
        assert acc[rec.ACC_JAC_OK] == 1.0
        jac = acc[rec.ACC_JAC:rec.ACC_JAC + 4].reshape(2, 2)
        h = 1e-6 * max(abs(q), abs(v), 1.0)
        fd = np.column_stack([(period(q + h, v)[0] - period(q - h, v)[0]) / (2 * h),
                              (period(q, v + h)[0] - period(q, v - h)[0]) / (2 * h)])
        np.testing.assert_allclose(jac, fd, rtol=0, atol=1e-7 * np.abs(fd).max())


@pytest.mark.parametrize("r, beta", [(0.8403, 0.6538), (1.2147, 1.3462), (0.5492, 0.0385), (1.5, 0.5), (3.0, 0.2),
                                     (0.3, 0.05), (1.02, 0.9)])
def test_joined_extremes_against_a_dense_replay(r, beta):
    """Peaks of x = z + cos(r t) (sampled per slip piece, refined by Newton) against 200,000 samples of
    the replayed orbit: never below the densest sample, above it by at most the sampling's reach, at
    the same phase. The first three peak just after the period's start, across the section."""
    g = event.compute_tile("joined", np.array([r]), np.array([beta]), OUTPUTS)
    n = 200_000
    h = event.time_histories("joined", [(r, beta)], n)
    m = int(h["history_orbit_period"][0]) * n
    x = h["history_displacement"][0, :m]
    dense = np.abs(x).max()
    peak = g["peak_transmissibility"][0, 0]
    assert dense <= peak * (1 + 1e-13)
    assert peak - dense <= 1e-8 * peak  # (half a sample spacing)^2 |x''| / 2
    i = np.argmax(x)  # the peak phase is that of the maximum
    lag = (h["history_time"][0, i] * 360 + 90) % 360 - 90
    assert abs((g["peak_phase"][0, 0] - lag + 180) % 360 - 180) <= 2 * 360 / n


# --- shooting through sticks, and from Den Hartog's orbit ------------------------------------------


def _period(p, q, v):
    acc = rec.new_accumulator()
    from friction_sweep.kernels.period_map import map_k

    q1, v1, st, _ = map_k(q, v, 1, p, event.kernel_settings(), 10**7, False, acc, None)
    assert st == 0
    return np.array([q1, v1]), acc


@pytest.mark.parametrize("A, r, bk, bs, c", [
    (1.0, 0.3, 0.5, 0.5, 0.0),  # two sticks, stuck at the section
    (1.0, 0.6, 0.7, 0.7, 0.0),  # two sticks, moving at the section
    (1.0, 0.2, 0.3, 0.3, 0.0),  # four stops
    (1.0, 0.45, 0.3, 0.45, 0.0),  # static friction: the release saltation is not zero
    (0.64, 0.8, 0.55, 0.55, 1.0),  # joined
])
def test_monodromy_through_sticks_is_the_derivative_of_the_period_map(A, r, bk, bs, c):
    """The exact Jacobian across sticks (saltation into the stick, release time moving with the stop)
    against central differences of the period map, on the orbit the march reaches."""
    p = Point(A, r, bk, bs, 0.0, c)
    x = np.zeros(2)
    for _ in range(300):
        x, _ = _period(p, *x)
    _, acc = _period(p, *x)
    assert acc[rec.ACC_STUCK] > 0 and acc[rec.ACC_JAC_OK] == 1.0
    exact = acc[rec.ACC_JAC:rec.ACC_JAC + 4].reshape(2, 2)
    h = 1e-6 * max(1.0, np.hypot(*x))
    fd = np.column_stack([(_period(p, *(x + d))[0] - _period(p, *(x - d))[0]) / (2 * h)
                          for d in (np.array([h, 0.0]), np.array([0.0, h]))])
    atol = np.full((2, 2), 1e-6 * max(1.0, np.abs(exact).max()))
    if x[1] == 0.0:
        atol[:, 1] = 10 * h  # stuck at the section: a push of dv slides dv^2/(2|a|), a kink of size O(h)
    assert np.all(np.abs(exact - fd) <= atol), (exact, fd)
    if bs == bk:
        assert abs(np.linalg.det(exact)) < 1e-12  # a stick forgets the velocity: rank 1


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_den_hartogs_section_state_is_the_simulated_orbit(excitation):
    """theory.den_hartog.section_state, the continuous orbit at the force's maximum, is where the
    simulation's orbit crosses the section (found here by the march alone, shooting off)."""
    r = np.array([0.8, 1.5, 3.0])
    beta = np.array([0.2, 0.3, 0.4]) * (r * r if excitation == "joined" else 1.0)
    A, _, bk, _, _ = event.point_parameters(excitation, r, beta)
    q, v = dh.section_state(r, bk / A)
    marched = event.solve_flat(excitation, r, beta, shoot_after=10**6, max_periods=20_000, steady_tol=1e-13)
    assert np.all(marched[:, steady.OUT_REGIME] == Regime.CONTINUOUS)
    np.testing.assert_allclose(A * q, marched[:, steady.OUT_END_Q], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(A * v, marched[:, steady.OUT_END_V], rtol=1e-9, atol=1e-12)


def test_the_guess_changes_the_cost_not_the_answer():
    """Where the steady state is unique the start does not matter: from Den Hartog's orbit (shoot_after
    0, the default) and from the march from rest (shoot_after 1) the same regimes, stops and values,
    continuous and stick-slip points alike, and the guess settles continuous points in one period or two."""
    r = np.array([0.3, 0.55, 0.8, 0.97, 1.2, 2.0, 4.0])
    beta = np.array([0.05, 0.2, 0.4, 0.7, 1.1])
    for excitation in ("base", "joined"):
        guess = event.compute_tile(excitation, r, beta, OUTPUTS)
        march = event.compute_tile(excitation, r, beta, OUTPUTS, settings={"shoot_after": 1})
        for name in ("regime", "stops_per_period", "steady_state"):
            np.testing.assert_array_equal(guess[name], march[name], err_msg=name)
        np.testing.assert_allclose(guess["transmissibility"], march["transmissibility"], rtol=1e-11, atol=1e-13)
        moving = guess["regime"] == Regime.CONTINUOUS
        # one measured period settles nearly every continuous point; the odd one (where the closed
        # form's own rounding is above the acceptance) takes a Newton step more
        assert moving.sum() >= 8 and np.all(guess["periods"][moving] <= 2)
        assert np.mean(guess["periods"][moving] == 1) >= 0.9
        assert np.all(guess["periods"] <= march["periods"] + 1)


def test_a_slip_from_rest_that_cannot_move_the_mass_is_a_stick():
    """Joined, r = 0.2, beta = 0.02, at rest at q = A - bs where the force peaks: the force exceeds the
    band by less than rounding, so the slip stops 1e-14 later without moving. The kernel used to find
    that stop again and again and spend the whole work budget in one period."""
    A = 0.2 * 0.2
    out = solve("joined", 0.2, 0.02, initial_displacement=A - 0.02, shoot_after=10**6, work_budget=100_000)
    assert out["steady_state"][0, 0] == SteadyState.CONVERGED and out["regime"][0, 0] == Regime.STICK_SLIP
