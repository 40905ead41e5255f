"""The Jenkins contact (effect contact_stiffness, issue 19) against independent truths: a DOP853 integrator
written here (independent_jenkins), the linear oscillator of stiffness 1 + kappa, the energy balance, and
the rigid model as kappa -> oo."""

import numpy as np
import pytest
from independent_jenkins import jenkins_orbit

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import jenkins as jk
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import steady
from friction_sweep.methods import event
from friction_sweep.spec.parse import load_spec

OUTPUTS = ("transmissibility", "phase", "regime", "friction_energy")


def jenkins(excitation, r, beta, kappa, **effects):
    """Raw Jenkins rows for points (r, beta) (1-D arrays)."""
    return event.solve_flat(excitation, np.atleast_1d(r), np.atleast_1d(beta),
                            {"contact_stiffness": kappa, **effects})


# (excitation, r, beta, kappa, effects, regime): points of every regime the slider shows
POINTS = [
    ("base", 1.5, 0.3, 100.0, {}, Regime.CONTINUOUS),
    ("base", 0.5, 0.5, 100.0, {}, Regime.STICK_SLIP),
    ("base", 0.3, 0.6, 100.0, {}, Regime.STICK_SLIP),
    ("base", 0.8, 0.9, 30.0, {}, Regime.STICK_SLIP),
    ("base", 2.0, 1.2, 100.0, {}, Regime.STUCK),
    ("force", 0.7, 0.4, 300.0, {}, Regime.CONTINUOUS),
    ("joined", 1.2, 0.5, 100.0, {}, Regime.CONTINUOUS),
    ("joined", 0.6, 0.3, 100.0, {}, Regime.STICK_SLIP),
    ("force", 0.5, 0.6, 100.0, {}, Regime.STICK_SLIP),
    ("base", 0.5, 0.5, 100.0, {"viscous_damping": 0.05}, Regime.STICK_SLIP),
    ("base", 1.3, 0.4, 100.0, {"static_friction_ratio": 1.5}, Regime.CONTINUOUS),
    # static friction: an orbit of period 3 forcing periods (10 slips, 4 stops), creeps across the section
    ("base", 0.5, 0.5, 100.0, {"static_friction_ratio": 1.5}, Regime.STICK_SLIP),
    # stick-slip in the rigid model, continuous at kappa = 100 (both integrators): at the rigid stop the holding
    # force is of the other sign than the kinetic one, so the mass's undamped swing on the contact spring
    # carries the contact force across the band (2 |bk - f_hold| > 2 bk) and the slider slips back at once
    ("joined", 0.7, 0.4, 100.0, {}, Regime.CONTINUOUS),
    ("base", 0.6, 0.5, 100.0, {"viscous_damping": 0.05}, Regime.CONTINUOUS),
]


@pytest.mark.parametrize(("excitation", "r", "beta", "kappa", "effects", "regime"), POINTS)
def test_independent_dop853_agrees(excitation, r, beta, kappa, effects, regime):
    """The kernel's orbit, continued by DOP853 with event switching (sharing no kernel code), repeats, and
    its first harmonic agrees to 1e-8, its orbit's period and its slips and stops per period exactly."""
    row = jenkins(excitation, r, beta, kappa, **effects)[0]
    assert row[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    assert row[steady.OUT_REGIME] == regime
    A, c, bk, bs, zeta = (float(x[0]) for x in event.point_parameters(excitation, [r], [beta], effects))
    mode = int(row[steady.OUT_END_MODE])
    ind = jenkins_orbit(A, r, bk, bs, kappa, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W], mode,
                        c=c, zeta=zeta)
    assert ind["orbit_period"] == row[steady.OUT_ORBIT_PERIOD]
    assert abs(ind["amplitude"] / row[steady.OUT_TRANSMISSIBILITY] - 1) <= 1e-8
    assert ind["slips"] == row[js.JOUT_SLIPS]
    assert ind["stops"] == row[steady.OUT_STOPS_PER_PERIOD]
    if regime != Regime.STUCK:
        assert abs(ind["friction_energy"] - row[steady.OUT_FRICTION_ENERGY]) <= 1e-9 * ind["friction_energy"]


#: held 80 % of each period, slipping 4 times from held sticks: twice a creep, twice a slide the load drives,
#: shorter than the band (joined, r = 0.999, beta = 0.985, kappa = 1000, zeta = 0.05)
CREEPING = ("joined", 0.999, 0.985, 1000.0, {"viscous_damping": 0.05})


