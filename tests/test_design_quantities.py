"""The design outputs `friction_energy` and `transmitted_force` (docs/equations.md §6) against truths
that share no code with how they are computed: Den Hartog's amplitude, the energy balance of a periodic
orbit (the forcing's work from the first harmonic, or by quadrature of an independently integrated
orbit), the linear oscillator's closed forms, and the support force summed from spring and friction.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import in_dir, small_spec, write_spec
from independent_integrator import orbit_energies

from friction_sweep import catalogue, methods
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.storage.schema import MOVING_SUFFIX, VARIABLES
from friction_sweep.theory import den_hartog as dh

pytestmark = pytest.mark.usefixtures("compiled")

DESIGN = ("transmissibility", "phase", "regime", "friction_energy", "transmitted_force")


def tile(method, excitation, r, beta, effects=None, settings=None):
    """One point's outputs as floats."""
    out = methods.get(method).compute_tile(excitation, np.array([r]), np.array([beta]), DESIGN, effects=effects,
                                           settings=settings)
    return {k: v[0, 0] if np.ndim(v) == 2 else v for k, v in out.items()}


def forcing_amplitude(excitation, r):
    return r * r if excitation == "joined" else 1.0


def forcing_work(excitation, r, point):
    """The forcing's work per period, from the point's own first harmonic: W = integral of A cos(r t) q'
    = A r integral of q sin(r t) (by parts; only q's first harmonic contributes) = pi A T sin(phase),
    with x ~ T cos(r t - phase) and q = x - c cos(r t) (the c part is orthogonal to sin). No motion
    (T = 0, phase undefined): no work."""
    t = point["transmissibility"]
    lag = np.where(t == 0.0, 0.0, np.radians(point["phase"]))
    return np.pi * forcing_amplitude(excitation, r) * t * np.sin(lag)


def den_hartog_energy(excitation, r, beta):
    """4 beta X, X the peak amplitude of q (z for joined: A times Den Hartog's amplitude at b = beta / A)."""
    a = forcing_amplitude(excitation, r)
    return 4.0 * beta * a * dh.amplitude(r, beta / a)


# continuous points (b well below beta*(r)), each scene
CONTINUOUS = [("base", 1.5, 0.3), ("base", 0.7, 0.1), ("force", 3.0, 0.4), ("joined", 1.5, 0.5),
              ("joined", 2.0, 1.5)]


@pytest.mark.parametrize("excitation, r, beta", CONTINUOUS)
def test_continuous_energy_is_four_beta_x(excitation, r, beta):
    """(a) Continuous motion slides 4X a period: friction_energy = 4 beta X exactly (event, auto, to
    rounding), and rk4 converges to it at fourth order in its step."""
    truth = den_hartog_energy(excitation, r, beta)
    assert tile("theory", excitation, r, beta)["regime"] == Regime.CONTINUOUS
    for method in ("event", "auto"):
        point = tile(method, excitation, r, beta)
        assert point["regime"] == Regime.CONTINUOUS
        assert point["friction_energy"] == pytest.approx(truth, rel=1e-9)
    errors = [abs(tile("rk4", excitation, r, beta, settings={"steps_per_period": n})["friction_energy"] / truth - 1)
              for n in (256, 512)]
    assert errors[0] < 1e-7
    assert 10.0 < errors[0] / errors[1] < 25.0  # 2^4 = 16: fourth order


# points of every regime, static = kinetic friction unless given: (excitation, r, beta, static ratio,
# expected regime, expected stops per period)
REGIMES = [
    ("base", 0.5, 1.2, 1.0, Regime.STUCK, 0.0),
    ("joined", 0.5, 0.3, 1.0, Regime.STUCK, 0.0),
    ("base", 0.5, 0.5, 1.0, Regime.STICK_SLIP, 2.0),  # one stop a half period
    ("base", 0.2, 0.3, 1.0, Regime.STICK_SLIP, 4.0),  # two stops a half period
    ("base", 0.5, 0.3, 1.5, Regime.STICK_SLIP, 1.0),  # static friction: one stop a period
    ("joined", 0.5, 0.1, 1.0, Regime.STICK_SLIP, 2.0),
    ("base", 1.5, 0.3, 1.0, Regime.CONTINUOUS, 0.0),
    ("joined", 1.5, 0.5, 1.0, Regime.CONTINUOUS, 0.0),
]


