"""Issue 31 item 4: the commands that read a cube read a structure cube. `fsweep info` gives the structure's
natural frequencies (against the closed form of a 2 x 2 eigenproblem); `fsweep check` runs the rules that
carry over (consistency_structure), each passing on cubes the engine wrote and failing on a copy corrupted
where it looks; `fsweep plot` draws each mass's amplitude with a regime strip per contact, and a regime map
per contact (the figure's artists, not its pixels).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir, one_error_line
from structure_specs import two_mass

import friction_sweep as fs
from friction_sweep import consistency_structure as rules
from friction_sweep.cli import main
from friction_sweep.codes import Regime

pytest.importorskip("matplotlib")

#: a blade (1) and a damper (0.1): springs ground-blade 1, blade-damper 2; a rigid contact damper-ground and a
#: Jenkins one (k_t 20) blade-base. friction_scale 0 (linear, contacts free) and 20 (every contact stuck)
FORCE = two_mass(24, "[0.0, 0.5, 20.0]", "[amplitude, phase, regime, friction_energy, harmonics]")
#: base excitation, a dashpot to the base, the rigid contact to the moving base
BASE = """\
scene: {excitation: base}
structure:
  masses: {blade: 1.0, damper: 0.1}
  springs: [[base, blade, 1.0], [blade, damper, 2.0]]
  dampers: [[base, blade, 0.01]]
  contacts:
    - {name: platform, between: [damper, base], friction: 0.3}
    - {name: root, between: [blade, ground], friction: 0.2, stiffness: 20}
  base_amplitude: 0.5
grid:
  frequency: {start: 0.2, stop: 3.0, num: 24}
  friction_scale: [0.0, 0.5, 20.0]
method: event
outputs: [amplitude, phase, regime, friction_energy]
"""
#: static friction 1.5 x kinetic at the Jenkins root: the cube also holds the states from a moving start
STATIC = two_mass(24, "[0.0, 0.5, 1.0, 20.0]", "[amplitude, phase, regime, friction_energy, harmonics]",
                  static_friction_ratio=1.5)
SPECS = {"force": FORCE, "undamped": FORCE.replace("  dampers: [[ground, blade, 0.004]]\n", ""), "base": BASE,
         "base_ground": BASE.replace("[damper, base]", "[damper, ground]"), "static": STATIC}
RULES = {"unsettled", "free_limit", "stuck_limit", "bound", "energy", "harmonics", "history"}


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    folder = tmp_path_factory.mktemp("structure_commands")
    out = {}
    for name, text in SPECS.items():
        (folder / f"{name}.yaml").write_text(text)
        out[name] = folder / f"{name}.h5"
        res = CliRunner().invoke(main, ["run", str(folder / f"{name}.yaml"), "-o", str(out[name]), "-q"])
        assert res.exit_code == 0, res.output
    return out


@pytest.fixture(scope="module")
def cubes(paths):
    return {name: fs.open_cube(path) for name, path in paths.items()}


def findings(ds: xr.Dataset) -> dict:
    return {f.rule: f for f in rules.check(ds)}


# --- info --------------------------------------------------------------------------------------------------


def test_info_gives_the_natural_frequencies_stuck_and_free_and_the_units(paths):
    res = CliRunner().invoke(main, ["info", str(paths["force"])])
    assert res.exit_code == 0, res.output
    # free: det(K - lambda M) = (3 - lambda)(2 - 0.1 lambda) - 4 = 0.1 lambda^2 - 2.3 lambda + 2 = 0
    root = math.sqrt(2.3**2 - 0.8)
    free = sorted(math.sqrt((2.3 + s * root) / 0.2) for s in (-1, 1))
    # stuck: the rigid platform holds the damper; the blade on springs 1 + 2 and the contact's 20
    assert f"natural frequencies, every contact stuck: {math.sqrt(23.0):.6g}\n" in res.output
    assert f"natural frequencies, every contact free: {free[0]:.6g}, {free[1]:.6g}\n" in res.output
    assert "frequency: 0.2 .. 3 (radians per the structure's time unit)" in res.output
    assert "amplitude: (of its absolute displacement; in the structure's own units" in res.output


# --- check -------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(SPECS))
def test_every_rule_passes_on_the_cubes_the_engine_writes(cubes, name):
    found = findings(cubes[name])
    # every rule holds at any steady state: with two starts, on the moving start's states too
    assert set(found) == RULES | ({rule + "_moving" for rule in RULES - {"history"}} if name == "static" else set())
    skipped = {"energy"} if name == "base" else set()  # the contact to the moving base does unrecorded work
    skipped |= {"history"}  # no time history in these cubes (tests/test_structure_history.py)
    if name.startswith("base"):
        skipped |= {"harmonics"}  # not among these cubes' outputs
    for rule, f in found.items():
        assert f.status == ("skipped" if rule in skipped else "ok"), (rule, f)
    assert found["free_limit"].checked == 24  # friction_scale 0, every frequency
    points = cubes[name].sizes["frequency"] * cubes[name].sizes["friction_scale"]  # 24 x 3, static 24 x 4
    assert found["stuck_limit"].checked > 0 and found["bound"].checked == points
    if name == "static":
        assert found["bound_moving"].checked == points and found["stuck_limit_moving"].checked > 0


def test_the_moving_starts_states_are_checked_on_their_own(cubes):
    """A corrupted state from the moving start fails that start's rule only; the state from rest still passes."""
    ds = cubes["static"]
    assert int((ds["steady_states"] >= 2).sum()) > 0  # the grid has points with two states
    found = findings(corrupt(ds, "amplitude_moving", 1e3, friction_scale=0.5, frequency=ds.frequency[3],
                             dof="blade"))
    assert found["bound_moving"].status == "failed" and found["bound_moving"].violations == 1
    assert found["bound"].status == "ok"


