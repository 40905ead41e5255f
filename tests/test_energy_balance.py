"""Issue 28, class 1: a steady state is one only if it balances its energy per period, and the damping
ratio has a floor below which doubles cannot tell a dashpot from none.

Truths independent of the code under test: the linear oscillator's closed forms at beta = 0 (DESIGN.md
§6: to the ground |X|/|Y| = 1/|1 - r^2 + 2i zeta r|; spring-parallel sqrt(1 + (2 zeta r)^2) times that), and
the energies per period that tests/independent_integrator.py integrates by quadrature.
"""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from independent_integrator import steady_orbit

from friction_sweep import catalogue, consistency
from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import period_map, shoot
from friction_sweep.methods import event
from friction_sweep.storage import cube, provenance

FLOOR = catalogue.VISCOUS_DAMPING_FLOOR


def _cube(excitation, r, beta, outputs, effects, method="event", **settings):
    """A cube as `fsweep run` labels it, computed by the method directly (no spec: a damping below the
    floor reaches the kernel as it did before the floor)."""
    from friction_sweep.methods import rk4

    module = rk4 if method == "rk4" else event
    arrays = module.compute_tile(excitation, r, beta, outputs, effects, settings or None)
    recorded = {**catalogue.method(method).defaults, **settings,
                "effects": catalogue.resolved_effects(excitation, effects)}
    return cube.build_dataset(
        arrays, frequency_ratio=np.asarray(r, float), force_ratio=np.asarray(beta, float), excitation=excitation,
        title="t", history=provenance.history_line("test"),
        attrs=provenance.attributes(spec_text="", spec_path="s.yaml", excitation=excitation, method=method,
                                    settings=recorded))


def _energy(ds):
    return next(f for f in consistency.check(ds) if f.rule == "energy")


def _linear(excitation, place, r, zeta):
    """|X|/|Y| of the linear oscillator (beta = 0), DESIGN.md §6."""
    gain = 1.0 / np.abs((1 - r) * (1 + r) + 2j * zeta * r)
    if excitation == "joined":  # x = z + y with z'' + 2 zeta z' + z = r^2 cos: |1 + r^2 G| = |1 + 2i zeta r| G
        return np.abs(1 + 2j * zeta * r) * gain
    return np.hypot(1.0, 2 * zeta * r) * gain if place == "base" else gain


# ---- the floor ----------------------------------------------------------------------------------------

def test_the_floor_is_where_the_kernel_still_resolves_resonance():
    """At the floor the resonant orbit (r = 1, beta = 0: 1/(2 zeta) = 5e5) is inside what the kernel
    resolves (|(J - I)^-1| x rounding below shoot.RESOLVABLE), and the check's restated rounding is the
    kernel's."""
    assert consistency.MAP_ROUNDING == period_map.MAP_ROUNDING
    assert math.sqrt(2) / (2 * math.pi * FLOOR) * period_map.MAP_ROUNDING <= shoot.RESOLVABLE
    # exp(-2 pi zeta) is distinguishable from 1 by ten decades at the floor
    assert 1.0 - math.exp(-2 * math.pi * FLOOR) > 1e10 * np.finfo(float).eps


@pytest.mark.parametrize("excitation, place", [("force", "ground"), ("base", "ground"), ("base", "base"),
                                               ("joined", "base")])
def test_at_the_floor_resonance_is_the_linear_closed_form(excitation, place):
    """Every point within 30 zeta of resonance is answered (main left r = 1 + zeta .. 1 + 1.3 zeta
    `unsettled`: shooting held the linear orbit, which sits on the forced bound, to 1e-9 while Newton
    lands within steady_tol |(J - I)^-1| of it), to that accuracy: 1e-10 / (2 pi zeta) ~ 1.6e-5 at most,
    measured 7e-8."""
    r = np.concatenate((1 + np.linspace(-30, 30, 121) * FLOOR, [0.5, 2.0]))
    effects = {"viscous_damping": {"ratio": FLOOR, "to": place}}
    ds = _cube(excitation, r, [0.0], ("transmissibility", "phase", "regime"), effects)
    T = ds["transmissibility"].values[0]
    np.testing.assert_allclose(T, _linear(excitation, place, r, FLOOR), rtol=1e-6)
    assert _energy(ds).status == consistency.OK


#: what main wrote at r = 1 for the issue's spec (base, zeta = 1e-18, beta = 0): T = 68 where the exact
#: value is 1/(2 zeta) = 5e17, labelled converged and continuous
MAIN_WRONG_ORBIT = {"transmissibility": 68.02467467134679, "phase": -63.11680981, "regime": Regime.CONTINUOUS,
                    "steady_state": SteadyState.CONVERGED}