def _effects(ratio=1.0, zeta=0.0):
    effects = {}
    if ratio != 1.0:
        effects["static_friction_ratio"] = ratio
    if zeta:
        effects["viscous_damping"] = zeta
    return effects


@pytest.mark.parametrize("excitation, r, beta, ratio, regime, stops", REGIMES)
def test_energy_balance_undamped(excitation, r, beta, ratio, regime, stops):
    """(b) Without damping the forcing's work per period (from the first harmonic) is what friction
    dissipates, in every regime (event to 1e-10, rk4 to its order); and both equal the energies of an
    orbit integrated independently (DOP853, forcing work by quadrature of A cos(r t) q')."""
    effects = _effects(ratio)
    point = tile("event", excitation, r, beta, effects)
    assert point["regime"] == regime
    assert point["stops_per_period"] == stops
    energy, work = point["friction_energy"], forcing_work(excitation, r, point)
    other = orbit_energies(forcing_amplitude(excitation, r), r, beta, ratio * beta, 0.0, 0.0)
    if regime == Regime.STUCK:
        assert energy == work == other["friction"] == other["forcing"] == 0.0
        return
    assert energy > 0.0
    assert energy == pytest.approx(work, rel=1e-10)
    rk4 = tile("rk4", excitation, r, beta, effects)
    assert rk4["friction_energy"] == pytest.approx(forcing_work(excitation, r, rk4), rel=1e-6)
    assert rk4["friction_energy"] == pytest.approx(energy, rel=1e-6)
    assert other["friction"] == pytest.approx(other["forcing"], rel=1e-9)
    assert energy == pytest.approx(other["friction"], rel=1e-9)


@pytest.mark.parametrize("r, beta, k", [(0.32, 0.1, 2), (0.42, 0.15, 3)])
def test_energy_balance_period_k(r, beta, k):
    """(b) A period-k orbit (static friction 1.5 x kinetic, base): the energy per forcing period, its k
    periods' over k, balances the forcing's work per period from the first harmonic over the k periods."""
    point = tile("event", "base", r, beta, _effects(1.5), settings={"starts": 1})
    assert point["orbit_period"] == k
    assert point["friction_energy"] == pytest.approx(forcing_work("base", r, point), rel=1e-10)
    rk4 = tile("rk4", "base", r, beta, _effects(1.5), settings={"starts": 1})
    assert rk4["orbit_period"] == k
    assert rk4["friction_energy"] == pytest.approx(point["friction_energy"], rel=1e-6)


@pytest.mark.parametrize("r, beta", [(0.5, 0.3), (1.0, 0.2), (2.0, 0.5), (0.3, 0.6)])
def test_energy_balance_damped(r, beta):
    """(b) With a dashpot (force scene: to the ground) the forcing's work is friction's energy plus the
    viscous dissipation 2 zeta integral of q'^2, the latter by quadrature of an independently integrated
    orbit."""
    zeta = 0.1
    point = tile("event", "force", r, beta, _effects(zeta=zeta))
    assert point["regime"] in (Regime.STICK_SLIP, Regime.CONTINUOUS)
    other = orbit_energies(1.0, r, beta, beta, 0.0, 0.0, zeta=zeta)
    work = forcing_work("force", r, point)
    assert work == pytest.approx(point["friction_energy"] + other["viscous"], rel=1e-9)
    assert point["friction_energy"] == pytest.approx(other["friction"], rel=1e-9)
    assert other["forcing"] == pytest.approx(other["friction"] + other["viscous"], rel=1e-9)


def test_theory_energy_balance():
    """(b) The theory's 4 beta X is the forcing's work from its own first harmonic (a quadrature of the
    waveform): the closed forms agree with each other on a grid of continuous points."""
    r = np.array([0.4, 0.7, 0.9, 1.2, 2.0, 4.0])
    beta = np.array([0.0, 0.05, 0.2, 0.35])
    for excitation in ("force", "base", "joined"):
        out = methods.get("theory").compute_tile(excitation, r, beta, DESIGN)
        ok = out["regime"] == Regime.CONTINUOUS
        assert ok.sum() >= 12
        work = forcing_work(excitation, r[None, :], out)
        energy = out["friction_energy"]
        np.testing.assert_allclose(energy[ok], work[ok], rtol=1e-10, atol=1e-14)
        assert np.all(np.isnan(energy[out["regime"] == Regime.STICK_SLIP]))