def test_info_gives_the_regimes_from_the_moving_start_per_contact(paths):
    res = CliRunner().invoke(main, ["info", str(paths["static"])])
    assert res.exit_code == 0, res.output
    for contact in ("platform", "root"):
        assert f"  regimes at contact {contact}: stuck " in res.output
        assert f"  regimes from a moving start at contact {contact}: stuck " in res.output
    assert "two steady states (from rest and from a moving start): " in res.output


def test_without_zero_friction_or_a_stuck_point_the_linear_limits_say_so(cubes):
    found = findings(cubes["force"].sel(friction_scale=[0.5]))
    assert found["free_limit"].status == "skipped" and "no friction_scale 0" in found["free_limit"].note
    assert found["stuck_limit"].status == "skipped"


def corrupt(ds: xr.Dataset, name: str, factor: float, **where) -> xr.Dataset:
    out = ds.copy(deep=True)
    out[name].loc[where] = out[name].loc[where] * factor
    return out


def stuck_point(ds: xr.Dataset) -> dict:
    every = (ds["regime"] == Regime.STUCK).all("contact")
    s, w = np.argwhere(every.transpose("friction_scale", "frequency").values)[0]
    return {"friction_scale": float(ds["friction_scale"][s]), "frequency": float(ds["frequency"][w])}


