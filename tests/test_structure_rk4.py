"""Issue 31 item 3: method rk4 for structures (kernels/structure/rk4.py): classical RK4 on a fixed grid with the
exact engine's modes (real stick modes: stuck rigid contacts as constraints, stuck Jenkins ones as springs) and
switches, its events located on the step's quintic Hermite interpolant.

Truth is the exact engine (method event, the closed-form flow exp(A t) between events) at a tight steady_tol:
rk4's error against it falls at order 4 in the step, on a continuous and on stick-slip points of a 2-mass
structure with a rigid contact and of one with a Jenkins contact; regimes and stops agree on a plane of several
regimes; a spec with `method: rk4` runs through fsweep run and fs.sweep.

Why the event timing does not dominate: an event is the first root of the event function on the step's
quintic Hermite interpolant, whose error on a step is O(h^6), below RK4's own local O(h^5); the stuck
fraction, which is a sum of event times, converges at order 4 as the amplitude does (asserted below).
"""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

#: the issue's blade and under-platform damper: blade 1, damper 0.1, springs ground-blade 1 and blade-damper 2,
#: a dashpot on the blade, a rigid contact damper-ground, forced at the blade
BLADE = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 0.3),),
                     {"blade": 1.0})
#: 3 masses in a chain, a Jenkins contact (k_t 5) on the middle one, forced at the last
JENKINS = StructureDef("force", {"a": 1.0, "b": 0.5, "c": 1.0},
                       (("ground", "a", 1.0), ("a", "b", 1.0), ("b", "c", 1.0)),
                       (("ground", "a", 0.02), ("ground", "c", 0.02)),
                       (ContactDef("mid", ("b", "ground"), 0.3, 5.0),), {"c": 1.0})
TIGHT = {"steady_tol": 1e-13}
STEPS = np.array([512, 1024, 2048, 4096])


def _slope(steps, err) -> float:
    """The fitted order p of err ~ steps^-p."""
    return -np.polyfit(np.log(steps), np.log(err), 1)[0]


@pytest.mark.nojit_slow
@pytest.mark.parametrize("definition, w, s, regime", [
    (BLADE, 1.0, 0.3, "continuous"), (BLADE, 0.8, 1.0, "stick_slip"), (JENKINS, 0.3, 1.0, "stick_slip"),
])
def test_rk4_converges_at_order_four_to_the_exact_engine(definition, w, s, regime):
    a = assemble(definition)
    w_, s_ = np.array([w]), np.array([s])
    exact = solve_points(a, w_, s_, TIGHT)
    assert Regime(int(exact["regime"][0, 0])).name.lower() == regime
    amp, stuck = [], []
    for n in STEPS:
        r = solve_points(a, w_, s_, {**TIGHT, "steps_per_period": int(n)}, method="rk4")
        assert r["steady_state"][0] == SteadyState.CONVERGED
        amp.append(np.abs(r["amplitude"] - exact["amplitude"]).max())
        stuck.append(abs(r["stuck_fraction"][0, 0] - exact["stuck_fraction"][0, 0]))
    amp_arr = np.array(amp)
    assert amp_arr[-1] > 1e-13  # above the steady state's tolerance: the slope is RK4's, not noise
    assert abs(_slope(STEPS, amp_arr) - 4.0) <= 0.5, amp
    if regime != "continuous":  # the event times converge at the method's order too
        assert abs(_slope(STEPS, np.array(stuck)) - 4.0) <= 0.5, stuck


@pytest.mark.nojit_slow
def test_rk4_finds_the_regimes_and_stops_of_the_exact_engine_on_a_plane():
    W, S = np.meshgrid(np.linspace(0.3, 2.8, 8), np.geomspace(0.1, 10.0, 5), indexing="ij")
    a = assemble(BLADE)
    exact = solve_points(a, W.ravel(), S.ravel())
    # the catalogue's default step count; w = 0.3 is the longest period (the longest step), where the RK4 orbit's
    # energy balance holds to its own order only (rk4.balance_tolerance), not to the exact flow's 1e-6
    r = solve_points(a, W.ravel(), S.ravel(), {"steps_per_period": 256}, method="rk4")
    regimes = set(np.unique(exact["regime"]).tolist())
    assert {int(Regime.STUCK), int(Regime.STICK_SLIP), int(Regime.CONTINUOUS)} <= regimes
    np.testing.assert_array_equal(r["steady_state"], exact["steady_state"])
    np.testing.assert_array_equal(r["regime"], exact["regime"])
    np.testing.assert_array_equal(r["stops_per_period"], exact["stops_per_period"])
    np.testing.assert_allclose(r["amplitude"], exact["amplitude"], rtol=1e-3, atol=1e-7)  # 2.5e-4 at w = 0.3


