"""Den Hartog's theory against independent truths: limits, reference values, linear case, identities."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from friction_sweep import ties
from friction_sweep.codes import Regime
from friction_sweep.methods import theory
from friction_sweep.theory import den_hartog as dh

OUTPUTS = ("transmissibility", "phase", "regime")


def _printed_u(r):
    """U as printed, corrected Eq. (15): sin(pi/r) / (r (1 + cos(pi/r)))."""
    return np.sin(np.pi / r) / (r * (1.0 + np.cos(np.pi / r)))


# --- reference values of DESIGN.md §2 --------------------------------------------------------


@pytest.mark.parametrize("eps", [1e-3, 1e-5, 1e-7])
def test_minus_v_over_u_tends_to_pi_over_4_at_resonance(eps):
    for r in (1.0 - eps, 1.0 + eps):
        ratio = -dh.response_function(r) / dh.damping_function(r)
        # -V/U = pi/4 + O(1 - r): the error must shrink with eps
        assert ratio == pytest.approx(np.pi / 4, abs=2.0 * eps)


def test_continuous_limit_at_resonance_is_pi_over_4():
    assert float(dh.continuous_limit(1.0)) == pytest.approx(np.pi / 4, rel=1e-14)


def test_continuous_limit_tends_to_two_over_sqrt_4_plus_pi2():
    target = 2.0 / np.sqrt(4.0 + np.pi**2)
    errs = [abs(float(dh.continuous_limit(r)) - target) for r in (1e2, 1e3, 1e4)]
    assert errs[-1] < 1e-8
    # the approach is O(1/r^2): each decade of r cuts the error by about 100
    assert errs[0] / errs[1] == pytest.approx(100.0, rel=0.05)


def test_continuous_limit_at_half_is_one_third():
    assert float(dh.damping_function(0.5)) == pytest.approx(0.0, abs=1e-15)
    assert float(dh.continuous_limit(0.5)) == pytest.approx(1.0 / 3.0, rel=1e-13)


def test_maximum_of_continuous_limit():
    res = minimize_scalar(
        lambda r: -float(dh.continuous_limit(r)), bounds=(0.75, 0.95), method="bounded",
        options={"xatol": 1e-10},
    )
    bmax, rmax = -res.fun, res.x
    # the paper prints 0.8265 at r = 0.8490 (Eq. 26); DESIGN.md 0.82649 at 0.84906
    assert bmax == pytest.approx(0.8265, abs=1e-4)
    assert rmax == pytest.approx(0.8490, abs=3e-4)
    # Independent truth: at the displacement maximum the mass only slides back if the spring-minus-
    # force exceeds friction, x0 - cos(phi) > b, i.e. x0 r^2 > b: so S >= 1, and near this r the
    # sup is that limit, S = 1. beta* then has the closed form |V| / sqrt(1/r^4 + U^2).
    exact = minimize_scalar(
        lambda r: -abs(1 / (1 - r * r)) / np.hypot(1 / r**2, np.tan(np.pi / (2 * r)) / r),
        bounds=(0.75, 0.95), method="bounded", options={"xatol": 1e-12},
    )
    assert bmax == pytest.approx(-exact.fun, rel=1e-11)
    assert rmax == pytest.approx(exact.x, abs=1e-5)


# --- identities and forms ----------------------------------------------------------------------


def test_damping_function_matches_printed_form_away_from_poles():
    r = np.array([0.21, 0.3, 0.4, 0.45, 0.6, 0.7, 0.9, 0.99, 1.01, 1.3, 2.0, 3.7, 10.0])
    np.testing.assert_allclose(dh.damping_function(r), _printed_u(r), rtol=1e-12)


def test_s_function_limits():
    # S = 1 at resonance (paper, before Eq. 15); S >= 1 everywhere (its tau -> 0 limit)
    assert dh.s_function(1.0)[0] == pytest.approx(1.0, abs=1e-12)
    s = dh.s_function(np.linspace(0.3, 5.0, 40))
    assert np.all(s >= 1.0)


def test_s_function_against_brute_force():
    for r in (0.35, 0.62, 1.7, 3.3):
        tau = np.linspace(0, np.pi / r, 2_000_001)[1:-1]
        u = dh.damping_function(r)
        brute = np.max((r * np.sin(tau) + u * r * r * (np.cos(r * tau) - np.cos(tau))) / np.sin(r * tau))
        assert dh.s_function(r)[0] == pytest.approx(max(brute, 1.0), rel=1e-9)


def test_waveform_starts_at_x0_and_is_half_wave_antisymmetric():
    for r, b in ((0.8, 0.3), (1.7, 0.5), (3.0, 0.2)):
        x0 = dh.amplitude(r, b)
        assert dh.waveform(r, b, 0.0) == pytest.approx(x0, rel=1e-14)
        # q(pi/r) = -x0 is the boundary condition (3b) that fixes x0 and phi
        assert dh.waveform(r, b, np.pi / r) == pytest.approx(-x0, rel=1e-12)
        assert dh.waveform_velocity(r, b, np.pi / r) == pytest.approx(0.0, abs=1e-12 * x0)


def test_waveform_solves_the_equation_of_motion():
    """Integrate q'' + q - b = cos(r t + phi) (sliding with q' < 0) from (x0, 0) and compare."""
    for r, b in ((0.8, 0.3), (1.3, 0.6), (2.5, 0.4)):
        x0, phi = float(dh.amplitude(r, b)), float(dh.phase(r, b))
        sol = solve_ivp(lambda t, y: [y[1], np.cos(r * t + phi) - y[0] + b], (0, np.pi / r), [x0, 0.0],
                        method="DOP853", rtol=1e-12, atol=1e-13, dense_output=True)
        tau = np.linspace(0, np.pi / r, 50)
        np.testing.assert_allclose(dh.waveform(r, b, tau), sol.sol(tau)[0], atol=1e-9 * x0)
        np.testing.assert_allclose(dh.waveform_velocity(r, b, tau), sol.sol(tau)[1], atol=1e-9 * x0)


def test_waveform_is_stable_next_to_resonance():
    # nothing divides by 1 - r^2: the waveform scaled by |1 - r| is smooth through r -> 1
    tau = np.linspace(0, np.pi, 7)
    scaled = [np.abs(1 - r) * dh.waveform(r, 0.3, tau * (1 / r)) for r in (1 - 1e-6, 1 - 1e-9, 1 - 1e-12)]
    np.testing.assert_allclose(scaled[1], scaled[2], atol=1e-8)
    np.testing.assert_allclose(scaled[0], scaled[2], atol=1e-5)


def test_first_harmonic_quadrature_converged():
    for r, b in ((0.6, 0.2), (1.05, 0.5), (4.0, 0.5)):
        a_n, b_n = dh.first_harmonic(r, b)
        a_2n, b_2n = dh.first_harmonic(r, b, nodes=4 * dh.gauss_legendre_nodes(r))
        assert float(a_n) == pytest.approx(float(a_2n), rel=1e-13, abs=1e-15)
        assert float(b_n) == pytest.approx(float(b_2n), rel=1e-13, abs=1e-15)


def test_first_harmonic_against_sampled_projection():
    """Project the full-period waveform onto cos/sin(r t) with a plain trapezoid sum (spectrally
    accurate for periodic integrands): an independent route to the same coefficients."""
    for r, b in ((0.7, 0.4), (2.2, 0.5)):
        n = 4096
        t = np.arange(n) * (2 * np.pi / r) / n
        half = np.pi / r
        q = np.where(t < half, dh.waveform(r, b, np.minimum(t, half)), -dh.waveform(r, b, np.maximum(t - half, 0)))
        a1 = 2 * np.mean(q * np.cos(r * t))
        b1 = 2 * np.mean(q * np.sin(r * t))
        fa, fb = dh.first_harmonic(r, b)
        assert float(fa) == pytest.approx(a1, rel=1e-10)
        assert float(fb) == pytest.approx(b1, rel=1e-10)


# --- the method on the grid -----------------------------------------------------------------------

R = np.array([0.1, 0.3, 0.55, 0.8, 0.95, 1.05, 1.2, 1.5, 2.0, 3.0, 5.0])


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_zero_friction_is_the_linear_oscillator(excitation):
    out = theory.compute_tile(excitation, R, np.array([0.0]), OUTPUTS)
    linear = 1.0 / np.abs(1.0 - R**2)
    np.testing.assert_allclose(out["transmissibility"][0], linear, rtol=1e-13)
    np.testing.assert_allclose(out["peak_transmissibility"][0], linear, rtol=1e-12)
    np.testing.assert_allclose(out["phase"][0], np.where(R < 1, 0.0, 180.0), atol=1e-9)
    np.testing.assert_allclose(out["peak_phase"][0], np.where(R < 1, 0.0, 180.0), atol=1e-6)
    assert np.all(out["regime"] == Regime.CONTINUOUS)


def test_base_equals_force_with_f0_equal_ky():
    beta = np.array([0.0, 0.1, 0.3, 0.5, 0.7, 1.0, 1.3])
    f = theory.compute_tile("force", R, beta, OUTPUTS)
    b = theory.compute_tile("base", R, beta, OUTPUTS)
    for name in f:
        np.testing.assert_array_equal(f[name], b[name])


def test_joined_relative_motion_equals_force_with_f0_equal_kyr2():
    """z/Y of the joined scene at beta equals r^2 times x/(F0/k) of the force scene at beta/r^2."""
    beta = np.array([0.05, 0.2, 0.5, 0.9])
    joined = theory.compute_tile("joined", R, beta, OUTPUTS)
    for j, r in enumerate(R):
        force = theory.compute_tile("force", np.array([r]), beta / r**2, OUTPUTS)
        z = joined["relative_peak_amplitude"][:, j]
        expected = r * r * force["peak_transmissibility"][:, 0]
        np.testing.assert_allclose(z, expected, rtol=1e-13)
        np.testing.assert_allclose(joined["relative_peak_phase"][:, j], force["peak_phase"][:, 0], atol=1e-12)
        np.testing.assert_array_equal(joined["regime"][:, j], force["regime"][:, 0])
    # and the continuous limits in the scene conventions: r^2 beta*(r)
    np.testing.assert_allclose(joined["continuous_limit"], R**2 * dh.continuous_limit(R), rtol=1e-15)


def test_joined_absolute_amplitude_relation_eq36():
    """Eq. (36): x0 = z0/r^2 is the absolute displacement at the z maximum, x(0) = z0 + Y cos(phi_yz)."""
    r, beta = np.array([1.2, 2.0, 3.0]), np.array([0.3])
    out = theory.compute_tile("joined", r, beta, OUTPUTS)
    z0 = out["relative_peak_amplitude"][0]
    phi = np.radians(out["relative_peak_phase"][0])
    np.testing.assert_allclose(z0 + np.cos(phi), z0 / r**2, rtol=1e-12)
    # the peak of |x| over the period is at least its value at tau = 0
    assert np.all(out["peak_transmissibility"][0] >= np.abs(z0 / r**2) * (1 - 1e-14))


def test_joined_peak_phase_is_difference_of_eq44():
    out = theory.compute_tile("joined", np.array([1.5, 2.5]), np.array([0.4, 0.8]), OUTPUTS)
    np.testing.assert_allclose(out["peak_phase"], out["relative_peak_phase"] - out["peak_phase_xz"], atol=1e-9)
    # Fig. 15 of the paper: phi_xz lies in [0, 180] and phi_yz > phi_xz
    assert np.all((out["peak_phase_xz"] >= 0) & (out["peak_phase_xz"] <= 180))
    assert np.all(out["relative_peak_phase"] > out["peak_phase_xz"])


def test_joined_peak_against_dense_sampling():
    r, beta = np.array([0.9, 1.45, 2.5]), np.array([0.2, 0.6])
    out = theory.compute_tile("joined", r, beta, OUTPUTS)
    for i, bb in enumerate(beta):
        for j, rr in enumerate(r):
            if out["regime"][i, j] != Regime.CONTINUOUS:
                continue
            b = bb / rr**2
            phi = float(dh.phase(rr, b))
            tau = np.linspace(0, np.pi / rr, 400_001)
            x = rr**2 * dh.waveform(rr, b, tau) + np.cos(rr * tau + phi)
            assert out["peak_transmissibility"][i, j] == pytest.approx(np.max(np.abs(x)), rel=1e-10)


def test_joined_inversion_between_1p4_and_1p55():
    """Curves of |X|/|Y| for different force ratios cross inside 1.4 < r < 1.55 (paper Fig. 14b)."""
    r = np.linspace(1.3, 1.7, 401)
    beta = np.array([0.2, 0.4, 0.6])
    out = theory.compute_tile("joined", r, beta, ("transmissibility",))
    peak = out["peak_transmissibility"]
    for lo, hi in ((0, 1), (1, 2), (0, 2)):
        diff = peak[hi] - peak[lo]
        crossings = r[1:][np.sign(diff[1:]) != np.sign(diff[:-1])]
        assert crossings.size >= 1
        assert np.all((crossings > 1.4) & (crossings < 1.55)), crossings


# --- regimes and thresholds -----------------------------------------------------------------------


def test_no_motion_thresholds_and_ties():
    r = np.array([0.5, 1.0, 2.0])
    base = theory.compute_tile("base", r, np.array([0.999, 1.0, 1.5]), OUTPUTS)
    assert np.all(base["regime"][1:] == Regime.STUCK)  # beta >= 1: stuck, tie included
    assert np.all(base["regime"][0] != Regime.STUCK)
    assert np.all(base["transmissibility"][1:] == 0.0)
    joined = theory.compute_tile("joined", np.array([0.5]), np.array([0.2499, 0.25, 0.3]), OUTPUTS)
    assert joined["regime"][0, 0] != Regime.STUCK
    assert np.all(joined["regime"][1:, 0] == Regime.STUCK)  # beta >= r^2: rides with the wall
    assert np.all(joined["transmissibility"][1:, 0] == 1.0)
    assert np.all(joined["phase"][1:, 0] == 0.0)


def test_continuous_limit_tie_is_continuous():
    r = np.array([0.5])  # beta*(0.5) = 1/3 exactly (to rounding)
    bstar = float(dh.continuous_limit(r)[0])
    out = theory.compute_tile("base", r, np.array([bstar, np.nextafter(bstar, 1)]), OUTPUTS)
    assert out["regime"][0, 0] == Regime.CONTINUOUS  # the velocity only grazes zero
    assert out["regime"][1, 0] == Regime.STICK_SLIP
    assert np.isfinite(out["transmissibility"][0, 0]) and np.isnan(out["transmissibility"][1, 0])


def test_resonance_unbounded_up_to_pi_over_4():
    # pi/4 (1 + 1e-12) is the tie's edge (friction_sweep.ties); just past it the peak is finite
    beta = np.array([0.0, 0.5, np.nextafter(np.pi / 4, 0), np.pi / 4, np.nextafter(np.pi / 4, 1),
                     np.pi / 4 * (1 + 2 * ties.TIE_RTOL), 0.9])
    out = theory.compute_tile("base", np.array([1.0]), beta, OUTPUTS)
    np.testing.assert_array_equal(
        out["regime"][:, 0],
        [Regime.UNBOUNDED] * 5 + [Regime.STICK_SLIP] * 2,
    )
    # the tie: at b = pi/4 the continuous amplitude still diverges as r -> 1 (like 1/sqrt|1 - r|)
    r = 1 - np.array([1e-4, 1e-6, 1e-8])
    x0 = dh.amplitude(r, np.pi / 4)
    assert np.all(np.diff(x0) > 0) and x0[-1] > 10 * x0[0]
    assert np.all(np.isnan(out["transmissibility"][:, 0]))
    # next to resonance the steady state is finite, large, and grows like 1/|1 - r|
    near = theory.compute_tile("base", np.array([1 - 1e-9, 1 + 1e-9]), np.array([0.5]), OUTPUTS)
    assert np.all(near["regime"] == Regime.CONTINUOUS)
    amp = near["peak_transmissibility"][0] * 1e-9
    np.testing.assert_allclose(amp, 0.5 * np.sqrt(1 - (4 * 0.5 / np.pi) ** 2), rtol=1e-6)


def test_singular_points_of_u_have_no_continuous_motion_with_friction():
    for r in (1 / 3, 1 / 5):
        out = theory.compute_tile("base", np.array([r]), np.array([0.0, 0.01]), OUTPUTS)
        assert out["regime"][0, 0] == Regime.CONTINUOUS  # linear
        assert out["regime"][1, 0] == Regime.STICK_SLIP
        assert out["continuous_limit"][0] < 1e-6


def test_outputs_outside_validity_are_nan_never_numbers():
    r = np.linspace(0.05, 5.0, 100)
    beta = np.linspace(0.0, 1.5, 31)
    for excitation in ("base", "joined"):
        out = theory.compute_tile(excitation, r, beta, OUTPUTS)
        code = out["regime"]
        for name in ("transmissibility", "phase", "peak_transmissibility", "peak_phase"):
            v = out[name]
            assert np.all(np.isnan(v[(code == Regime.STICK_SLIP) | (code == Regime.UNBOUNDED)]))
            assert np.all(np.isfinite(v[code == Regime.CONTINUOUS]))
        assert np.all(np.isfinite(out["transmissibility"][code == Regime.STUCK]))


def test_regime_map_is_ordered_in_beta():
    """For fixed r, raising friction never turns stuck/stick-slip motion back into continuous motion."""
    r = np.linspace(0.05, 5.0, 200)
    beta = np.linspace(0.0, 1.5, 151)
    for excitation in ("base", "joined"):
        code = theory.compute_tile(excitation, r, beta, ("regime",))["regime"]
        cont = code == Regime.CONTINUOUS
        # once not continuous (going up in beta) never continuous again
        first_break = np.argmin(cont, axis=0)
        for j in range(r.size):
            if not cont[:, j].all():
                assert not cont[first_break[j]:, j].any()
