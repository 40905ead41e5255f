"""Method rk4 with the Jenkins contact (kernels/jenkins_rk4.py) against method event, which solves the same
contact exactly (closed-form pieces): the order of convergence in the step, the labels, the sub-stepped
stick, the budget, and the CLI.

What to expect: the slip and the stick are smooth between events and integrated by classical RK4 (global
error O(h^4)); each event is located on a cubic Hermite interpolant (error O(h^4) in the event's time and
state) once per event, not once per step, so it adds O(h^4) per period too. The transmissibility of the
steady orbit thus converges like h^4: its error falls about 16-fold per doubling of steps_per_period.
Measured (64 -> 512 steps, both kappas): slopes 3.9-4.1, except two held stick-slip points at kappa = 100
where the h^4 term nearly cancels and the error falls faster (4.5, 4.8).
"""

import math

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir
from test_jenkins import CREEPING
from test_jenkins import POINTS as CHECKED

from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import jenkins as jk
from friction_sweep.kernels import jenkins_steady as js
from friction_sweep.kernels import measure as rec
from friction_sweep.kernels import steady
from friction_sweep.kernels.jenkins_rk4 import advance_period_jenkins_rk4, stick_substeps
from friction_sweep.kernels.point import JenkinsPoint
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import event

STEPS = np.array([64, 128, 256, 512])
BUDGET = 10**8


def exact(excitation, r, beta, effects):
    return event.solve_flat(excitation, np.array([r]), np.array([beta]), effects, stability=1)[0]


def rk4(excitation, r, beta, effects, steps, **settings):
    return event.solve_flat(excitation, np.array([r]), np.array([beta]), effects, kernel=KERNEL_RK4,
                            steps_per_period=steps, **{"stability": 1, **settings})[0]


def slope(errors, steps=STEPS):
    """The observed order: minus the slope of log |error| against log steps_per_period."""
    return -np.polyfit(np.log(steps), np.log(np.abs(errors)), 1)[0]


# one point of each regime, the scenes and the effects (regimes at kappa = 10 / 100 per the exact method)
POINTS = [
    ("base", 1.5, 0.3, {}),  # continuous / continuous
    ("base", 0.3, 0.6, {}),  # stick-slip / stick-slip with creeps (6 slips per period)
    ("base", 2.0, 1.5, {}),  # the slider never slips: stuck / stuck
    ("base", 0.5, 0.5, {"viscous_damping": 0.05}),  # damped: continuous / stick-slip
    ("base", 0.5, 0.5, {"static_friction_ratio": 1.5}),  # continuous / stick-slip of period 3
    ("joined", 0.6, 0.3, {}),  # stick-slip / stick-slip
]