@pytest.mark.parametrize("method", ["event", "rk4", "theory", "auto"])
def test_transmitted_force_linear(method):
    """(c) beta = 0, undamped, force scene: the force into the ground is the spring's, x = 1/(1 - r^2),
    so its amplitude is 1/|1 - r^2| (not the m x'' of base/joined)."""
    r = np.array([0.3, 0.5, 0.8, 1.3, 2.0, 5.0])
    out = methods.get(method).compute_tile("force", r, np.array([0.0]), DESIGN)
    np.testing.assert_allclose(out["transmitted_force"][0], 1.0 / np.abs(1.0 - r * r),
                               rtol=1e-6 if method == "rk4" else 1e-9)  # rk4: its O(h^4) at 256 steps
    np.testing.assert_array_equal(out["friction_energy"][0], 0.0)


@pytest.mark.parametrize("method", ["event", "rk4"])
def test_transmitted_force_damped_base(method):
    """(c) beta = 0, base scene with the dashpot to the ground: m x'' has amplitude r^2 / |1 - r^2 + 2 i zeta r|."""
    zeta = 0.15
    r = np.array([0.3, 0.8, 1.0, 1.3, 3.0])
    out = methods.get(method).compute_tile("base", r, np.array([0.0]), DESIGN, effects=_effects(zeta=zeta))
    truth = r * r / np.abs(1.0 - r * r + 2j * zeta * r)
    np.testing.assert_allclose(out["transmitted_force"][0], truth, rtol=1e-9 if method == "event" else 1e-6)


@pytest.mark.parametrize("excitation, r, beta", CONTINUOUS)
def test_transmitted_force_continuous(excitation, r, beta):
    """(c) Continuous motion: the support force summed another way. The supports hold the spring and the
    friction, q + beta sgn(q') (plus the base's cos(r t) for base: spring x - y), whose first harmonic in
    the frame of q's maximum is Q1 + i 4 beta / pi (the friction is a square wave, -beta from the maximum
    to the minimum, first harmonic -(4 beta / pi) sin(r t)), with Q1 = A (a1 - i b1) from Den Hartog's
    first harmonic and the excitation cos(r t + phi). For base that must be r^2 T = r^2 |X1| too."""
    a = forcing_amplitude(excitation, r)
    b = beta / a
    a1, b1 = dh.first_harmonic(r, b)
    phi = dh.phase(r, b)
    q1 = a * (a1 - 1j * b1)
    support = q1 + 4j * beta / np.pi
    if excitation == "base":
        support -= np.exp(1j * phi)  # the spring pulls on the base with x - y
        assert abs(support) == pytest.approx(r * r * abs(q1), rel=1e-12)
    for method in ("event", "auto", "theory"):
        assert tile(method, excitation, r, beta)["transmitted_force"] == pytest.approx(abs(support), rel=1e-9)


def test_stuck_and_unbounded():
    """(d) Nothing slides when stuck (0, and the support force of a mass at rest or riding with the wall);
    NaN where there is no steady state (unbounded at r = 1, unsettled when the budget runs out)."""
    for method in ("event", "rk4", "theory", "auto"):
        stuck = tile(method, "base", 0.5, 1.2)
        assert stuck["regime"] == Regime.STUCK
        assert stuck["friction_energy"] == 0.0
        assert stuck["transmitted_force"] == 0.0  # base: no motion, m x'' = 0
        assert tile(method, "force", 0.5, 1.2)["transmitted_force"] == 1.0  # the wall holds the whole force
        riding = tile(method, "joined", 0.5, 0.3)  # x = y: m x'' = r^2
        assert riding["friction_energy"] == 0.0
        assert riding["transmitted_force"] == pytest.approx(0.25, rel=1e-15)
        unbounded = tile(method, "base", 1.0, 0.5)
        assert unbounded["regime"] == Regime.UNBOUNDED
        assert np.isnan(unbounded["friction_energy"]) and np.isnan(unbounded["transmitted_force"])
    unsettled = tile("event", "base", 0.3, 0.05, settings={"work_budget": 1})
    assert unsettled["regime"] == Regime.UNSETTLED
    assert np.isnan(unsettled["friction_energy"]) and np.isnan(unsettled["transmitted_force"])


