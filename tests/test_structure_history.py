"""Issue 31 item 4 (and issue 32 item 4's hysteresis loop) for structures: a spec's `time_history:` section
stores chosen points' steady orbits in the cube (each mass's displacement, each contact's force and relative
displacement), checked against truths the samples do not share: the engine's first harmonics (an FFT of the
samples, to the sampling's aliasing), the friction energy per period (the loop's area, to the trapezoid rule's
order), the contact laws (|lambda| within the static band, exactly +-mu while slipping, zero without friction).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from click.testing import CliRunner
from conftest import in_dir
from structure_specs import two_mass

import friction_sweep as fs
from friction_sweep.batch import structure_sweep
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.spec import load_spec
from friction_sweep.structures import assemble, solve_points

#: the issue's blade and damper: a rigid platform contact and a Jenkins root; a point of each kind of motion
#: (stick-slip at the platform, everything slipping, no friction at all, everything stuck)
POINTS = [[0.8, 1.0], [2.0, 0.1], [1.2, 0.0], [3.0, 10.0]]
SPEC = two_mass(4, "[0.0, 1.0]", "[amplitude, phase, regime, friction_energy, time_history]") + (
    f"time_history: {{points: {POINTS}, samples_per_period: 4096}}\n")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("structure_history")
    (folder / "h.yaml").write_text(SPEC)
    res = CliRunner().invoke(main, ["run", str(folder / "h.yaml"), "-o", str(folder / "h.h5"), "-q"])
    assert res.exit_code == 0, res.output
    spec = load_spec(folder / "h.yaml")
    a = assemble(structure_sweep.structure_def(spec))
    p = np.array(POINTS)
    solved = solve_points(a, p[:, 0], p[:, 1], outputs=("amplitude", "phase", "regime", "friction_energy"))
    return fs.open_cube(folder / "h.h5"), solved, a, folder / "h.h5"


def test_the_cube_holds_each_history_where_the_spec_put_it(run):
    ds, solved, *_ = run
    np.testing.assert_array_equal(ds["history_frequency"].values, [p[0] for p in POINTS])
    np.testing.assert_array_equal(ds["history_friction_scale"].values, [p[1] for p in POINTS])
    assert ds["history_displacement"].dims == ("history_point", "sample", "dof")
    assert ds["history_contact_force"].dims == ("history_point", "sample", "contact")
    assert (ds["history_orbit_period"].values == solved["orbit_period"]).all()
    np.testing.assert_allclose(ds["history_time"].values[:, :4], np.broadcast_to(np.arange(4) / 4096, (len(POINTS), 4)))


def test_the_samples_first_harmonic_is_the_engines_amplitude(run):
    """An FFT of each mass's samples over the orbit gives its first harmonic, to the aliasing of 4,096 samples a
    period (the harmonics of a stick-slip orbit fall like k^-3)."""
    ds, solved, *_ = run
    x = ds["history_displacement"].values  # (point, sample, dof)
    X1 = 2.0 * np.fft.rfft(x, axis=1)[:, 1, :] / x.shape[1]
    # (a mass held still by a stuck contact: no samples move, and the engine's amplitude is rounding, 1e-18)
    np.testing.assert_allclose(np.abs(X1), solved["amplitude"], rtol=1e-7, atol=1e-15)
    moving = solved["amplitude"] > 1e-12  # a phase where the mass moves
    phase = np.degrees(-np.angle(X1))
    np.testing.assert_allclose(((phase - solved["phase"] + 180.0) % 360.0 - 180.0)[moving], 0.0, atol=1e-5)


def test_the_hysteresis_loops_area_is_the_friction_energy(run):
    """Each contact's force against its relative displacement over the period encloses the energy its friction
    dissipates. The trapezoid rule is second order but for the interval holding a rigid contact's stop, where the
    force jumps from mu to the stuck force: (jump / 2) x the slip's last du there, which depends on where the stop
    falls between samples (1.2e-5 of the energy at 1,024 samples a period, 3e-8 at 4,096)."""
    ds, solved, *_ = run
    u = ds["history_relative_displacement"].values
    f = ds["history_contact_force"].values
    u, f = np.concatenate([u, u[:, :1]], axis=1), np.concatenate([f, f[:, :1]], axis=1)  # the closed loop
    area = np.sum(0.5 * (f[:, 1:] + f[:, :-1]) * np.diff(u, axis=1), axis=1)
    np.testing.assert_allclose(area, solved["friction_energy"], rtol=1e-5, atol=1e-12)
    assert (area[:2] > 0).all()


def test_contact_forces_obey_their_laws(run):
    """The rigid platform's force never leaves its band and is +-mu exactly while it slips; without friction
    (the third point) no contact pushes."""
    ds, solved, a, _ = run
    f = ds["history_contact_force"].sel(contact="platform").values
    mu = a.mu[0] * np.array([p[1] for p in POINTS])
    assert (np.abs(f) <= mu[:, None] * (1 + 1e-12)).all()
    everywhere = solved["regime"][1, 0] == Regime.CONTINUOUS  # at w = 2, friction x 0.1 it never sticks
    assert everywhere and np.allclose(np.abs(f[1]), mu[1], rtol=1e-14)
    assert (ds["history_contact_force"].isel(history_point=2).values == 0).all()


def test_the_jenkins_root_obeys_its_law(run):
    """The Jenkins root's force k_t (u - p) never leaves +-mu; where its slider slips at some time the force
    sits at +-mu there, and where it is stuck all period the slider p = u - f / k_t holds still (the law's
    reading of the samples, not the engine's)."""
    ds, solved, a, _ = run
    j = list(ds["contact"].values).index("root")
    f = ds["history_contact_force"].isel(contact=j).values
    u = ds["history_relative_displacement"].isel(contact=j).values * a.amplitude_unit
    mu = a.mu[j] * np.array([p[1] for p in POINTS])
    assert (np.abs(f) <= mu[:, None] * (1 + 1e-12)).all()
    assert {Regime.STUCK, Regime.CONTINUOUS} <= set(solved["regime"][mu > 0, j])  # both branches below are read
    for i, regime in enumerate(solved["regime"][:, j]):
        if mu[i] == 0:
            assert (f[i] == 0).all()
        elif regime == Regime.STUCK:
            slider = u[i] - f[i] / a.kt[j]
            assert np.ptp(slider) <= 1e-12 * np.abs(u[i]).max()
        else:
            assert np.isclose(np.abs(f[i]).max(), mu[i], rtol=1e-14)


#: base excitation with the rigid platform on the moving base: stuck (friction x 20), stick-slip, and slipping
BASE_POINTS = [[1.5, 20.0], [0.8, 0.5], [2.5, 0.5]]
BASE = f"""\
scene: {{excitation: base}}
structure:
  masses: {{blade: 1.0, damper: 0.1}}
  springs: [[base, blade, 1.0], [blade, damper, 2.0]]
  dampers: [[base, blade, 0.01]]
  contacts:
    - {{name: platform, between: [damper, base], friction: 0.3}}
    - {{name: root, between: [blade, ground], friction: 0.2, stiffness: 20}}
  base_amplitude: 0.5
grid:
  frequency: {{start: 0.5, stop: 2.5, num: 2}}
  friction_scale: [0.5]
method: event
outputs: [amplitude, regime, friction_energy, time_history]
time_history: {{points: {BASE_POINTS}, samples_per_period: 4096}}
"""


def test_a_contact_on_the_moving_base_measures_from_the_base(tmp_path):
    """Under base excitation a contact's u is measured from the moving base (u = w . x - Y cos wt), and the
    cube's displacements are over Y (transmissibilities): the platform stuck to the base holds u still while
    its mass moves with the base, the FFT of each mass's samples gives its transmissibility, and each loop's
    area is the friction energy."""
    spec = tmp_path / "b.yaml"
    spec.write_text(BASE)
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "b.h5"), "-q"])
    assert res.exit_code == 0, res.output
    ds = fs.open_cube(tmp_path / "b.h5")
    a = assemble(structure_sweep.structure_def(load_spec(spec)))
    p = np.array(BASE_POINTS)
    solved = solve_points(a, p[:, 0], p[:, 1], outputs=("amplitude", "regime", "friction_energy"))
    assert list(solved["regime"][:, 0]) == [Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS]
    u = ds["history_relative_displacement"].sel(contact="platform").values
    x = ds["history_displacement"].sel(dof="damper").values
    # still against the base to the flow's rounding (1e-12 of Y), while the mass moves with it (2 Y peak to peak)
    assert np.ptp(u[0]) <= 1e-10 and np.ptp(x[0]) > 1.0
    X1 = 2.0 * np.fft.rfft(ds["history_displacement"].values, axis=1)[:, 1, :] / u.shape[1]
    np.testing.assert_allclose(np.abs(X1), solved["amplitude"], rtol=1e-7)
    f = ds["history_contact_force"].values
    assert (np.abs(f) <= (a.mu * p[:, 1:])[:, None, :] * (1 + 1e-12)).all()
    uu = ds["history_relative_displacement"].values * a.amplitude_unit
    uu, f = np.concatenate([uu, uu[:, :1]], axis=1), np.concatenate([f, f[:, :1]], axis=1)
    area = np.sum(0.5 * (f[:, 1:] + f[:, :-1]) * np.diff(uu, axis=1), axis=1)
    np.testing.assert_allclose(area, solved["friction_energy"], rtol=1e-5, atol=1e-12)