@pytest.mark.parametrize("rule, change", [
    ("free_limit", lambda ds: corrupt(ds, "amplitude", 1 + 1e-6, friction_scale=0.0, frequency=ds.frequency[5],
                                      dof="damper")),
    ("free_limit", lambda ds: corrupt(ds, "phase", 1 + 1e-5, friction_scale=0.0, frequency=ds.frequency[7],
                                      dof="blade")),
    ("stuck_limit", lambda ds: corrupt(ds, "amplitude", 1 + 1e-6, dof="blade", **stuck_point(ds))),
    ("bound", lambda ds: corrupt(ds, "amplitude", 1e3, friction_scale=0.5, frequency=ds.frequency[3], dof="blade")),
    ("energy", lambda ds: corrupt(ds, "friction_energy", 3.0, friction_scale=0.5, frequency=ds.frequency[10])),
    ("harmonics", lambda ds: corrupt(ds, "response_harmonic_imag", 1 + 1e-6, friction_scale=0.5,
                                     frequency=ds.frequency[6], dof="damper", harmonic=1)),
    # the platform's force over its square wave's 4/pi mu at the third harmonic
    ("harmonics", lambda ds: corrupt(ds, "friction_harmonic_real", 0.3 * 0.5 * 4 / np.pi / float(np.abs(
        ds["friction_harmonic_real"].sel(friction_scale=0.5, frequency=ds.frequency[9], contact="platform",
                                         harmonic=3))) * 1.01,
        friction_scale=0.5, frequency=ds.frequency[9], contact="platform", harmonic=3)),
])
def test_each_rule_fails_on_a_cube_corrupted_where_it_looks(cubes, rule, change):
    found = findings(change(cubes["force"]))
    assert found[rule].status == "failed" and found[rule].violations == 1, found[rule]
    example = found[rule].examples[0]
    assert set(example) >= {"frequency", "friction_scale", "found", "expected"}


def test_without_dashpots_the_energy_balance_is_an_equality(cubes):
    """Friction energy 1 % short of the forcing's work: no dashpot can take the rest (with one, it could)."""
    point = {"friction_scale": 0.5, "frequency": cubes["undamped"].frequency[10]}
    assert findings(corrupt(cubes["undamped"], "friction_energy", 0.99, **point))["energy"].status == "failed"
    assert findings(corrupt(cubes["force"], "friction_energy", 0.99, **point))["energy"].status == "ok"


def test_an_unsettled_contact_fails_and_names_the_contact(cubes):
    ds = cubes["force"].copy(deep=True)
    ds["regime"].loc[{"friction_scale": 0.5, "frequency": ds.frequency[2], "contact": "root"}] = Regime.UNSETTLED
    f = findings(ds)["unsettled"]
    assert f.status == "failed" and f.violations == 1 and f.examples[0]["at"] == "root"


def test_fsweep_check_reads_a_structure_cube_and_exits_1_on_a_failed_rule(paths, cubes, tmp_path):
    from friction_sweep.storage.cube import write_atomic

    runner = CliRunner()
    res = runner.invoke(main, ["check", str(paths["force"])])
    assert res.exit_code == 0, res.output
    assert "free_limit  ok       24 checked" in res.output and ": ok: 6 ok, 1 skipped" in res.output
    bad = corrupt(cubes["force"], "amplitude", 1e3, friction_scale=0.5, frequency=cubes["force"].frequency[3],
                  dof="blade")
    write_atomic(bad, tmp_path / "bad.h5", overwrite=False)
    res = runner.invoke(main, ["check", str(tmp_path / "bad.h5")])
    assert res.exit_code == 1, res.output
    line = next(x for x in res.output.splitlines() if x.startswith("bound"))
    assert "FAILED" in line and "frequency=" in line and "friction_scale=0.5" in line and "at='blade'" in line


# --- plot --------------------------------------------------------------------------------------------------


def gids(ax) -> set:
    return {a.get_gid() for a in (*ax.lines, *ax.collections) if a.get_gid()}


def test_curves_draw_a_panel_per_mass_a_curve_per_friction_scale_and_a_strip_per_contact(cubes):
    from friction_sweep import quicklook_structure

    ds = cubes["force"]
    fig = quicklook_structure.draw(ds, "curves")
    axes = fig.axes
    panels, strips = axes[:2], axes[2:4]
    for ax, dof in zip(panels, ("blade", "damper"), strict=True):
        assert {f"curve {dof} {row}" for row in range(3)} <= gids(ax)
        for row, s in enumerate((0.0, 0.5, 20.0)):
            (line,) = [x for x in ax.lines if x.get_gid() == f"curve {dof} {row}"]
            np.testing.assert_array_equal(line.get_ydata(), ds["amplitude"].sel(friction_scale=s, dof=dof).values)
    for ax, contact in zip(strips, ("platform", "root"), strict=True):
        regime = ds["regime"].sel(contact=contact).transpose("friction_scale", "frequency").values
        for row in range(3):
            for code in (Regime.STUCK, Regime.STICK_SLIP):
                assert (f"{code.name.lower()} {row}" in gids(ax)) == bool((regime[row] == code).any())
    assert "platform" in strips[0].get_ylabel() and "root" in strips[1].get_ylabel()


