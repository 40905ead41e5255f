"""Issues 30 and 31: the structure engine's start state. A point solved from a state (x, v, the Jenkins sliders,
each contact's status at the section) instead of rest, its end state (the steady orbit's at the section), and
what rides on them: the second start where static friction exceeds kinetic, stepped-sine sweeps, and time
histories of the steady orbit.

The truths: an orbit's end state is a fixed point of the period map, so a solve started there settles in its
first period with the same numbers; two steady states at one point, both sides of a sweep's jump, and the
sampled orbits are confirmed by the independent hybrid integrator (tests/independent_structure.py, SciPy's
DOP853).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from independent_structure import Automaton, model

import friction_sweep as fs
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.storage.schema import MOVING_SUFFIX
from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points, starts, time_histories

#: the issue's blade with an under-platform damper on one rigid contact (benchmarks/structures.py's BLADE)
BLADE = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 0.3),),
                     {"blade": 1.0})
#: two masses, a Jenkins contact at the root and a rigid one at the tip
JENKINS = StructureDef("force", {"blade": 1.0, "damper": 0.2}, (("ground", "blade", 1.0), ("blade", "damper", 1.0)),
                       (("ground", "blade", 0.03),),
                       (ContactDef("root", ("blade", "ground"), 0.2, 8.0), ContactDef("tip", ("damper", "ground"), 0.1)),
                       {"blade": 1.0})


def test_an_orbit_restarted_from_its_end_state_settles_at_once():
    """The end state is on the steady orbit at the section: from it the first period closes the orbit (the
    march's P(s) = s within steady_tol), and every number agrees with the solve from rest."""
    for d, w in ((BLADE, np.linspace(0.3, 2.8, 12)), (JENKINS, np.linspace(0.4, 2.0, 8))):
        a = assemble(d)
        s = np.ones(w.size)
        rest = solve_points(a, w, s)
        assert (rest["steady_state"] == 0).all()
        again = solve_points(a, w, s, start=rest["end_state"])
        assert (again["steady_state"] == 0).all()
        assert (again["periods"] == 1).all()
        np.testing.assert_allclose(again["amplitude"], rest["amplitude"], rtol=1e-8)
        np.testing.assert_array_equal(again["regime"], rest["regime"])
        np.testing.assert_array_equal(again["stops_per_period"], rest["stops_per_period"])
        np.testing.assert_allclose(again["end_state"], rest["end_state"], rtol=1e-6, atol=1e-9)


def test_a_nan_start_is_rest():
    a = assemble(BLADE)
    w, s = np.array([0.5, 1.2]), np.array([1.0, 1.0])
    rest = solve_points(a, w, s)
    nan = solve_points(a, w, s, start=np.full_like(rest["end_state"], np.nan))
    for name, values in rest.items():
        np.testing.assert_array_equal(nan[name], values, err_msg=name)


#: a forced mass on a rigid contact whose static friction is 3 times its kinetic, a second mass sprung to it: from
#: rest the contact holds the forced mass (its force, the forcing, stays below static friction, and the second
#: mass is never driven), while a mass already slipping keeps slipping (kinetic friction below the forcing)
STATIC = StructureDef("force", {"m1": 1.0, "m2": 0.5}, (("ground", "m1", 1.0), ("m1", "m2", 0.5)),
                      (("ground", "m1", 0.05),), (ContactDef("c", ("m1", "ground"), 0.7, static_friction_ratio=3.0),),
                      {"m1": 1.0})


@pytest.mark.parametrize("w, scale, moving_regime", [(0.5, 0.7, Regime.STICK_SLIP), (1.5, 0.7, Regime.CONTINUOUS)])
def test_two_steady_states_from_two_starts_are_the_independent_integrators(w, scale, moving_regime):
    """From rest the contact never lets go; from the orbit kinetic friction alone sustains it moves. The
    independent hybrid integrator, started the same two ways (its own kinetic orbit's state for the second),
    finds the same two orbits."""
    a = assemble(STATIC)
    rest = solve_points(a, [w], [scale])
    moving = starts.solve_moving(a, [w], [scale])
    assert starts.count_states(rest, moving)[0] == 2
    auto = Automaton(model(STATIC, scale), w)
    z, modes, k = auto.steady()
    ref_rest = auto.measure(z, modes, k)
    kinetic = Automaton(model(replace(STATIC, contacts=tuple(replace(c, static_friction_ratio=1.0)
                                                             for c in STATIC.contacts)), scale), w)
    zk, mk, kk = kinetic.steady()
    z, modes, k = auto.steady(z=zk, modes=mk)
    ref_moving = auto.measure(z, modes, k)
    for got, ref in ((rest, ref_rest), (moving, ref_moving)):
        assert got["steady_state"][0] == SteadyState.CONVERGED
        np.testing.assert_array_equal(got["regime"][0], ref["regime"])
        np.testing.assert_array_equal(got["stops_per_period"][0], ref["stops_per_period"])
        np.testing.assert_allclose(got["amplitude"][0], ref["amplitude"], rtol=1e-8, atol=1e-10)
    assert ref_rest["regime"][0] == Regime.STUCK and ref_moving["regime"][0] == moving_regime


def _spec(ratio: float, starts_setting: int | None = None) -> dict:
    """A spec of the STATIC structure on a small plane through its two-state points."""
    spec = {"scene": {"excitation": "force"},
            "structure": {"masses": {"m1": 1.0, "m2": 0.5}, "springs": [["ground", "m1", 1.0], ["m1", "m2", 0.5]],
                          "dampers": [["ground", "m1", 0.05]],
                          "contacts": [{"name": "c", "between": ["m1", "ground"], "friction": 0.7,
                                        "static_friction_ratio": ratio}],
                          "forcing": {"m1": 1.0}},
            "grid": {"frequency": [0.5, 1.0, 1.5], "friction_scale": [0.7]},
            "outputs": ["amplitude", "regime"]}
    if starts_setting is not None:
        spec["settings"] = {"starts": starts_setting}
    return spec


def test_the_cube_holds_the_moving_start_only_with_static_friction():
    """As in 1-DoF: with static above kinetic friction every variable again from the moving start, and
    `steady_states`, which counts the states the two solves found; without it (or with starts: 1) nothing
    is added, and the variables from rest are the same."""
    two = fs.sweep(_spec(3.0))
    names = ("amplitude", "peak_amplitude", "regime", "stops_per_period", "stuck_fraction", "periods",
             "steady_state", "orbit_period")
    assert set(two.data_vars) == {*names, *(n + MOVING_SUFFIX for n in names), "steady_states"}
    a = assemble(STATIC)
    w, s = np.array([0.5, 1.0, 1.5]), np.full(3, 0.7)
    rest, moving = solve_points(a, w, s), starts.solve_moving(a, w, s)
    np.testing.assert_array_equal(two["steady_states"].values[0], starts.count_states(rest, moving))
    np.testing.assert_array_equal(two["regime_moving"].values[0], moving["regime"])
    np.testing.assert_array_equal(two["amplitude"].values[0], rest["amplitude"])
    assert two["steady_states"].dims == ("friction_scale", "frequency")
    for ratio, setting in ((1.0, None), (3.0, 1)):
        one = fs.sweep(_spec(ratio, setting))
        assert set(one.data_vars) == set(names)
    np.testing.assert_array_equal(one["amplitude"].values, two["amplitude"].values)


#: the blade and a heavy under-platform damper whose static friction is 1.5 times its kinetic: swept at friction
#: scale 2 the damper's motion jumps at different frequencies up and down
SWEPT = StructureDef("force", {"blade": 1.0, "damper": 0.5}, (("ground", "blade", 1.0), ("blade", "damper", 1.0)),
                     (("ground", "blade", 0.05),),
                     (ContactDef("platform", ("damper", "ground"), 0.3, static_friction_ratio=1.5),), {"blade": 1.0})
SWEPT_W = np.linspace(0.6, 2.0, 29)


def _independent_orbit(d, scale, w, end_state):
    """The independent integrator's steady orbit at (w, scale) from an engine state at the section (x, v,
    statuses; rigid contacts only)."""
    auto = Automaton(model(d, scale), w)
    n = len(d.masses)
    x, v, status = end_state[:n], end_state[n:2 * n], end_state[2 * n:]
    z = np.concatenate([x, v, auto.md.W @ x])
    z, modes, k = auto.steady(z=z, modes=status.astype(int))
    return auto.measure(z, modes, k)


def test_stepped_sine_sweeps_jump_at_different_frequencies_up_and_down():
    """Hysteresis: sweeping up the damper keeps stick-slipping, then slipping, to 1.8, where sweeping down it is
    still stuck. At 0.9 both sweeps stick-slip: the up sweep's stuck orbit at 0.85, the member the motion from
    the sweep's state settles on (the engine marched alone from each step's state to each next: the same
    regimes), breaks away there. (An engine that reported the member Newton landed on held it stuck to 0.95.)
    Both orbits at each of these points are steady states of the independent integrator (started from them, it
    stays on them)."""
    a = assemble(SWEPT)
    up = starts.solve_sweep(a, SWEPT_W, 2.0, "up")
    down = starts.solve_sweep(a, SWEPT_W[::-1], 2.0, "down")  # any order in: the sweep sorts
    down = {name: values[::-1] for name, values in down.items()}
    # at 1.35 the only orbit Newton finds repels (multiplier 1.007) and the motion does not settle: the period cap
    cap = np.isclose(SWEPT_W, 1.35)
    for got in (up, down):
        assert (got["steady_state"][~cap] == SteadyState.CONVERGED).all()
        assert (got["steady_state"][cap] == SteadyState.PERIOD_CAP).all()
    for w, want_up, want_down in ((0.9, Regime.STICK_SLIP, Regime.STICK_SLIP), (0.85, Regime.STUCK, Regime.STUCK),
                                  (1.8, Regime.CONTINUOUS, Regime.STUCK)):
        i = int(np.argmin(np.abs(SWEPT_W - w)))
        for got, want in ((up, want_up), (down, want_down)):
            assert got["regime"][i, 0] == want
            ref = _independent_orbit(SWEPT, 2.0, SWEPT_W[i], got["end_state"][i])
            assert ref["regime"][0] == want
            np.testing.assert_array_equal(got["stops_per_period"][i], ref["stops_per_period"])
            np.testing.assert_allclose(got["amplitude"][i], ref["amplitude"], rtol=1e-8, atol=1e-10)
    # away from the jumps the two sweeps agree: one state there
    same = np.abs(up["amplitude"] - down["amplitude"]) <= 1e-6 * np.nanmax(np.abs(up["amplitude"]))
    assert same.all(axis=1).sum() >= 20


def test_a_swept_spec_runs_the_sweep_at_each_friction_scale():
    """`sweep: {direction: up}` (the 1-DoF spec's section) on a structure spec: each friction scale's row of the
    cube is solve_sweep's, no second start (even with static friction), `starts` refused beside it."""
    from friction_sweep.spec.errors import SpecError

    spec = _spec(3.0)
    spec["sweep"] = {"direction": "down"}
    spec["grid"] = {"frequency": [0.5, 0.9, 1.3], "friction_scale": [0.5, 0.7]}
    ds = fs.sweep(spec)
    assert not any(name.endswith(MOVING_SUFFIX) for name in ds.data_vars) and "steady_states" not in ds
    for k, scale in enumerate((0.5, 0.7)):
        row = starts.solve_sweep(assemble(STATIC), [0.5, 0.9, 1.3], scale, "down")
        np.testing.assert_array_equal(ds["amplitude"].values[k], row["amplitude"])
        np.testing.assert_array_equal(ds["regime"].values[k], row["regime"])
    assert '"sweep": "down"' in ds.attrs["method_settings"] and '"starts"' not in ds.attrs["method_settings"]
    spec["settings"] = {"starts": 2}
    with pytest.raises(SpecError) as err:
        fs.sweep(spec)
    assert [p.key for p in err.value.errors] == ["settings.starts"]


def test_a_swept_cube_is_the_same_whatever_the_executor():
    """Tiles of a swept run are blocks of friction scales (4 a tile: 5 scales make two), each scale one
    sequential sweep: the cube does not depend on the workers."""
    spec = _spec(3.0)
    spec["sweep"] = {"direction": "up"}
    spec["grid"] = {"frequency": [0.5, 0.9, 1.3], "friction_scale": [0.3, 0.5, 0.7, 0.9, 1.1]}
    one = fs.sweep(spec)
    two = fs.sweep(spec, jobs=2, executor="processes")
    assert set(one.data_vars) == set(two.data_vars)
    for name in one.data_vars:
        np.testing.assert_array_equal(one[name].values, two[name].values, err_msg=str(name))


@pytest.mark.parametrize("d, w, scale", [(BLADE, 1.2, 1.0), (JENKINS, 0.9, 1.0), (JENKINS, 1.6, 3.0),
                                         (STATIC, 0.5, 0.7)])
def test_time_histories_are_the_independent_integrators_orbit(d, w, scale):
    """Every mass's displacement and every contact's force over the steady orbit, sampled 16 times a period
    from the excitation's maximum: the independent integrator's orbit (from its own steady state) at the same
    instants, to 1e-9 of the orbit's size and of the largest friction."""
    S = 16
    h = time_histories(assemble(d), [[w, scale]], S)
    k = int(h["orbit_period"][0])
    np.testing.assert_array_equal(h["time"][0], np.arange(k * S) / S)
    auto = Automaton(model(d, scale), w)
    z, modes, k_ref = auto.steady()
    assert k_ref == k
    n = len(d.masses)
    size = np.abs(h["displacement"][0]).max()
    friction = max(c.friction * c.static_friction_ratio for c in d.contacts) * scale
    t0 = 0.0
    for q in range(k * S):
        t = q * auto.T / S
        if q:
            _, z, modes = auto.run(t0, z, modes, t)
        t0 = t
        lam = auto.forces(t, z[:n], z[n:2 * n], z[2 * n:], modes)[1]
        np.testing.assert_allclose(h["displacement"][0, q], z[:n], rtol=0, atol=1e-9 * max(size, 1e-300))
        np.testing.assert_allclose(h["contact_force"][0, q], lam, rtol=0, atol=1e-9 * friction)