@pytest.mark.parametrize("kappa", [10.0, 100.0])
@pytest.mark.parametrize(("excitation", "r", "beta", "effects"), POINTS)
def test_fourth_order_against_the_exact_method(excitation, r, beta, effects, kappa):
    """The steady orbit's transmissibility converges to the exact one at order 4 (3.6 to 5.2: see the module's
    docstring), every doubling of the steps gaining at least 12-fold, with the exact labels, slips, stops and
    orbit period at every step count."""
    effects = {"contact_stiffness": kappa, **effects}
    ref = exact(excitation, r, beta, effects)
    assert ref[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    errors = []
    for n in STEPS:
        row = rk4(excitation, r, beta, effects, n)
        assert row[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
        for slot in (steady.OUT_REGIME, steady.OUT_STOPS_PER_PERIOD, steady.OUT_ORBIT_PERIOD):
            assert row[slot] == ref[slot], (n, slot)
        assert row[js.JOUT_SLIPS] == ref[js.JOUT_SLIPS] or np.isnan(ref[js.JOUT_SLIPS]), n
        errors.append(row[steady.OUT_TRANSMISSIBILITY] / ref[steady.OUT_TRANSMISSIBILITY] - 1.0)
    errors = np.abs(errors)
    assert 3.6 <= slope(errors) <= 5.2, errors
    assert np.all(errors[:-1] / errors[1:] >= 12.0), errors
    assert errors[-1] < 1e-7, errors
    if ref[steady.OUT_REGIME] != Regime.STUCK:
        # the orbit's multipliers: finite differences of a map that converges to the exact one
        assert abs(row[js.JOUT_FLOQUET] - ref[js.JOUT_FLOQUET]) < 1e-4


@pytest.mark.parametrize(("excitation", "r", "beta", "kappa", "effects"), [p[:5] for p in CHECKED] + [CREEPING])
def test_the_independently_checked_points_at_512_steps(excitation, r, beta, kappa, effects):
    """The points test_jenkins.py checks against DOP853 (every regime and scene, kappa 30 to 1000, damping,
    static friction, creeps of a held orbit): at 512 steps rk4 has event's regime, stops, slips and orbit
    period, and its transmissibility and friction energy within 1e-8 (measured: at most 3e-9)."""
    effects = {"contact_stiffness": kappa, **effects}
    ref = exact(excitation, r, beta, effects)
    row = rk4(excitation, r, beta, effects, 512)
    for slot in (steady.OUT_REGIME, steady.OUT_STOPS_PER_PERIOD, js.JOUT_SLIPS, steady.OUT_ORBIT_PERIOD):
        assert row[slot] == ref[slot], slot
    assert abs(row[steady.OUT_TRANSMISSIBILITY] / ref[steady.OUT_TRANSMISSIBILITY] - 1) < 1e-8
    if ref[steady.OUT_REGIME] != Regime.STUCK:
        assert abs(row[steady.OUT_FRICTION_ENERGY] / ref[steady.OUT_FRICTION_ENERGY] - 1) < 1e-8


NONE = np.empty(0)  # no samples


def _on_orbit(p, periods=300):
    """A state on the steady orbit at a period boundary, by the exact kernel."""
    state = (0.0, 0.0, 0.0, 0, math.nan)
    for _ in range(periods):
        state = jk.advance_period_jenkins(*state, p, 1e-12, BUDGET, False, jk.new_jenkins_accumulator(), NONE, NONE,
                                          NONE)[:5]
    return state


def test_one_period_fourth_order_with_the_exact_events():
    """One period of a held stick-slip orbit (kappa = 100, base r = 0.3, beta = 0.6: 6 slips, 4 of them creeps
    from a held stick, 2 stops) from the same state: the end state (q, v, w) converges like h^4 and the
    slips, stops and velocity zeros are the exact kernel's at every step count."""
    p = JenkinsPoint(1.0, 0.3, 0.6, 0.6, 0.0, 0.0, 100.0)
    start = _on_orbit(p)
    acc = jk.new_jenkins_accumulator()
    end = jk.advance_period_jenkins(*start, p, 1e-12, BUDGET, True, acc, NONE, NONE, NONE)
    assert (acc[jk.JACC_SLIPS], acc[rec.ACC_STOPS]) == (6, 2)
    errors = []
    for n in STEPS:
        a = jk.new_jenkins_accumulator()
        got = advance_period_jenkins_rk4(*start, p, int(n), BUDGET, True, a)
        assert got[5] == rec.OK and got[3] == end[3]
        for slot in (jk.JACC_SLIPS, rec.ACC_STOPS, rec.ACC_EVENTS):
            assert a[slot] == acc[slot], (n, slot)
        errors.append(abs(got[0] - end[0]) + abs(got[1] - end[1]) + abs(got[2] - end[2]))
    assert 3.6 <= slope(errors) <= 5.2, errors
    assert errors[-1] < 5e-8, errors


def test_stiff_contact_is_sub_stepped_not_unstable():
    """kappa = 1e4 at r = 0.3: on the slip's grid of 256 steps h Omega = 8.2, beyond RK4's stability bound
    2 sqrt(2); sticks take ceil(Omega) = 101 steps per grid step, so the point converges, with the exact
    labels (70 slips a period, nearly all creeps) and its transmissibility within 1e-6."""
    assert 2 * math.pi / (0.3 * 256) * math.sqrt(1e4 + 1) > 2 * math.sqrt(2)
    assert stick_substeps(1e4) == 101 and stick_substeps(0.001) == 2
    effects = {"contact_stiffness": 1e4}
    ref = exact("base", 0.3, 0.6, effects)
    row = rk4("base", 0.3, 0.6, effects, 256)
    assert row[steady.OUT_STEADY_STATE] == SteadyState.CONVERGED
    assert (row[js.JOUT_SLIPS], row[steady.OUT_STOPS_PER_PERIOD]) == (ref[js.JOUT_SLIPS], 2)
    assert abs(row[steady.OUT_TRANSMISSIBILITY] / ref[steady.OUT_TRANSMISSIBILITY] - 1) < 1e-6


def test_budget_is_a_status_not_an_exception():
    row = rk4("base", 0.3, 0.6, {"contact_stiffness": 100.0}, 256, work_budget=1000)
    assert row[steady.OUT_STEADY_STATE] == SteadyState.EVENT_BUDGET
    assert row[steady.OUT_REGIME] == Regime.UNSETTLED
    acc = jk.new_jenkins_accumulator()
    p = JenkinsPoint(1.0, 0.3, 0.6, 0.6, 0.0, 0.0, 100.0)
    assert advance_period_jenkins_rk4(0.0, 0.0, 0.0, 0, math.nan, p, 256, 10, False, acc)[5] == rec.BUDGET


SPEC = """\
scene: {excitation: base, effects: {contact_stiffness: 100}}
grid: {frequency_ratio: [0.3, 1.5, 2.0], force_ratio: [0.3, 0.6, 1.5]}
method: rk4
outputs: [transmissibility, regime, stability]
output: j.h5
"""


def test_fsweep_run_with_rk4_writes_the_jenkins_variables(tmp_path):
    """`fsweep run` with method rk4 and the effect: the cube has slips_per_period and floquet_multiplier, the
    exact method's labels and slips, and its transmissibility within 1e-6 (256 steps, the default)."""
    (tmp_path / "spec.yaml").write_text(SPEC)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["run", "spec.yaml", "-q"])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(tmp_path / "j.h5", engine="h5netcdf") as ds:
        got = {name: ds[name].values for name in ("transmissibility", "regime", "slips_per_period",
                                                  "floquet_multiplier")}
    ref = event.compute_tile("base", np.array([0.3, 1.5, 2.0]), np.array([0.3, 0.6, 1.5]),
                             ("transmissibility", "regime"), {"contact_stiffness": 100.0})
    assert got["regime"].shape == ref["regime"].shape == (3, 3)
    assert np.array_equal(got["regime"], ref["regime"])
    assert np.array_equal(got["slips_per_period"], ref["slips_per_period"], equal_nan=True)
    slipping = got["slips_per_period"] > 0
    assert slipping.sum() >= 5 and (~slipping).sum() >= 1  # both kinds of point are in the cube
    assert np.all(got["floquet_multiplier"][slipping] < 1.0) and np.all(np.isnan(got["floquet_multiplier"][~slipping]))
    assert np.allclose(got["transmissibility"], ref["transmissibility"], rtol=1e-6, atol=0)