def test_where_a_point_holds_two_states_the_history_is_the_rest_starts(tmp_path):
    """With static friction 1.5 x kinetic at the root, the grid point 0.3217... x 1 holds two steady states
    (amplitude and amplitude_moving differ by 5e-3, each the one the engine marched alone from that start
    settles on): the stored orbit, from rest, has the first harmonic of `amplitude`, not of the moving
    start's."""
    spec = tmp_path / "s.yaml"
    spec.write_text(two_mass(24, "[1.0]", "[amplitude, phase, regime, time_history]", static_friction_ratio=1.5)
                    + "time_history: {points: [[0.321739130435, 1.0]], samples_per_period: 2048}\n")
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "s.h5"), "-q"])
    assert res.exit_code == 0, res.output
    ds = fs.open_cube(tmp_path / "s.h5")
    at = ds.sel(frequency=float(ds["history_frequency"][0]), friction_scale=1.0)  # exactly a grid point
    rest, moving = at["amplitude"].values, at["amplitude_moving"].values
    assert int(at["steady_states"]) == 2 and np.abs(rest - moving).max() > 1e-5
    x = ds["history_displacement"].isel(history_point=0).values
    np.testing.assert_allclose(np.abs(2.0 * np.fft.rfft(x, axis=0)[1] / x.shape[0]), rest, rtol=1e-7)


