"""The Jenkins contact's exact monodromy matrix (issue 19) against central differences of the period map taken
here, its Floquet multiplier, and Newton with it against Newton with differences."""

import numpy as np
import pytest

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import jenkins as jk
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady
from friction_sweep.kernels.point import JenkinsPoint
from friction_sweep.methods import event

#: (excitation, r, beta, kappa, effects, regime, section): orbits whose period map is smooth at the section;
#: section: the slider's state there (1/-1 slipping, 2 stuck and held)
ORBITS = [
    ("base", 0.5, 0.5, 100.0, {}, Regime.STICK_SLIP, 1),
    ("base", 0.3, 0.6, 100.0, {}, Regime.STICK_SLIP, 2),  # held at the section: all three columns
    ("base", 0.8, 0.9, 30.0, {}, Regime.STICK_SLIP, 1),
    ("force", 0.5, 0.6, 100.0, {}, Regime.STICK_SLIP, 1),
    ("joined", 0.6, 0.3, 100.0, {}, Regime.STICK_SLIP, 1),  # c = 1
    ("base", 0.5, 0.5, 100.0, {"viscous_damping": 0.05}, Regime.STICK_SLIP, 1),
    ("base", 0.5, 0.5, 100.0, {"static_friction_ratio": 1.5}, Regime.STICK_SLIP, 1),  # period 3, jumps
    ("base", 1.5, 0.3, 100.0, {}, Regime.CONTINUOUS, 1),
    ("base", 1.3, 0.4, 100.0, {"static_friction_ratio": 1.5}, Regime.CONTINUOUS, 1),
    ("joined", 1.2, 0.5, 100.0, {}, Regime.CONTINUOUS, 1),
]
IDS = [f"{e}-r{r}-b{b}-k{k:g}-{'-'.join(f'{n}{v}' for n, v in f.items())}" for e, r, b, k, f, *_ in ORBITS]


NONE = np.empty(0)  # no samples


def orbit_start(excitation, r, beta, kappa, effects):
    """The converged orbit's state at the section (q, v, w), its mode, period k and the point's parameters."""
    row = event.solve_flat(excitation, np.array([r]), np.array([beta]), {"contact_stiffness": kappa, **effects},
                           stability=1)[0]
    assert row[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    A, c, bk, bs, zeta = (float(x[0]) for x in event.point_parameters(excitation, [r], [beta], effects))
    x0 = np.array([row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W]])
    return row, x0, int(row[steady.OUT_END_MODE]), int(row[steady.OUT_ORBIT_PERIOD]), \
        JenkinsPoint(A, r, bk, bs, zeta, c, kappa)


def period_map(x, mode, p, periods=1):
    """P^periods(x) by the kernel's period march, and the product of its periods' monodromy matrices (None
    where one is not valid)."""
    acc = jk.new_jenkins_accumulator()
    q, v, w, anchor = x[0], x[1], x[2], np.nan
    m = np.eye(3)
    for _ in range(periods):
        q, v, w, mode, anchor, st, _ = jk.advance_period_jenkins(q, v, w, mode, anchor, p, 1e-12, 10**7, False, acc,
                                                                 NONE, NONE, NONE)
        assert st == 0
        valid = acc[jk.JACC_JAC_OK] == 1.0
        m = acc[jk.JACC_JAC:jk.JACC_JAC + 9].reshape(3, 3) @ m if valid and m is not None else None
    return np.array([q, v, w]), mode, m


def central_differences(x0, mode, p, periods=1, rel=1e-6):
    """d P^periods / d(q, v, w) by central differences, each perturbation one coordinate (a perturbation of w
    where the slider slips moves nothing: the period begins by slaving it to q)."""
    h = rel * max(np.hypot(x0[0], x0[1]), p.A)
    jac = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        xp, mp, _ = period_map(x0 + e, mode, p, periods)
        xm, mm, _ = period_map(x0 - e, mode, p, periods)
        assert mp == mm  # the perturbation stays on one piece of the map
        jac[:, j] = (xp - xm) / (2 * h)
    return jac