def _as_main_wrote(ds):
    """The issue's cube with r = 1 as main wrote it (the kernel now refuses that orbit)."""
    ds = ds.copy(deep=True)
    for name, value in MAIN_WRONG_ORBIT.items():
        ds[name].loc[{"frequency_ratio": 1.0, "force_ratio": 0.0}] = value
    return ds


def test_check_fails_the_wrong_orbit_main_wrote():
    r = [0.999999, 1.0, 1.000001]
    ds = _as_main_wrote(_cube("base", r, [0.0], ("transmissibility", "phase", "regime"),
                              {"viscous_damping": 1e-18}))
    finding = _energy(ds)
    assert finding.status == consistency.FAILED and finding.violations == 1
    assert finding.examples[0]["r"] == 1.0


@pytest.mark.parametrize("excitation, place", [("force", "ground"), ("base", "ground"), ("base", "base"),
                                               ("joined", "base")])
@pytest.mark.parametrize("method", ["event", "rk4"])
def test_the_kernel_refuses_orbits_that_do_not_balance(excitation, place, method):
    """Below the floor (reachable from the kernels' API, not from a spec) every point next to resonance
    is the linear closed form or `unsettled`; at r = 1, where main answered 68, 1020, ... for 5e17, 5e18,
    ..., the orbit found fails the energy balance and is labelled `unbalanced`."""
    r = np.array([0.999999, 1.0, 1.000001])
    for zeta in (1e-20, 1e-19, 1e-18, 1e-17):
        ds = _cube(excitation, r, [0.0], ("transmissibility", "phase", "regime"),
                   {"viscous_damping": {"ratio": zeta, "to": place}}, method)
        T, regime = ds["transmissibility"].values[0], ds["regime"].values[0]
        right = np.abs(T / _linear(excitation, place, r, zeta) - 1) <= 1e-6
        assert np.all(right | (regime == Regime.UNSETTLED)), (zeta, T, regime)
        assert not right[1] and ds["steady_state"].values[0, 1] in (SteadyState.UNBALANCED, SteadyState.PERIOD_CAP)
        assert _energy(ds).status == consistency.OK


@pytest.mark.parametrize("zeta", [1e-20, 1e-19, 1e-18, 1e-17])
@pytest.mark.parametrize("excitation", ["force", "joined"])
def test_every_tiny_damping_of_the_issue_is_refused_or_failed(zeta, excitation, tmp_path):
    """Each damping of the issue (1e-20 ... 1e-17) is refused by the spec with file:line:column, and the
    kernel, reached without a spec, labels r = 1 `unsettled` instead of answering a wrong orbit."""
    spec = tmp_path / "s.yaml"
    spec.write_text(f"scene: {{excitation: {excitation}, effects: {{viscous_damping: {zeta!r}}}}}\n"
                    "grid: {frequency_ratio: [1.0], force_ratio: [0]}\nmethod: event\noutput: o.h5\n")
    res = CliRunner().invoke(main, ["validate", str(spec)])
    assert res.exit_code == 2
    assert f"{spec}:1:" in res.output and "scene.effects.viscous_damping: must be 0 or at least 1e-06" in res.output
    ds = _cube(excitation, [1.0], [0.0], ("transmissibility", "phase", "regime"), {"viscous_damping": zeta})
    assert ds["regime"].values[0, 0] == Regime.UNSETTLED  # and the kernel, reached without a spec, refuses


@pytest.mark.parametrize("refused", [9.99e-7, 1e-10, 5e-324])
def test_the_spec_takes_zero_or_the_floor_upwards(refused, tmp_path):
    def validate(value):
        spec = tmp_path / "s.yaml"
        spec.write_text(f"scene: {{excitation: base, effects: {{viscous_damping: {{ratio: {value!r}, to: base}}}}}}\n"
                        "grid: {frequency_ratio: [1.0], force_ratio: [0]}\nmethod: event\noutput: o.h5\n")
        return CliRunner().invoke(main, ["validate", str(spec)])

    res = validate(refused)
    assert res.exit_code == 2 and "scene.effects.viscous_damping.ratio: must be 0 or at least 1e-06" in res.output
    assert res.output.startswith("fsweep: error: invalid spec\n") and len(res.output.splitlines()) == 2
    for allowed in (0, 0.0, FLOOR, 0.05):
        assert validate(allowed).exit_code == 0, allowed