def test_labels_are_the_orbits_own():
    """The slip across the section began from a held stick before t = 0; the orbit is measured with the
    creep anchor its own periods carry (not the march's where shooting began, which once gave 1 stop per
    period here against 0 for every later period): DOP853, carrying its anchor, counts the same: the rigid
    model's 2 stops."""
    excitation, r, beta, kappa, effects = CREEPING
    row = jenkins(excitation, r, beta, kappa, **effects)[0]
    A, c, bk, bs, zeta = (float(x[0]) for x in event.point_parameters(excitation, [r], [beta], effects))
    ind = jenkins_orbit(A, r, bk, bs, kappa, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W],
                        int(row[steady.OUT_END_MODE]), c=c, zeta=zeta)
    assert (ind["slips"], ind["stops"]) == (row[js.JOUT_SLIPS], row[steady.OUT_STOPS_PER_PERIOD]) == (4, 2)
    assert abs(ind["amplitude"] / row[steady.OUT_TRANSMISSIBILITY] - 1) <= 1e-8


@pytest.mark.parametrize("kappa", [100.0, 1000.0, 1e4, 1e5])
def test_slides_shorter_than_the_band_still_end_the_stop(kappa):
    """Next to r = 1 with beta close to A the rigid mass is held 85 % of the time and slides less than the
    contact's band, 2 beta / kappa, at kappa = 1000: a rule by slide length read those slides as creeps and
    the orbit as continuous. A creep is a slip the load never drives (the mass coasts on its swing); these
    slides are driven, so every kappa keeps the rigid model's 2 stops, and the time held approaches its."""
    excitation, r, beta, _, effects = CREEPING
    rigid = event.solve_flat(excitation, np.array([r]), np.array([beta]), effects)[0]
    row = jenkins(excitation, r, beta, kappa, **effects)[0]
    assert rigid[steady.OUT_REGIME] == row[steady.OUT_REGIME] == Regime.STICK_SLIP
    assert row[steady.OUT_STOPS_PER_PERIOD] == rigid[steady.OUT_STOPS_PER_PERIOD] == 2
    if kappa >= 1000.0:
        assert abs(row[steady.OUT_STUCK_FRACTION] - rigid[steady.OUT_STUCK_FRACTION]) < 0.05


@pytest.mark.parametrize(("excitation", "r", "beta"), [("base", 1.5, 0.3), ("base", 0.5, 0.5), ("base", 0.3, 0.6),
                                                      ("joined", 1.2, 0.5), ("force", 0.8, 0.9)])
def test_energy_balance(excitation, r, beta):
    """Without damping the forcing's work per period, pi A T sin(phase) (docs/equations.md §6: the contact
    spring's energy returns over a period), equals what the slider dissipates, to 1e-10."""
    row = jenkins(excitation, r, beta, 100.0)[0]
    A = event.point_parameters(excitation, [r], [beta])[0][0]
    work = np.pi * A * row[steady.OUT_TRANSMISSIBILITY] * np.sin(np.radians(row[steady.OUT_PHASE]))
    assert abs(work / row[steady.OUT_FRICTION_ENERGY] - 1) <= 1e-10


def test_energy_balance_with_static_friction():
    """With static above kinetic friction each break-away also dissipates (bs^2 - bk^2)/(2 kappa): the
    massless slider's jump, so that the balance still closes."""
    row = jenkins("base", 1.3, 0.4, 100.0, static_friction_ratio=1.5)[0]
    work = np.pi * row[steady.OUT_TRANSMISSIBILITY] * np.sin(np.radians(row[steady.OUT_PHASE]))
    assert abs(work / row[steady.OUT_FRICTION_ENERGY] - 1) <= 1e-10


