"""The output group `stability`: each steady orbit's largest Floquet multiplier (`floquet_multiplier`), against
independent truths: the linear oscillator's decay over a period, central differences of the period map
computed here from the bare period integrator, and the RK4 kernel's own (finite-difference) value."""

import math

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import event as event_kernel
from friction_sweep.kernels import steady
from friction_sweep.kernels.measure import new_accumulator
from friction_sweep.kernels.period_map import mode_of
from friction_sweep.kernels.point import Point
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import event
from friction_sweep.spec.parse import load_spec


def rows(excitation, r, beta, effects=None, **settings):
    """Raw rows of points (r, beta) with the multiplier measured."""
    return event.solve_flat(excitation, np.atleast_1d(np.asarray(r, dtype=float)),
                            np.atleast_1d(np.asarray(beta, dtype=float)), effects, stability=1, **settings)


@pytest.mark.parametrize("zeta", [0.05, 0.3])
@pytest.mark.parametrize(("excitation", "contact"), [("force", {}), ("base", {}), ("base", {"contact_stiffness": 50.0})])
def test_linear_damped_orbit_decays_by_its_damping(excitation, contact, zeta):
    """Without friction the period map is linear: eigenvalues exp((-zeta +- i sqrt(1 - zeta^2)) 2 pi / r), whose
    modulus exp(-2 pi zeta / r) does not depend on the spring (nor on a contact that carries no force)."""
    r = np.array([0.3, 0.9, 1.0, 1.7, 4.0])
    out = rows(excitation, r, np.zeros_like(r), {"viscous_damping": zeta, **contact})
    np.testing.assert_allclose(out[:, steady.OUT_FLOQUET], np.exp(-2 * np.pi * zeta / r), rtol=1e-12)


def test_undamped_linear_orbit_is_neutral():
    """beta = 0, no damping: the forced steady state of a conservative oscillator; its map is a rotation."""
    r = np.array([0.4, 1.3, 2.5])
    out = rows("base", r, np.zeros_like(r))
    np.testing.assert_allclose(out[:, steady.OUT_FLOQUET], 1.0, rtol=1e-12)


def period_map_jacobian(excitation, r, beta, effects, row):
    """Central differences of P^k (k = the orbit's period) at the orbit's state, from event.advance_period
    alone (no steady-state code): the independent check of the monodromy product."""
    A, c, bk, bs, zeta = event.point_parameters(excitation, np.array([r]), np.array([beta]), effects)
    p = Point(A[0], r, bk[0], bs[0], zeta[0], c[0])
    k = int(row[steady.OUT_ORBIT_PERIOD])
    none = event_kernel.NO_SAMPLES

    def P(q, v):
        mode = mode_of(q, v, p)
        for _ in range(k):
            q, v, mode, status, _ = event_kernel.advance_period(q, v, mode, p, 1e-13, 10**7, False,
                                                                new_accumulator(), none, none, none)
            assert status == 0
        return np.array([q, v])

    q, v = row[steady.OUT_END_Q], row[steady.OUT_END_V]
    h = 1e-6 * max(abs(q), abs(v), A[0])
    return np.column_stack([(P(q + h, v) - P(q - h, v)) / (2 * h), (P(q, v + h) - P(q, v - h)) / (2 * h)])


# (excitation, r, beta, effects, regime, orbit period): moving orbits of every kind the exact matrix covers
ORBITS = [
    ("base", 1.5, 0.3, None, Regime.CONTINUOUS, 1),
    ("base", 0.5, 0.5, None, Regime.STICK_SLIP, 1),
    ("base", 0.1, 0.3, None, Regime.STICK_SLIP, 1),  # many stops
    ("force", 0.5, 0.6, None, Regime.STICK_SLIP, 1),
    ("joined", 0.6, 0.3, None, Regime.STICK_SLIP, 1),
    ("joined", 1.2, 0.5, None, Regime.CONTINUOUS, 1),
    ("base", 0.5, 0.5, {"viscous_damping": 0.05}, Regime.STICK_SLIP, 1),
    ("base", 0.5, 0.5, {"static_friction_ratio": 1.5}, Regime.STICK_SLIP, 1),
    # static friction locks onto longer periods: the product of the periods' matrices
    ("base", 0.46, 0.25, {"static_friction_ratio": 1.5}, Regime.STICK_SLIP, 8),
    ("base", 0.4, 0.1, {"static_friction_ratio": 2.0}, Regime.STICK_SLIP, 2),
]


@pytest.mark.parametrize(("excitation", "r", "beta", "effects", "regime", "orbit"), ORBITS)
def test_exact_multiplier_matches_central_differences(excitation, r, beta, effects, regime, orbit):
    row = rows(excitation, r, beta, effects)[0]
    assert row[steady.OUT_REGIME] == regime and row[steady.OUT_ORBIT_PERIOD] == orbit
    jac = period_map_jacobian(excitation, r, beta, effects, row)
    truth = np.max(np.abs(np.linalg.eigvals(jac)))
    assert row[steady.OUT_FLOQUET] == pytest.approx(truth, rel=1e-6, abs=1e-9)
    assert row[steady.OUT_FLOQUET] < 1.0  # a steady state attracts