def test_moving_twins_and_schema():
    """Both describe one steady state: with static friction the moving start's values come as `_moving`
    twins, with CF attributes naming the unit they are measured in."""
    out = methods.get("event").compute_tile("base", np.array([0.5]), np.array([0.3]), DESIGN,
                                            effects=_effects(1.5))
    for name in ("friction_energy", "transmitted_force"):
        assert name + MOVING_SUFFIX in out
        assert name + MOVING_SUFFIX in VARIABLES
    assert "k Y^2" in VARIABLES["friction_energy"].attrs("base")["long_name"]
    assert "F0^2/k" in VARIABLES["friction_energy"].attrs("force")["long_name"]
    assert "(k Y)" in VARIABLES["transmitted_force"].attrs("joined")["long_name"]
    assert "(F0)" in VARIABLES["transmitted_force"].attrs("force")["long_name"]
    assert catalogue.DEFAULT_OUTPUTS == ("transmissibility", "phase", "regime")
    assert set(catalogue.able("friction_energy")) == {"theory", "event", "rk4", "auto"}


def test_cli_writes_them_and_lists_them(runner, tmp_path):
    """Selected in a spec's outputs they reach the cube with CF attributes (`fsweep check` passes it);
    `fsweep info --methods` lists them; the paper's method refuses them."""
    text = small_spec("force").replace("outputs: [transmissibility, phase, regime]",
                                       "outputs: [regime, friction_energy, transmitted_force]")
    spec = write_spec(tmp_path, text=text)
    with in_dir(tmp_path):
        res = runner.invoke(main, ["run", str(spec), "--quiet"])
        assert res.exit_code == 0, res.output
        assert runner.invoke(main, ["check", "out.h5"]).exit_code == 0
    ds = xr.open_dataset(tmp_path / "out.h5", engine="h5netcdf")
    for name in ("friction_energy", "transmitted_force"):
        assert ds[name].dims == ("force_ratio", "frequency_ratio")
        assert ds[name].attrs["units"] == "1"
    assert "F0^2/k" in ds["friction_energy"].attrs["long_name"]
    assert "transmissibility" not in ds  # only what was asked
    listing = runner.invoke(main, ["info", "--methods"]).output
    assert "friction_energy" in listing and "transmitted_force" in listing
    spec.write_text(text.replace("method: theory", "method: paper"))
    res = runner.invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2 and "cannot write output 'friction_energy'" in res.output


def test_swept_run_writes_them_alike():
    """A stepped-sine sweep (event) writes the same values where the steady state is unique."""
    from friction_sweep.methods import event

    r, beta = np.array([0.5, 1.5, 0.8]), np.array([0.3, 0.5])
    swept = event.compute_sweep_tile("base", r, beta, DESIGN, direction="down")
    plain = event.compute_tile("base", r, beta, DESIGN)
    for name in ("friction_energy", "transmitted_force"):
        np.testing.assert_allclose(swept[name], plain[name], rtol=1e-9)
        assert np.all(plain[name] > 0.0)


@pytest.mark.parametrize("r, beta", [(0.5, 0.3), (1.0, 0.2), (2.0, 0.5), (2.0, 1.05)])
def test_energy_balance_with_the_dashpot_on_the_base(r, beta):
    """(b) With the spring-parallel dashpot (base, `to: base`) the dashpot's base end works too: the work
    per period is pi A' T sin(phase + phi0) (docs/equations.md §6), and friction's energy is that minus
    the viscous loss, against an orbit integrated independently with the force cos - 2 zeta r sin as it
    stands (no phase shift)."""
    from independent_integrator import steady_orbit

    zeta = 0.1
    effects = {"viscous_damping": {"ratio": zeta, "to": "base"}}
    point = tile("event", "base", r, beta, effects)
    assert point["regime"] in (Regime.STICK_SLIP, Regime.CONTINUOUS)
    other = steady_orbit(1.0, r, beta, beta, 0.0, 0.0, zeta=zeta, base_dashpot=True)["energies"]
    amplitude, phi0 = np.hypot(1.0, 2 * zeta * r), np.arctan2(2 * zeta * r, 1.0)
    work = np.pi * amplitude * point["transmissibility"] * np.sin(np.radians(point["phase"]) + phi0)
    assert work == pytest.approx(other["forcing"], rel=1e-8)
    assert point["friction_energy"] == pytest.approx(other["friction"], rel=1e-8)
    assert point["friction_energy"] == pytest.approx(work - other["viscous"], rel=1e-8)