def test_curves_take_a_log_axis_where_the_range_is_wide_as_the_1dof_curves(cubes):
    from friction_sweep import quicklook, quicklook_structure

    ds = cubes["force"]
    fig = quicklook_structure.draw(ds, "curves", sel=["dof=blade"])
    wide = quicklook.choose_yscale(ds["amplitude"].sel(dof="blade").values) == "log"
    assert fig.axes[0].get_yscale() == ("log" if wide else "linear")
    assert quicklook_structure.draw(ds, "curves", sel=["dof=blade"], yscale="linear").axes[0].get_yscale() == "linear"


def test_selections_choose_friction_scales_masses_and_contacts(cubes):
    from friction_sweep import quicklook_structure

    fig = quicklook_structure.draw(cubes["force"], sel=["friction_scale=0.4", "dof=damper", "contact=root"])
    assert len(fig.axes) == 2  # the damper's panel, the root's strip
    assert gids(fig.axes[0]) == {"curve damper 0"}  # 0.4 -> nearest 0.5, one curve
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(),
                                  cubes["force"]["amplitude"].sel(friction_scale=0.5, dof="damper").values)


def test_map_draws_a_panel_per_contact_with_its_regime_counts(cubes):
    from friction_sweep import quicklook_structure

    ds = cubes["force"]
    fig = quicklook_structure.draw(ds)  # the default on a plane with regimes
    assert len(fig.axes) == 2
    for ax, contact in zip(fig.axes, ("platform", "root"), strict=True):
        (mesh,) = [c for c in ax.collections if c.get_gid() == f"regime {contact}"]
        assert mesh.get_array().shape == (3, 24)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        regime = ds["regime"].sel(contact=contact).values
        for code in Regime:
            n = int((regime == code).sum())
            name = code.name.lower().replace("_", "-")
            assert (f"{name} ({n})" in labels) == (n > 0), labels


@pytest.mark.parametrize("kind, sel, words", [
    ("orbit", (), "holds no time history"),
    ("map", ("dof=blade",), "does not apply to --kind map"),
    ("curves", ("dof=tip",), "no dof 'tip'"),
    ("curves", ("friction_scale=x",), "is not a number"),
])
def test_bad_requests_are_refused(cubes, kind, sel, words):
    from friction_sweep import quicklook_structure
    from friction_sweep.quicklook import PlotError

    with pytest.raises(PlotError, match=words):
        quicklook_structure.draw(cubes["force"], kind, sel)


@pytest.mark.parametrize("kind", ["map", "curves", "phase"])
def test_fsweep_plot_writes_each_kind_of_a_structure_cube(paths, tmp_path, kind):
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["plot", str(paths["base"]), "--kind", kind, "-o", f"{kind}.png"])
        assert res.exit_code == 0, res.output
        assert (tmp_path / f"{kind}.png").stat().st_size > 0


def test_fsweep_plot_refuses_in_one_line(paths, tmp_path):
    with in_dir(tmp_path):
        line = one_error_line(CliRunner().invoke(main, ["plot", str(paths["base"]), "--kind", "orbit",
                                                        "-o", "o.png"]), 2)
    assert "--kind orbit: the cube holds no time history" in line and not (tmp_path / "o.png").exists()


def test_a_jenkins_contact_without_friction_is_not_labelled_stuck():
    ds = fs.sweep_yaml(FORCE.replace("    - {name: platform, between: [damper, ground], friction: 0.3}\n", "")
                       .replace("num: 24", "num: 4").replace("[0.0, 0.5, 20.0]", "[0.0]"))
    assert (ds["regime"] != Regime.STUCK).all()
    assert findings(ds)["stuck_limit"].status != "failed"