SPEC = """\
scene: {excitation: force}
structure:
  masses: {blade: 1.0, damper: 0.1}
  springs: [[ground, blade, 1.0], [blade, damper, 2.0]]
  dampers: [[ground, blade, 0.004]]
  contacts:
    - {name: platform, between: [damper, ground], friction: 0.3}
  forcing: {blade: 1.0}
grid:
  frequency: [0.5, 1.0, 1.5]
  friction_scale: [0.3, 3.0]
method: rk4
settings: {steps_per_period: 1024}
"""


def test_a_stuck_contact_is_a_constraint_that_rk4_keeps():
    """Friction far above the forces: the damper stays stuck all period (a constraint RK4 keeps: its relative
    acceleration is zero in the mode's A, so every stage keeps its relative velocity at zero), and the blade is
    the linear blade on springs 1 + 2 (amplitude 1 / |3 - w^2 + 0.004 i w|). The damper's first harmonic is
    its constant position projected on the forcing that RK4 integrates: zero to RK4's error."""
    a = assemble(BLADE)
    w = 1.2
    r = solve_points(a, np.array([w]), np.array([20.0]), {"steps_per_period": 256}, method="rk4")
    assert r["regime"][0, 0] == Regime.STUCK and r["stuck_fraction"][0, 0] == 1.0
    assert r["amplitude"][0, 1] <= 1e-8
    assert r["amplitude"][0, 0] == pytest.approx(1.0 / abs(3.0 - w * w + 0.004j * w), rel=1e-6)


@pytest.mark.nojit_slow
def test_a_structure_spec_runs_with_method_rk4(tmp_path):
    spec = tmp_path / "blade.yaml"
    spec.write_text(SPEC)
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "blade.h5"), "-q"])
    assert res.exit_code == 0, res.output
    cube = fs.open_cube(tmp_path / "blade.h5")
    assert cube.attrs["method"] == "rk4" and '"steps_per_period": 1024' in cube.attrs["method_settings"]
    exact = fs.sweep_yaml(SPEC.replace("method: rk4", "method: event").replace(
        "settings: {steps_per_period: 1024}", "settings: {}"))
    np.testing.assert_array_equal(cube["regime"].values, exact["regime"].values)
    np.testing.assert_allclose(cube["amplitude"].values, exact["amplitude"].values, rtol=1e-6, atol=1e-9)
    np.testing.assert_array_equal(fs.sweep_yaml(SPEC)["amplitude"].values, cube["amplitude"].values)


@pytest.mark.parametrize("method, settings, key", [
    ("rk4", "{stop_tol: 1.0e-9}", "stop_tol"),  # rk4's switches keep event's rounding tolerance (as for one mass)
    ("event", "{steps_per_period: 512}", "steps_per_period"),
    ("rk4", "{steps_per_period: 16}", "steps_per_period"),  # below the catalogue's range
])
def test_a_structure_spec_refuses_settings_its_method_does_not_take(tmp_path, method, settings, key):
    spec = tmp_path / "bad.yaml"
    spec.write_text(SPEC.replace("method: rk4", f"method: {method}").replace(
        "settings: {steps_per_period: 1024}", f"settings: {settings}"))
    res = CliRunner().invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2, res.output
    assert f"settings: {key}" in res.output or f"settings.{key}" in res.output, res.output


def test_the_estimate_of_an_rk4_structure_grows_with_its_steps():
    """fsweep run's estimate (batch.estimate) prices an rk4 point at STRUCTURE_RK4_COST times event's, linear in
    steps_per_period (the measured cost of a fixed grid)."""
    from friction_sweep.batch.estimate import KERNEL_LOAD_SECONDS, STRUCTURE_RK4_COST, estimate
    from friction_sweep.spec import parse_spec_text

    def seconds(text: str) -> float:
        return estimate(parse_spec_text(text), jobs=1, executor="threads", cache=False).seconds

    event = seconds(SPEC.replace("method: rk4", "method: event").replace("settings: {steps_per_period: 1024}",
                                                                           "settings: {}"))
    a, b = STRUCTURE_RK4_COST
    for steps in (256, 1024):
        rk4 = seconds(SPEC.replace("1024", str(steps)))
        assert rk4 > event
        assert (rk4 - KERNEL_LOAD_SECONDS) == pytest.approx((event - KERNEL_LOAD_SECONDS) * (a + b * steps / 256))