def test_the_api_refuses_a_damping_below_the_floor():
    import friction_sweep as fs
    from friction_sweep.errors import FsweepError

    with pytest.raises(FsweepError, match="at least 1e-06"):
        fs.sweep({"scene": {"excitation": "base", "effects": {"viscous_damping": 1e-18}},
                  "grid": {"frequency_ratio": [1.0], "force_ratio": [0]}, "method": "event"})


# ---- the energy rule ----------------------------------------------------------------------------------

def test_energy_terms_match_an_independent_integration():
    """W = pi A T sin(phi) and the stored friction energy are the forcing's work and the friction's
    dissipation that an independent integrator finds by quadrature (base, dashpot to the base, stick-slip
    and continuous points); the viscous loss exceeds the first harmonic's, as the rule's inequality says."""
    zeta = 0.05
    effects = {"viscous_damping": {"ratio": zeta, "to": "base"}}
    r, beta = np.array([0.6, 1.5]), np.array([0.3])
    ds = _cube("base", r, beta, ("transmissibility", "phase", "regime", "friction_energy"), effects)
    cube_ = consistency._read(ds)
    W, V1, _ = consistency.energy_terms(cube_, ds["transmissibility"].values, ds["phase"].values)
    for i, ri in enumerate(r):
        ref = steady_orbit(1.0, ri, 0.3, 0.3, 0.0, 0.0, zeta=zeta, base_dashpot=True)["energies"]
        assert W[0, i] == pytest.approx(ref["forcing"], rel=1e-6)
        assert ds["friction_energy"].values[0, i] == pytest.approx(ref["friction"], rel=1e-6)
        assert V1[0, i] <= ref["viscous"] * (1 + 1e-6)
        assert ref["forcing"] == pytest.approx(ref["friction"] + ref["viscous"], rel=1e-6)
    assert _energy(ds).status == consistency.OK


@pytest.mark.parametrize("excitation, effects, method", [
    ("base", {}, "event"),
    ("joined", {}, "event"),
    ("force", {"viscous_damping": 0.05}, "event"),
    ("joined", {"viscous_damping": 0.02}, "event"),
    ("base", {"static_friction_ratio": 1.5}, "event"),
    ("base", {"viscous_damping": 0.05}, "rk4"),
    ("base", {"contact_stiffness": 100.0}, "event"),
])
def test_correct_cubes_pass_and_a_planted_phase_fails(excitation, effects, method):
    r = np.array([0.3, 0.5, 0.8, 0.999, 1.0, 1.2, 2.0])
    beta = np.array([0.0, 0.05, 0.3, 0.8])
    ds = _cube(excitation, r, beta, ("transmissibility", "phase", "regime", "friction_energy"), effects, method)
    finding = _energy(ds)
    assert finding.status == consistency.OK and finding.checked > 0, finding
    moved = ds["transmissibility"].values[2, 2] > 0 and ds["regime"].values[2, 2] != 0
    assert moved
    ds["phase"].values[2, 2] -= 2.0  # two degrees less lag (r < 1): the forcing's work no longer pays for the loss
    bad = _energy(ds)
    assert bad.status == consistency.FAILED and bad.violations == 1
    assert (bad.examples[0]["r"], bad.examples[0]["beta"]) == (0.8, 0.3)


def test_a_friction_energy_one_part_in_a_million_off_fails_without_damping():
    r, beta = np.array([0.5, 0.8, 2.0]), np.array([0.1, 0.3])
    ds = _cube("base", r, beta, ("transmissibility", "phase", "regime", "friction_energy"), {})
    assert _energy(ds).status == consistency.OK
    ds["friction_energy"].values[1, 1] *= 1 + 1e-6
    assert _energy(ds).violations == 1


def test_negative_dissipation_fails_where_friction_energy_is_not_stored():
    """Without friction_energy (the default outputs) the rule still checks W >= V1: an orbit that takes
    energy out of the forcing it is driven by is no steady state."""
    ds = _cube("base", np.array([0.8]), np.array([0.3]), ("transmissibility", "phase", "regime"),
               {"viscous_damping": 0.05})
    assert _energy(ds).status == consistency.PARTIAL  # beta > 0: only W >= V1 is known
    ds["phase"].values[0, 0] = -ds["phase"].values[0, 0]
    assert _energy(ds).status == consistency.FAILED