def test_stick_from_an_edge_exits_at_the_other():
    """A stick begun where a slip stopped (fc = +bk, on the band's edge) whose swing crosses the band within
    the skip off that edge: the exit is found at the other edge (fc = -bs), not a step beyond it (the skip
    once ignored the other edge, 2 bs / kappa away: fc reached -2 bs, the energy balance missed by 3e-3 and
    DOP853 disagreed by 1e-3 at base r = 1.5, beta = 0.3, kappa = 100)."""
    A, r, beta, kappa = 1.0, 1.5, 0.3, 100.0
    t0, q0 = 1.8050754385783274, 0.7505128927253959  # a reversal of that orbit (velocity zero)
    w = q0 - beta / kappa
    om, rho, zp = jk.stick_scales(r, 0.0, kappa)
    m = w / om**2
    p0, ap, hb = q0 - w + m, A / om**2, beta / kappa
    u, found, edge, _ = jk.band_exit(om * t0, p0, 0.0, m, hb, ap, rho, zp, om * (2 * np.pi / r - t0),
                                     1e-12 * max(ap, abs(p0), hb), min(1.0, 1.0 / rho), 10**6, 0.0)
    assert found and edge == -1 and 0.0 < u < 1.0
    q, _ = jk.stick_state(u / om, t0, q0, 0.0, w, A, r, 0.0, kappa)
    assert abs(kappa * (q - w) / beta + 1.0) <= 1e-9


@pytest.mark.parametrize(("r", "beta", "kappa"), [(2.0, 1.2, 100.0), (0.5, 1.5, 10.0), (3.0, 0.5, 1.0),
                                                  (0.2, 0.05, 0.01)])
def test_slider_that_never_slips_is_the_linear_oscillator(r, beta, kappa):
    """Where kappa x the stuck oscillator's amplitude stays below beta the slider never slips: the forced
    motion of stiffness 1 + kappa, |X|/|Y| = 1/|1 + kappa - r^2|, labelled stuck (the slider's)."""
    assert kappa / abs(1 + kappa - r * r) < beta
    row = event.solve_flat("base", np.array([r]), np.array([beta]), {"contact_stiffness": kappa}, stability=1)[0]
    assert row[steady.OUT_REGIME] == Regime.STUCK
    assert row[js.JOUT_SLIPS] == 0 and np.isnan(row[js.JOUT_FLOQUET])  # the slider's position is neutral
    assert abs(row[steady.OUT_TRANSMISSIBILITY] * abs(1 + kappa - r * r) - 1) <= 1e-12


@pytest.mark.parametrize(("kappa", "beta"), [(3.0, 1.5), (3.0, 5.0), (8.0, 2.0)])
def test_the_stuck_oscillators_resonance_is_bounded(kappa, beta):
    """At r = sqrt(1 + kappa) the stuck oscillator's forced motion is infinite, so the contact force leaves the
    band and the slider slips, dissipating 4 beta (a - beta/kappa) a cycle: a bounded, attracting orbit, not
    `unbounded` (the forcing's work pi A a sin(phase) cannot outgrow it off r = 1). DOP853 agrees."""
    r = np.sqrt(1.0 + kappa)
    row = event.solve_flat("base", np.array([r]), np.array([beta]), {"contact_stiffness": kappa}, stability=1)[0]
    assert row[steady.OUT_REGIME] == Regime.CONTINUOUS and 0.0 < row[steady.OUT_FLOQUET] < 1.0
    ind = jenkins_orbit(1.0, r, beta, beta, kappa, row[steady.OUT_END_Q], row[steady.OUT_END_V], row[js.JOUT_END_W],
                        int(row[steady.OUT_END_MODE]))
    assert ind["amplitude"] == pytest.approx(row[steady.OUT_TRANSMISSIBILITY], rel=1e-8)
    assert ind["slips"] == row[js.JOUT_SLIPS] == 2


# kappa -> oo: the rigid model, at a rate measured here (README, "The Jenkins contact")
KAPPAS = np.array([1e3, 1e4, 1e5])


@pytest.mark.parametrize(("r", "beta", "rate", "spread"), [(1.5, 0.3, 0.5, 0.15), (2.5, 0.2, 0.5, 0.15),
                                                           (0.5, 0.5, 1.0, 0.55), (0.3, 0.6, 1.0, 0.15),
                                                           (0.8, 0.9, 1.0, 0.55)])
