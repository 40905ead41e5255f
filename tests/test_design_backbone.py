"""The backbone (fs.backbone, friction_sweep.design.backbone) against truths that share no code with it: the
linear oscillator's phase resonance and damping ratio (no friction; a stuck Jenkins contact), the energy
balance (the forcing's work, from the first harmonic, against the friction energy the kernel sums over the
slip pieces), and the Jenkins contact's describing function (tests/test_jenkins_describing_function.py)
where the response is nearly harmonic (the third harmonic, measured by the independent DOP853 integrator,
below 0.5 % of the first: the issue 19 criterion that test established).
"""

from __future__ import annotations

import numpy as np
import pytest
from independent_jenkins import jenkins_orbit
from test_jenkins_describing_function import describing_function

import friction_sweep as fs
from friction_sweep.codes import Regime
from friction_sweep.design import backbone as bb
from friction_sweep.design.peak import Problem
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady


def _spec(excitation, r, beta, effects=None):
    scene = {"excitation": excitation, **({"effects": effects} if effects else {})}
    return {"scene": scene, "grid": {"frequency_ratio": r, "force_ratio": beta}, "method": "event"}


@pytest.mark.parametrize("excitation, effects", [
    ("force", {"viscous_damping": 0.05}),
    ("base", {"viscous_damping": {"ratio": 0.05, "to": "ground"}}),
    ("force", {"viscous_damping": 0.05, "contact_stiffness": 3.0}),  # no friction: the spring carries nothing
])
def test_without_friction_the_linear_natural_frequency_and_the_viscous_damping_ratio(excitation, effects):
    """beta = 0: q'' + 2 zeta q' + q = cos(r t) lags 90 degrees at r = 1 exactly, with amplitude 1 / (2 zeta),
    and zeta_eq = E_d / (4 pi E_p) = 2 pi zeta r a^2 / (2 pi a^2) = zeta."""
    ds = fs.backbone(_spec(excitation, {"start": 0.5, "stop": 2.0, "num": 31}, [0.0], effects))
    assert ds.sizes["crossing"] == 1
    one = ds.isel(force_ratio=0, crossing=0)
    assert abs(float(one.backbone_frequency_ratio) - 1.0) <= 1e-9
    assert float(one.backbone_amplitude) == pytest.approx(10.0, rel=1e-8)
    assert float(one.backbone_damping_ratio) == pytest.approx(0.05, rel=1e-8)
    assert float(one.backbone_friction_energy) == 0.0


def test_a_stuck_jenkins_contact_is_the_stiffened_linear_oscillator():
    """Friction far above the spring's force: the contact is the spring kappa, the oscillator's stiffness 1 +
    kappa, its phase resonance at r = sqrt(1 + kappa) and its damping ratio c / (2 sqrt(k m)) =
    zeta / sqrt(1 + kappa) (E_p = (1 + kappa) a^2 / 2: the contact's spring stores its share)."""
    kappa, zeta = 3.0, 0.05
    ds = fs.backbone(_spec("force", {"start": 1.0, "stop": 3.0, "num": 41}, [100.0],
                           {"viscous_damping": zeta, "contact_stiffness": kappa}))
    one = ds.isel(force_ratio=0, crossing=0)
    omega = np.sqrt(1.0 + kappa)
    assert int(one.backbone_regime) == Regime.STUCK
    assert abs(float(one.backbone_frequency_ratio) - omega) <= 1e-9
    assert float(one.backbone_amplitude) == pytest.approx(1.0 / (2 * zeta * omega), rel=1e-8)
    assert float(one.backbone_damping_ratio) == pytest.approx(zeta / omega, rel=1e-8)


@pytest.fixture(scope="module")
def jenkins():
    """The undamped Jenkins contact's backbone, kappa = 10, from the slider sliding most of the period to
    barely slipping. Without a dashpot a bounded phase resonance needs friction above pi/4 of the forcing
    (its work pi T against the slider's 4 beta (T - beta / kappa) per period)."""
    kappa = 10.0
    beta = np.geomspace(0.8, 20.0, 12)
    problem = Problem("event", "force", {"contact_stiffness": kappa})
    return kappa, beta, bb.backbone(problem, np.linspace(0.9, 3.4, 51), beta)


def test_the_dissipated_energy_is_the_friction_energy_without_a_dashpot(jenkins):
    """zeta = 0: the forcing's work per period, pi A T sin(phase) from the first harmonic (E_d), is what the
    slider dissipates, which the kernel sums over the slip pieces of the orbit (friction_energy): the energy
    balance of a periodic orbit. Every level has exactly one phase resonance, and the backbone softens from
    sqrt(1 + kappa) towards 1 and its damping ratio rises, then falls, with amplitude."""
    kappa, beta, found = jenkins
    assert np.all(np.isfinite(found.frequency_ratio[:, 0]))
    e_d, e_f = found.dissipated_energy[:, 0], found.friction_energy[:, 0]
    np.testing.assert_allclose(e_d, e_f, rtol=1e-7)
    zeta = bb.dataset(found, beta, {}).backbone_damping_ratio.values[:, 0]
    r_star, amplitude = found.frequency_ratio[:, 0], found.amplitude[:, 0]
    order = np.argsort(amplitude / beta)  # the amplitude at one friction force (homogeneity: backbone.py)
    assert np.all(np.diff(r_star[order]) < 0) and 1.0 < r_star.min() and r_star.max() < np.sqrt(1.0 + kappa)
    top = int(np.argmax(zeta[order]))
    assert 0 < top < beta.size - 1