@pytest.mark.parametrize(("excitation", "r", "beta", "kappa", "effects", "regime", "section"), ORBITS, ids=IDS)
def test_exact_monodromy_matches_central_differences(excitation, r, beta, kappa, effects, regime, section):
    """The matrix built along one period (piece flows and saltations at every velocity zero and band exit)
    equals central differences of that period's map from the orbit's section state, to 1e-6 relative."""
    row, x0, mode, _, p = orbit_start(excitation, r, beta, kappa, effects)
    assert (row[steady.OUT_REGIME], mode) == (regime, section)
    _, _, exact = period_map(x0, mode, p)
    assert exact is not None
    fd = central_differences(x0, mode, p)
    assert np.max(np.abs(exact - fd)) <= 1e-6 * np.max(np.abs(fd))
    if section != 2:
        # slipping at the section: w is slaved to q, so its column is zero and its row is q's
        assert np.all(exact[:, 2] == 0.0) and np.array_equal(exact[2], exact[0])


def test_period_k_monodromy_is_the_product():
    """The period-3 orbit (static friction): the product of the three periods' matrices equals central
    differences of P^3, and the driver's P^k (jenkins_steady._map_k) writes that product."""
    row, x0, mode, k, p = orbit_start("base", 0.5, 0.5, 100.0, {"static_friction_ratio": 1.5})
    assert k == 3
    _, _, product = period_map(x0, mode, p, periods=k)
    fd = central_differences(x0, mode, p, periods=k)
    assert np.max(np.abs(product - fd)) <= 1e-6 * np.max(np.abs(fd))
    acc = np.empty(jk.JACC_SIZE)
    *_, st, _ = js._map_k(x0[0], x0[1], x0[2], mode, np.nan, k, p, event.kernel_settings({}), 10**7, False, acc,
                          None)
    assert st == 0 and acc[jk.JACC_JAC_OK] == 1.0
    np.testing.assert_allclose(acc[jk.JACC_JAC:jk.JACC_JAC + 9].reshape(3, 3), product, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(("excitation", "r", "beta", "kappa", "effects", "regime", "section"), ORBITS, ids=IDS)
def test_floquet_multiplier_matches_differences(excitation, r, beta, kappa, effects, regime, section):
    """floquet_multiplier (now the exact matrix's largest |eigenvalue|) equals that of central differences of
    P^k at the orbit, to 1e-6, and is below 1 (an attracting orbit)."""
    row, x0, mode, k, p = orbit_start(excitation, r, beta, kappa, effects)
    fd = central_differences(x0, mode, p, periods=k)
    radius = np.max(np.abs(np.linalg.eigvals(fd)))
    assert abs(row[js.JOUT_FLOQUET] - radius) <= 1e-6 * max(radius, 1e-3)
    assert row[js.JOUT_FLOQUET] < 1.0


def newton(x, mode, p, jacobian, tol=1e-13, iterations=20):
    """Newton on P(x) = x in the coordinates the driver uses ((q, v) where the slider slips at the section,
    (q, v, w) where it is stuck); returns (x, Newton steps, period-map evaluations) on convergence."""
    dim = 2 if mode in (1, -1) else 3
    evaluations = 0
    for steps in range(iterations):
        if dim == 2:
            x[2] = x[0] - mode * p.bk / p.kappa
        x1, m1, exact = period_map(x, mode, p)
        evaluations += 1
        assert m1 == mode
        f = (x1 - x)[:dim]
        if np.sum(np.abs(f)) <= tol * max(np.hypot(x[0], x[1]), p.A):
            return x, steps, evaluations
        if jacobian == "exact":
            jac = exact
        else:
            jac = central_differences(x, mode, p)
            evaluations += 2 * dim
        x[:dim] -= np.linalg.solve(jac[:dim, :dim] - np.eye(dim), f)
    raise AssertionError("Newton did not converge")


@pytest.mark.parametrize("point", [ORBITS[0], ORBITS[1], ORBITS[4], ORBITS[7]], ids=[IDS[i] for i in (0, 1, 4, 7)])
def test_newton_with_the_exact_matrix(point):
    """From a state off the orbit (1e-3 of its size), Newton with the exact matrix converges to the kernel's
    orbit in no more iterations than Newton with central differences, so in fewer period-map evaluations."""
    excitation, r, beta, kappa, effects, *_ = point
    _, x0, mode, _, p = orbit_start(excitation, r, beta, kappa, effects)
    start = x0 + 1e-3 * np.hypot(x0[0], x0[1]) * np.array([1.0, -0.5, 0.3 if mode == 2 else 0.0])
    xe, steps_e, ne = newton(start.copy(), mode, p, "exact")
    xd, steps_d, nd = newton(start.copy(), mode, p, "differences")
    assert 0 < steps_e <= steps_d and ne < nd
    assert np.max(np.abs(xe - x0)) <= 1e-9 * np.hypot(x0[0], x0[1])
    assert np.max(np.abs(xd - x0)) <= 1e-9 * np.hypot(x0[0], x0[1])