@pytest.mark.parametrize("change, key, reason, at", [
    (("time_history: {points:", "# time_history: {points:"), "outputs", "give `time_history: {points:", "outputs:"),
    ((", time_history]", "]"), "time_history", "not listed in outputs", "time_history:"),
    (("samples_per_period: 4096", "samples_per_period: 4"), "time_history.samples_per_period", "8", "4}"),
    (("[[0.8, 1.0]", "[[-0.8, 1.0]"), "time_history.points[0][0]", "must be > 0", "-0.8,"),
    (("samples_per_period: 4096}", "samples_per_period: 4096}\nsweep: {direction: up}"), "sweep",
     "would not follow the sweep", "sweep:"),
])
def test_spec_errors_name_the_key(tmp_path, change, key, reason, at):
    """file:line:column: key: reason, exit 2, no cube; the line and column point at the offending text."""
    spec = tmp_path / "bad.yaml"
    text = SPEC.replace(*change)
    assert text != SPEC
    spec.write_text(text)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["run", str(spec), "-o", "bad.h5"])
        assert res.exit_code == 2 and isinstance(res.exception, SystemExit), res.output
        where = re.search(rf"^{re.escape(str(spec))}:(\d+):(\d+): {re.escape(key)}: .*{re.escape(reason)}",
                          res.stderr, re.M)
        assert where, res.stderr
        line, column = int(where[1]), int(where[2])
        assert text.splitlines()[line - 1][column - 1:].startswith(at), res.stderr
        assert not (tmp_path / "bad.h5").exists()


PHYSICAL = """\
scene: {excitation: force}
structure:
  masses: {blade: 2 kg, damper: 0.25 kg}
  springs: [[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]
  dampers: [[ground, blade, 4 N*s/m]]
  contacts:
    - {name: platform, between: [damper, ground], friction: 8 N}
  forcing: {blade: 30 N}
grid:
  frequency: {start: 10 Hz, stop: 60 Hz, num: 6}
  friction_scale: [0.5, 1.0]
outputs: [amplitude, time_history]
time_history: {points: [[25 Hz, 1.0], [1200 rpm, 0.5]], samples_per_period: 64}
"""