def test_with_a_dashpot_the_dissipated_energy_holds_the_friction_and_the_dashpot(jenkins):
    """zeta > 0: E_d - friction_energy is the dashpot's loss, at least 2 pi zeta r T^2 (its first harmonic's
    share; higher harmonics only add), and no more than a few percent above it where the motion is nearly
    harmonic."""
    zeta = 0.02
    beta = np.array([0.05, 0.2, 0.5])
    found = bb.backbone(Problem("event", "force", {"contact_stiffness": 10.0, "viscous_damping": zeta}),
                        np.linspace(0.9, 3.4, 51), beta)
    r, t = found.frequency_ratio[:, 0], found.amplitude[:, 0]
    dashpot = found.dissipated_energy[:, 0] - found.friction_energy[:, 0]
    first = 2 * np.pi * zeta * r * t * t
    assert np.all(dashpot >= first * (1 - 1e-7)) and np.all(dashpot <= first * 1.05)


def test_the_jenkins_backbone_is_its_describing_function_where_the_motion_is_nearly_harmonic(jenkins):
    """Harmonic balance of the Jenkins element with N(a) = k_eq + i d_eq: at phase resonance (the response in
    quadrature with the forcing) the forcing balances the damping, A = d_eq(a) a, so (A = 1, zeta = 0)
    a = 4 beta^2 / (kappa (4 beta - pi)), and the stiffness the inertia, r^2 = 1 + k_eq(a). Where the third
    harmonic (DOP853, from the kernel's end state) is below 0.5 % of the first, the backbone's amplitude and
    frequency are both within 2 % of these; and enough such points along the curve. (Not its energy: d_eq
    is proportional to a - beta / kappa, which near sticking magnifies the amplitude's error tenfold.)"""
    kappa, beta, found = jenkins
    problem = Problem("event", "force", {"contact_stiffness": kappa})
    near = 0
    for j, b in enumerate(beta):
        r, t = found.frequency_ratio[j, 0], found.amplitude[j, 0]
        row = problem.rows(np.array([r]), np.array([b]))[0]
        h = jenkins_orbit(1.0, r, b, b, kappa, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W],
                          int(row[steady.OUT_END_MODE]), harmonics=(1, 3))["harmonics"]
        assert abs(h[1] / t - 1.0) <= 1e-8  # one orbit: the kernel's and DOP853's first harmonics
        if h[3] / h[1] >= 0.005:
            continue
        near += 1
        a = 4 * b * b / (kappa * (4 * b - np.pi))
        assert abs(describing_function(a, b, kappa).imag * a - 1.0) <= 1e-12  # the closed form solves A = d_eq a
        assert abs(t / a - 1.0) <= 0.02, (b, r, t, a)
        assert abs(r / np.sqrt(1.0 + describing_function(a, b, kappa).real) - 1.0) <= 0.02, (b, r, t, a)
    assert near >= 4


def test_the_scenes_without_a_phase_resonance_of_their_own_are_refused():
    """joined (q = z, not x) and base with the dashpot to the base (its forcing leads the excitation)."""
    r = {"start": 0.5, "stop": 2.0, "num": 11}
    with pytest.raises(fs.FsweepError, match="scene: the backbone is the phase resonance of the mass"):
        fs.backbone(_spec("joined", r, [0.5]))
    with pytest.raises(fs.FsweepError, match="scene: the backbone is the phase resonance of the mass"):
        fs.backbone(_spec("base", r, [0.5], {"viscous_damping": {"ratio": 0.05, "to": "base"}}))


def test_cli_backbone_prints_each_phase_resonance_and_writes_the_dataset(tmp_path):
    import xarray as xr
    from click.testing import CliRunner

    from friction_sweep.cli import main

    spec = tmp_path / "bb.yaml"
    spec.write_text("scene: {excitation: force, effects: {viscous_damping: 0.05}}\n"
                    "grid: {frequency_ratio: {start: 0.5, stop: 2.0, num: 31}, force_ratio: [0.0, 0.1]}\n"
                    "method: event\n")
    out = tmp_path / "bb.nc"
    done = CliRunner().invoke(main, ["backbone", str(spec), "-o", str(out)])
    assert done.exit_code == 0, done.output
    lines = done.output.splitlines()
    assert len(lines) == 2 and lines[0].startswith("force_ratio 0: r = 1") and "zeta_eq 0.05" in lines[0]
    with xr.open_dataset(out) as ds:
        np.testing.assert_array_equal(ds.backbone_damping_ratio.values,
                                      fs.backbone(str(spec)).backbone_damping_ratio.values)