@pytest.mark.parametrize(("excitation", "r", "beta", "effects", "regime", "orbit"), ORBITS[:8])
def test_rk4_differences_agree_with_the_exact_matrix(excitation, r, beta, effects, regime, orbit):
    exact = rows(excitation, r, beta, effects)[0]
    rk4 = rows(excitation, r, beta, effects, kernel=KERNEL_RK4, steps_per_period=512)[0]
    assert rk4[steady.OUT_FLOQUET] == pytest.approx(exact[steady.OUT_FLOQUET], rel=1e-4)
    # its central differences integrate 4 k more periods than the same solve without them
    plain = event.solve_flat(excitation, np.array([r]), np.array([beta]), effects, kernel=KERNEL_RK4,
                             steps_per_period=512)[0]
    assert rk4[steady.OUT_PERIODS] == plain[steady.OUT_PERIODS] + 4 * orbit
    assert np.isnan(plain[steady.OUT_FLOQUET])


def test_undefined_where_there_is_no_isolated_orbit():
    # stuck (a continuum of rest positions), the r = 1/(2n) family, unbounded at r = 1
    out = rows("base", [2.0, 0.5, 1.0], [1.2, 0.1, 0.3])
    assert list(out[:, steady.OUT_REGIME]) == [Regime.STUCK, Regime.CONTINUOUS, Regime.UNBOUNDED]
    assert out[1, steady.OUT_STEADY_STATE] == SteadyState.FAMILY
    assert np.isnan(out[:, steady.OUT_FLOQUET]).all()


def test_asked_for_only_and_free_where_exact():
    """Without the output the slot is NaN and nothing else changes by a bit; with it, an event orbit of one
    period costs no period more (its measured period's matrix is the monodromy)."""
    r = np.linspace(0.2, 3.0, 15)
    beta = np.full_like(r, 0.4)
    plain = event.solve_flat("base", r, beta)
    asked = rows("base", r, beta)
    assert np.isnan(plain[:, steady.OUT_FLOQUET]).all()
    others = [i for i in range(steady.OUT_SIZE) if i != steady.OUT_FLOQUET]
    one = asked[:, steady.OUT_ORBIT_PERIOD] == 1
    np.testing.assert_array_equal(plain[np.ix_(one, others)], asked[np.ix_(one, others)])
    moving = np.isin(asked[:, steady.OUT_REGIME], [Regime.CONTINUOUS, Regime.STICK_SLIP])
    assert np.isfinite(asked[moving & one, steady.OUT_FLOQUET]).all()


def test_cube_variable_and_its_moving_twin(tmp_path):
    spec = tmp_path / "s.yaml"
    spec.write_text("scene: {excitation: base, effects: {static_friction_ratio: 1.5}}\n"
                    "grid: {frequency_ratio: [0.5, 1.5], force_ratio: [0.3]}\n"
                    "method: event\noutputs: [transmissibility, regime, stability]\n")
    load_spec(spec)  # the spec layer accepts the group for event
    tile = event.compute_tile("base", np.array([0.5, 1.5]), np.array([0.3]), ("regime", "stability"),
                              {"static_friction_ratio": 1.5})
    assert tile["floquet_multiplier"].shape == (1, 2) and tile["floquet_multiplier_moving"].shape == (1, 2)
    assert (tile["floquet_multiplier"] < 1.0).all()


@pytest.mark.parametrize("effects", ["{static_friction_ratio: 1.5}",
                                     "{static_friction_ratio: 1.5, contact_stiffness: 100}"])
def test_run_writes_the_variable_and_its_moving_twin(tmp_path, effects):
    spec = tmp_path / "s.yaml"
    spec.write_text(f"scene: {{excitation: base, effects: {effects}}}\n"
                    "grid: {frequency_ratio: [0.5, 1.5], force_ratio: [0.3]}\n"
                    "method: event\noutputs: [transmissibility, regime, stability]\n")
    out = tmp_path / "s.h5"
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    cube = xr.open_dataset(out, engine="h5netcdf")
    for name in ("floquet_multiplier", "floquet_multiplier_moving"):
        assert "output stability" in cube[name].attrs["comment"]
        assert (cube[name].values < 1.0).all()


def test_theory_refuses_the_group(tmp_path):
    spec = tmp_path / "s.yaml"
    spec.write_text("scene: {excitation: base}\ngrid: {frequency_ratio: [0.5], force_ratio: [0.3]}\n"
                    "method: theory\noutputs: [stability]\n")
    with pytest.raises(Exception, match="stability"):
        load_spec(spec)


def test_the_multiplier_predicts_the_march():
    """An independent reading of the multiplier: the march's distance to the orbit shrinks by it per period (to
    within the 20th root of the matrix's eigenvector conditioning: its multipliers are a complex pair)."""
    excitation, r, beta = "base", 1.5, 0.3
    row = rows(excitation, r, beta)[0]
    A, c, bk, bs, zeta = event.point_parameters(excitation, np.array([r]), np.array([beta]))
    p = Point(A[0], r, bk[0], bs[0], zeta[0], c[0])
    q, v = row[steady.OUT_END_Q] + 1e-4, row[steady.OUT_END_V]
    none = event_kernel.NO_SAMPLES
    dist = []
    mode = mode_of(q, v, p)
    for _ in range(40):
        q, v, mode, _, _ = event_kernel.advance_period(q, v, mode, p, 1e-13, 10**7, False, new_accumulator(),
                                                       none, none, none)
        dist.append(math.hypot(q - row[steady.OUT_END_Q], v - row[steady.OUT_END_V]))
    rate = (dist[30] / dist[10]) ** (1 / 20)
    assert rate == pytest.approx(row[steady.OUT_FLOQUET], rel=1e-2)