def test_a_physical_structures_points_carry_their_unit(tmp_path):
    """A physical structure's points give their frequency with a unit, as its grid does: the cube's
    history_frequency is the engine's (over reference_frequency, as `frequency`), history_frequency_hz the
    written one, and the samples those of the engine at that frequency (structures.time_histories); a point
    without its unit is refused, located."""
    from friction_sweep.structures import time_histories

    spec = tmp_path / "p.yaml"
    spec.write_text(PHYSICAL)
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "p.h5"), "-q"])
    assert res.exit_code == 0, res.output
    ds = fs.open_cube(tmp_path / "p.h5")
    # (the engine's frequency is rounded to 12 significant digits, as the grid's: spec.system.ratios)
    np.testing.assert_allclose(ds["history_frequency_hz"].values, [25.0, 20.0], rtol=1e-12)
    w0 = float(ds["reference_frequency"])
    np.testing.assert_allclose(ds["history_frequency"].values, 2 * np.pi * np.array([25.0, 20.0]) / w0, rtol=1e-11)
    parsed = load_spec(spec)
    h = time_histories(assemble(structure_sweep.structure_def(parsed)), parsed.history_points, 64)
    np.testing.assert_array_equal(ds["history_displacement"].values, h["displacement"])
    spec.write_text(PHYSICAL.replace("[[25 Hz, 1.0]", "[[25.0, 1.0]"))
    res = CliRunner().invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2 and ": time_history.points[0][0]: a physical structure's point gives its frequency " \
        "with a unit" in res.stderr, res.output


def test_fsweep_plot_draws_a_stored_orbit_and_its_loops(run, tmp_path):
    """--kind orbit: a panel per mass (its displacement against time) and a panel per contact (its force against
    its relative displacement, the loop closed over the orbit); history_point picks the orbit."""
    from friction_sweep import quicklook_structure

    ds = run[0]
    fig = quicklook_structure.draw(ds, "orbit", ("history_point=1", "contact=platform"))
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.lines}
    assert set(lines) == {"orbit blade", "orbit damper", "loop platform"}
    u, f = lines["loop platform"].get_data()
    np.testing.assert_array_equal(u, np.append(ds["history_relative_displacement"].isel(history_point=1).sel(
        contact="platform").values, u[0]))
    assert u[0] == u[-1] and f[0] == f[-1]
    assert quicklook_structure.default_kind(ds, ("history_point=2",)) == "orbit"
    with pytest.raises(quicklook_structure.PlotError, match="holds histories 0..3"):
        quicklook_structure.draw(ds, "orbit", ("history_point=4",))
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["plot", str(run[3]), "--kind", "orbit", "-o", "o.png"])
        assert res.exit_code == 0, res.output
        assert (tmp_path / "o.png").stat().st_size > 0


def test_fsweep_check_holds_each_stored_contact_force_in_its_band(run):
    """Rule `history`: the cube's stored forces pass; one sample pushed 1 % past the platform's static band
    fails it, named by its history point, contact and sample."""
    from friction_sweep import consistency_structure as rules

    ds = run[0]
    found = {f.rule: f for f in rules.check(ds)}
    assert found["history"].status == "ok" and found["history"].checked == len(ds["history_frequency"])
    bad = ds.copy(deep=True)
    bound = float(bad["history_friction_scale"][0]) * 0.3
    bad["history_contact_force"][0, 10, 0] = 1.01 * bound
    f = {f.rule: f for f in rules.check(bad)}["history"]
    assert f.status == "failed" and f.violations == 1
    assert f.examples[0]["history_point"] == 0 and f.examples[0]["at"] == "platform, sample 10"


def test_fsweep_info_lists_the_stored_orbits(run):
    """fsweep info names each stored orbit: where it lies and its periods."""
    res = CliRunner().invoke(main, ["info", str(run[3])])
    assert res.exit_code == 0, res.output
    periods = run[0]["history_orbit_period"].values
    assert (periods >= 1).all()
    listed = ", ".join(f"{p[0]:g}, {p[1]:g}: {k:g}" for p, k in zip(POINTS, periods, strict=True))
    assert f"  time histories (frequency, friction_scale: orbit periods): {listed}\n" in res.output