def test_converges_to_rigid(r, beta, rate, spread):
    """|T_kappa - T_rigid| falls like kappa^-rate (slopes per decade of kappa within spread of rate) with
    the labels the rigid model's: continuous motion like kappa^-1/2 (each reversal's stick lasts
    ~kappa^-1/2 and delays the friction's flip by as much), stick-slip about like 1/kappa (measured slopes
    0.92, 0.78 at (0.5, 0.5); 1.0 at (0.3, 0.6); 0.94, 1.47 at (0.8, 0.9), kappa 1e3 -> 1e4 -> 1e5)."""
    rigid = event.solve_flat("base", np.array([r]), np.array([beta]))[0]
    rows = np.vstack([jenkins("base", r, beta, k)[0] for k in KAPPAS])
    assert np.all(rows[:, steady.OUT_REGIME] == rigid[steady.OUT_REGIME])
    assert np.all(rows[:, steady.OUT_STOPS_PER_PERIOD] == rigid[steady.OUT_STOPS_PER_PERIOD])
    err = np.abs(rows[:, steady.OUT_TRANSMISSIBILITY] - rigid[steady.OUT_TRANSMISSIBILITY])
    slopes = -np.diff(np.log10(err))
    assert np.all(np.abs(slopes - rate) <= spread), slopes


def test_stuck_region_converges_to_rigid_stuck():
    """beta >= 1 (base): rigid stuck; the slider never slips and the mass vibrates by 1/(1 + kappa - r^2)."""
    rows = jenkins("base", np.array([0.3, 0.9, 2.0]), np.array([1.2, 1.2, 1.2]), 1e4)
    assert np.all(rows[:, steady.OUT_REGIME] == Regime.STUCK)
    assert np.all(rows[:, steady.OUT_TRANSMISSIBILITY] < 2e-4)


def test_rigid_path_unchanged_without_the_effect():
    """No contact_stiffness: the rigid kernels' rows, of their own size (no Jenkins slot, no Jenkins code)."""
    r, beta = np.array([0.3, 1.5]), np.array([0.6, 0.3])
    assert event.solve_flat("base", r, beta).shape == (2, steady.OUT_SIZE)
    assert event.solve_flat("base", r, beta, {"contact_stiffness": 100.0}).shape == (2, js.JOUT_SIZE)


def test_tile_writes_slips_and_floquet():
    tile = event.compute_tile("base", np.array([0.5, 1.5]), np.array([0.0, 0.5]), (*OUTPUTS, "stability"),
                              {"contact_stiffness": 100.0})
    assert {"slips_per_period", "floquet_multiplier"} <= set(tile)
    assert np.isnan(tile["slips_per_period"][0]).all()  # beta = 0: no contact force, nothing slips
    assert np.all(tile["floquet_multiplier"][1] < 1.0)
    plain = event.compute_tile("base", np.array([0.5, 1.5]), np.array([0.0, 0.5]), OUTPUTS)
    assert "slips_per_period" not in plain and "floquet_multiplier" not in plain


@pytest.mark.parametrize("method", ["theory", "paper", "auto"])
def test_methods_without_the_effect_refuse_it(method, tmp_path):
    spec = tmp_path / "s.yaml"
    spec.write_text("scene: {excitation: base, effects: {contact_stiffness: 100}}\n"
                    "grid: {frequency_ratio: [1.0], force_ratio: [0.5]}\n"
                    f"method: {method}\n")
    with pytest.raises(Exception, match="does not model contact_stiffness"):
        load_spec(spec)


def test_a_held_slider_with_damping_settles_on_its_one_period_orbit():
    """A slider that never slips holds the mass on the damped linear oscillator of stiffness 1 + kappa, whose
    forced orbit is unique and of one period: T = 1 / |1 + kappa - r^2 + 2 i zeta r|. Its free motion decays
    at a frequency near 5/3 of the forcing's at r = 2 (kappa 10), so the march's state repeated at lag 3 to
    steady_tol while each period still moved it by a few steady_tol: the kernel called those orbits period 3
    (91 of 1,829 points of a kappa 10, zeta 0.05 plane). A lag k now needs every divisor of k to move the state
    by more than js.DISTINCT times the bound."""
    r = np.linspace(1.7, 2.3, 13)
    kappa, zeta = 10.0, 0.05
    out = event.compute_tile("force", r, [1.5], ("transmissibility", "regime"),
                             {"contact_stiffness": kappa, "viscous_damping": zeta}, {"starts": 1})
    stuck = out["regime"].ravel() == Regime.STUCK
    assert stuck.sum() >= 7  # up to r = 2.05; above it the slider slips
    assert (out["orbit_period"].ravel()[stuck] == 1).all()
    closed = 1.0 / np.abs(1.0 + kappa - r ** 2 + 2j * zeta * r)
    np.testing.assert_allclose(out["transmissibility"].ravel()[stuck], closed[stuck], rtol=1e-10)