def test_the_rule_skips_methods_without_a_stated_accuracy():
    ds = _cube("base", np.array([0.8]), np.array([0.3]), ("transmissibility", "phase", "regime"), {})
    ds.attrs["method"] = "paper"
    finding = _energy(ds)
    assert finding.status == consistency.SKIPPED and "paper" in finding.note


def test_check_reports_the_energy_rule_in_json(tmp_path):
    ds = _cube("base", np.array([0.8]), np.array([0.3]), ("transmissibility", "phase", "regime"),
               {"viscous_damping": 0.05})
    ds["phase"].values[0, 0] = -ds["phase"].values[0, 0]  # the forcing's work now negative
    path = tmp_path / "wrong.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    res = CliRunner().invoke(main, ["check", str(path), "--json"])
    assert res.exit_code == 1
    found = {f["rule"]: f for f in json.loads(res.output)}
    assert found["energy"]["status"] == "failed" and found["energy"]["violations"] == 1


def test_a_cube_with_a_damping_below_the_floor_is_refused_by_every_reader(tmp_path):
    """Main's cube of the issue (zeta = 1e-18) records a damping no run writes now (issue 28 round 2: the
    reader audits the effects against the catalogue): refused, exit 2, before any rule."""
    ds = _as_main_wrote(_cube("base", [0.999999, 1.0, 1.000001], [0.0], ("transmissibility", "phase", "regime"),
                              {"viscous_damping": 1e-18}))
    path = tmp_path / "wrong.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    for command in ("check", "info"):
        res = CliRunner().invoke(main, [command, str(path)])
        assert res.exit_code == 2 and "effect viscous_damping is not a number in 0 or [1e-06, 1): 1e-18" in res.output


@pytest.mark.parametrize("steady_tol", ['"abc"', "true", "-1", "1e300", "null"])
def test_a_cube_whose_settings_are_not_numbers_is_refused_not_a_traceback(steady_tol, tmp_path):
    ds = _cube("base", np.array([0.8]), np.array([0.3]), ("transmissibility", "phase", "regime"), {})
    settings = json.loads(ds.attrs["method_settings"])
    settings["steady_tol"] = json.loads(steady_tol)
    ds.attrs["method_settings"] = json.dumps(settings)
    path = tmp_path / "c.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    res = CliRunner().invoke(main, ["check", str(path)])
    assert res.exception is None or isinstance(res.exception, SystemExit), res.output
    assert res.exit_code == 2 and "method_settings: steady_tol is not a number in [1e-13, 1e-06]" in res.output


# ---- issue 28, round 2: cube readers and check ------------------------------------------------------------

@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_without_friction_energy_the_rule_says_partial_not_ok(zeta):
    """Finding 3: on a default cube (no friction_energy) a transmissibility 1.5 times too large at beta > 0
    passed `energy` as "ok" (only W >= V1 was checked there, W >= 0 at zeta = 0). The rule now judges in
    full only where F is known (beta = 0, stuck) and says `partial` with the count and the cure; with
    friction_energy the same corruption fails (at zeta = 0, where the balance is an equality)."""
    effects = {"viscous_damping": zeta} if zeta else {}
    r, beta = np.array([0.5, 0.8, 1.5]), np.array([0.0, 0.3])
    plain = _cube("base", r, beta, ("transmissibility", "phase", "regime"), effects)
    plain["transmissibility"].values[1, 1] *= 1.5
    finding = _energy(plain)
    assert finding.status == consistency.PARTIAL and finding.violations == 0
    assert finding.note.startswith("3 of 6 points") and "add friction_energy to outputs" in finding.note
    full = _cube("base", r, beta, ("transmissibility", "phase", "regime", "friction_energy"), effects)
    assert _energy(full).status == consistency.OK
    full["transmissibility"].values[1, 1] *= 1.5
    finding = _energy(full)
    if zeta == 0.0:  # the balance is an equality: the corruption fails (with damping W >= F + V1 may still hold)
        assert finding.status == consistency.FAILED and finding.violations == 1 and finding.examples[0]["r"] == 0.8


def test_check_prints_the_partial_rule_with_its_reason(tmp_path):
    ds = _cube("base", np.array([0.8]), np.array([0.0, 0.3]), ("transmissibility", "phase", "regime"), {})
    path = tmp_path / "c.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    res = CliRunner().invoke(main, ["check", str(path)])
    assert res.exit_code == 0, res.output
    line = next(x for x in res.output.splitlines() if x.startswith("energy"))
    assert line.split()[1] == "partial" and "1 of 2 points" in line and "add friction_energy to outputs" in line
    assert "1 partial" in res.output.splitlines()[-1]
