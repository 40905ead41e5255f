"""Where the viscous damper sits: `viscous_damping: {ratio: zeta, to: ground | base}` (docs/equations.md §6).

Truths used here: the linear closed forms at beta = 0 (derived below, not read from the code), the
independent integrator (tests/independent_integrator.py, which integrates the spring-parallel
dashpot's forcing cos(r t) - 2 zeta r sin(r t) as it stands, in the base's own time) and the spec
layer's error contract (file:line:col: key: reason, exit 2).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from independent_integrator import steady_orbit

from friction_sweep import api, consistency
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.methods import event, rk4
from friction_sweep.spec import SpecError, parse_spec_text
from friction_sweep.storage import cube, provenance

ALL = ("transmissibility", "phase", "regime")
ZETA = 0.1


def damper(to: str, zeta: float = ZETA) -> dict:
    return {"viscous_damping": {"ratio": zeta, "to": to}}


def linear(to: str, r, zeta):
    """Complex amplitude X/Y of x'' + 2 zeta x' + x = forcing at beta = 0, y = cos(r t) = Re e^{irt}:
    dashpot to the ground, forcing y: X (1 - r^2 + 2i zeta r) = 1; spring-parallel, forcing y + 2 zeta y':
    X (1 - r^2 + 2i zeta r) = 1 + 2i zeta r."""
    numerator = 1.0 + 2j * zeta * r if to == "base" else 1.0
    return numerator / (1.0 - r**2 + 2j * zeta * r)


def wrapped(degrees):
    return (np.asarray(degrees) + 90.0) % 360.0 - 90.0


# --- beta = 0: the linear closed forms -------------------------------------------------------------


def test_the_closed_forms_quoted_in_the_docs_are_the_complex_amplitudes():
    """|X|/|Y| = sqrt(1 + (2 zeta r)^2) / |1 - r^2 + 2i zeta r| and the lag atan2(2 zeta r^3, 1 - r^2 +
    4 zeta^2 r^2) (from (1 - r^2 + 2i zeta r)(1 - 2i zeta r), the denominator times the conjugate numerator)
    for the spring-parallel dashpot; 1/|1 - r^2 + 2i zeta r| and atan2(2 zeta r, 1 - r^2) to the ground."""
    r = np.linspace(0.05, 5.0, 200)
    for zeta in (0.01, 0.1, 0.5):
        X = linear("base", r, zeta)
        np.testing.assert_allclose(np.abs(X), np.sqrt(1 + (2 * zeta * r) ** 2)
                                   / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2), rtol=1e-13)
        np.testing.assert_allclose(-np.angle(X), np.arctan2(2 * zeta * r**3, 1 - r**2 + 4 * zeta**2 * r**2),
                                   atol=1e-13)
        G = linear("ground", r, zeta)
        np.testing.assert_allclose(-np.angle(G), np.arctan2(2 * zeta * r, 1 - r**2), atol=1e-13)
        # r = sqrt(2) is where every spring-parallel damper transmits 1; above it the damper raises the
        # transmissibility over the undamped one, below it lowers it; the ground damper lowers it everywhere
        above, below = r > np.sqrt(2) + 1e-9, r < np.sqrt(2) - 1e-9
        undamped = 1 / np.abs(1 - r**2)
        assert np.all(np.abs(X[above]) > undamped[above]) and np.all(np.abs(X[below]) < undamped[below])
        assert np.all(np.abs(G) < undamped)


R_LINEAR = np.array([0.3, 0.8, 1.0, 1.3, np.sqrt(2), 2.0, 3.0])


@pytest.mark.parametrize("method, rtol, atol_deg", [(event, 1e-10, 1e-8), (rk4, 1e-6, 1e-4)], ids=["event", "rk4"])
@pytest.mark.parametrize("to", ["ground", "base"])
@pytest.mark.parametrize("zeta", [0.05, 0.2])
def test_each_attachment_is_its_linear_oscillator_without_friction(compiled, method, rtol, atol_deg, to, zeta):
    out = method.compute_tile("base", R_LINEAR, np.array([0.0]), ALL, effects=damper(to, zeta))
    X = linear(to, R_LINEAR, zeta)
    lag = wrapped(np.degrees(-np.angle(X)))
    for name in ("transmissibility", "peak_transmissibility"):  # a sinusoid: peak = first harmonic
        np.testing.assert_allclose(out[name][0], np.abs(X), rtol=rtol, err_msg=name)
    for name in ("phase", "peak_phase"):
        np.testing.assert_allclose(out[name][0], lag, atol=atol_deg, err_msg=name)
    assert np.all(out["regime"][0] == Regime.CONTINUOUS) and np.all(out["orbit_period"][0] == 1)
    if to == "base":  # the crossing point, whatever zeta
        assert out["transmissibility"][0, 4] == pytest.approx(1.0, rel=rtol)


def test_without_friction_the_spring_parallel_damper_moves_the_mass_as_the_joined_scene_does(compiled):
    """z = x - y obeys z'' + 2 zeta z' + z = r^2 cos(r t) in both: x = z + y is the same motion."""
    r = np.array([0.5, 1.0, 2.0])
    base = event.compute_tile("base", r, np.array([0.0]), ALL, effects=damper("base"))
    joined = event.compute_tile("joined", r, np.array([0.0]), ALL, effects=damper("base"))
    for name in ("transmissibility", "peak_transmissibility", "phase", "peak_phase"):
        np.testing.assert_allclose(base[name], joined[name], rtol=1e-9, atol=1e-8, err_msg=name)


def test_above_root_two_the_spring_parallel_damper_transmits_more_than_the_ground_one(compiled):
    r = np.array([0.5, 1.0, 1.6, 2.5, 4.0])
    base = event.compute_tile("base", r, np.array([0.0, 0.2]), ALL, effects=damper("base"))["transmissibility"]
    ground = event.compute_tile("base", r, np.array([0.0, 0.2]), ALL, effects=damper("ground"))["transmissibility"]
    assert np.all(base > ground)  # sqrt(1 + (2 zeta r)^2) at beta = 0, and with friction too here
    plain = event.compute_tile("base", r, np.array([0.0]), ALL)["transmissibility"][0]
    assert np.all(base[0, 2:] > plain[2:]) and base[0, 0] < plain[0]  # undamped, r = 1 is unbounded


# --- friction: against the independent integrator ----------------------------------------------------

# (r, beta, regime): every regime, and (2, 1.05), which moves only because the dashpot adds to the
# spring's pull on a mass at rest: |cos(r t) - 2 zeta r sin(r t)| reaches sqrt(1.16) = 1.077 > 1.05
FRICTION_POINTS = [(0.3, 0.3, Regime.STICK_SLIP), (2.0, 1.05, Regime.STICK_SLIP), (2.0, 1.2, Regime.STUCK),
                   (0.7, 0.5, Regime.CONTINUOUS), (1.0, 0.3, Regime.CONTINUOUS), (1.5, 0.3, Regime.CONTINUOUS)]


@pytest.fixture(scope="module")
def truths():
    return {(r, beta): steady_orbit(1.0, r, beta, beta, 0.0, 0.0, zeta=ZETA, base_dashpot=True)
            for r, beta, _ in FRICTION_POINTS}


@pytest.mark.parametrize("r, beta, regime", FRICTION_POINTS)
def test_spring_parallel_damper_with_friction_is_the_independent_integration(compiled, truths, r, beta, regime):
    truth = truths[(r, beta)]
    out = {k: v[0, 0] for k, v in event.compute_tile("base", np.array([r]), np.array([beta]), ALL,
                                                       effects=damper("base")).items() if k != "continuous_limit"}
    assert out["regime"] == regime
    assert out["stops_per_period"] == truth["stops"]
    assert out["stuck_fraction"] == pytest.approx(truth["stuck_fraction"], abs=1e-8)
    assert out["orbit_period"] == 1
    assert out["transmissibility"] == pytest.approx(truth["amplitude"], rel=1e-7, abs=1e-15)
    assert out["peak_transmissibility"] == pytest.approx(truth["peak"], rel=1e-6, abs=1e-15)
    if regime == Regime.STUCK:
        assert np.isnan(out["phase"]) and np.isnan(out["peak_phase"]) and truth["amplitude"] == 0.0
        return
    assert out["phase"] == pytest.approx(truth["lag"], abs=1e-6)
    if regime == Regime.CONTINUOUS:  # a stick holds the maximum over an interval: its time is not one number
        assert out["peak_phase"] == pytest.approx(truth["peak_lag"], abs=1e-3)
    if regime != Regime.STUCK:
        fixed = rk4.compute_tile("base", np.array([r]), np.array([beta]), ALL, effects=damper("base"))
        assert fixed["regime"][0, 0] == regime and fixed["stops_per_period"][0, 0] == truth["stops"]
        assert fixed["transmissibility"][0, 0] == pytest.approx(truth["amplitude"], rel=1e-5)
        assert fixed["phase"][0, 0] == pytest.approx(truth["lag"], abs=1e-3)


def test_the_dashpot_force_counts_in_the_stick_condition(compiled):
    """At (2, 1.05) a mass with the dashpot to the ground never leaves rest (the spring's pull peaks at
    1 < 1.05); with it in parallel with the spring the pull of both peaks at 1.077 and the mass moves."""
    r, beta = np.array([2.0]), np.array([1.05])
    assert event.compute_tile("base", r, beta, ALL, effects=damper("ground"))["regime"][0, 0] == Regime.STUCK
    assert event.compute_tile("base", r, beta, ALL, effects=damper("base"))["regime"][0, 0] == Regime.STICK_SLIP


def test_time_histories_are_in_the_base_frame(compiled, truths):
    """History time 0 is a maximum of the base motion y = cos(2 pi t): the state there is the independent
    integration's state at its period boundary, and the projection of x on y gives the cube's numbers."""
    pts = [[0.7, 0.5], [0.3, 0.3], [1.5, 0.3]]
    n = 1024
    h = event.time_histories("base", pts, n, effects=damper("base"))
    for i, (r, beta) in enumerate(pts):
        truth = truths[(r, beta)]
        assert h["history_orbit_period"][i] == 1
        assert h["history_relative_displacement"][i, 0] == pytest.approx(truth["q_end"], abs=1e-8)
        assert h["history_relative_velocity"][i, 0] == pytest.approx(truth["v_end"], abs=1e-8)
        t = h["history_time"][i, :n]
        np.testing.assert_allclose(h["history_excitation"][i, :n], np.cos(2 * np.pi * np.arange(n) / n), atol=1e-12)
        assert t[0] == 0.0
        x = h["history_displacement"][i, :n]
        a1, b1 = 2 * np.mean(x * np.cos(2 * np.pi * t)), 2 * np.mean(x * np.sin(2 * np.pi * t))
        assert np.hypot(a1, b1) == pytest.approx(truth["amplitude"], rel=1e-4)
        assert wrapped(np.degrees(np.arctan2(b1, a1))) == pytest.approx(truth["lag"], abs=0.05)
        assert np.max(np.abs(x)) == pytest.approx(truth["peak"], rel=1e-4)


def test_the_moving_start_and_the_sweep_report_phases_against_the_base(compiled):
    """The `_moving` twins (static friction) and a stepped-sine sweep run the same kernels from other
    starts: where the steady state is one, they must agree with the plain solve, phases included."""
    r, beta = np.array([1.5, 2.5]), np.array([0.1])
    effects = {**damper("base"), "static_friction_ratio": 1.5}
    out = event.compute_tile("base", r, beta, ALL, effects=effects)
    assert np.all(out["regime"] == Regime.CONTINUOUS) and np.all(out["steady_states"] == 1)
    for name in ("phase", "peak_phase"):
        np.testing.assert_allclose(out[name + "_moving"], out[name], atol=1e-6)
    truth = steady_orbit(1.0, 1.5, 0.1, 0.15, 0.0, 0.0, zeta=ZETA, base_dashpot=True)
    assert out["phase"][0, 0] == pytest.approx(truth["lag"], abs=1e-6)
    plain = event.compute_tile("base", r, np.array([0.1, 0.3]), ALL, effects=damper("base"))
    swept = event.compute_sweep_tile("base", r, np.array([0.1, 0.3]), ALL, effects=damper("base"), direction="down")
    np.testing.assert_array_equal(swept["regime"], plain["regime"])
    for name in ("transmissibility", "phase", "peak_phase"):
        np.testing.assert_allclose(swept[name], plain[name], rtol=1e-9, atol=1e-7, err_msg=name)


# --- a bare number keeps today's meaning, bit for bit --------------------------------------------------


@pytest.mark.parametrize("excitation, place", [("base", "ground"), ("joined", "base"), ("force", "ground")])
@pytest.mark.parametrize("method", [event, rk4], ids=["event", "rk4"])
def test_a_bare_number_is_its_default_place_bit_for_bit(compiled, excitation, place, method):
    r, beta = np.array([0.4, 1.0, 2.2]), np.array([0.0, 0.3, 0.9])
    bare = method.compute_tile(excitation, r, beta, ALL, effects={"viscous_damping": 0.07})
    placed = method.compute_tile(excitation, r, beta, ALL, effects=damper(place, 0.07))
    assert bare.keys() == placed.keys()
    for name in bare:
        np.testing.assert_array_equal(bare[name], placed[name], err_msg=name)


SPEC = """\
scene:
  excitation: {excitation}
  effects: {{viscous_damping: {damping}}}
grid:
  frequency_ratio: [0.5, 1.0, 1.8]
  force_ratio: [0.0, 0.4]
method: event
outputs: [transmissibility, phase, regime, time_history]
time_history: {{points: [[0.6, 0.2], [1.6, 0.4]], samples_per_period: 64}}
"""


@pytest.mark.parametrize("excitation, place", [("base", "ground"), ("joined", "base")])
def test_bare_and_placed_specs_give_the_same_cube_and_record_the_place(compiled, excitation, place):
    cubes = [api.run(parse_spec_text(SPEC.format(excitation=excitation, damping=damping)))
             for damping in ("0.05", f"{{ratio: 0.05, to: {place}}}")]
    assert list(cubes[0].data_vars) == list(cubes[1].data_vars)
    for name in cubes[0].data_vars:
        np.testing.assert_array_equal(cubes[0][name].values, cubes[1][name].values, err_msg=name)
    for ds in cubes:
        recorded = json.loads(ds.attrs["method_settings"])["effects"]
        assert recorded == {"viscous_damping": {"ratio": 0.05, "to": place}}
        assert ds.attrs["effects"].startswith(f"viscous_damping 0.05, to: {place} (from the mass to the ")


def test_the_spring_parallel_cube_passes_fsweep_check_with_its_own_forcing(compiled):
    """Rule `bound` needs the forcing amplitude sqrt(1 + (2 zeta r)^2): at beta = 0 the transmissibility is
    that over |1 - r^2 + 2i zeta r|, above the bound of the dashpot to the ground."""
    ds = api.run(parse_spec_text(SPEC.format(excitation="base", damping="{ratio: 0.2, to: base}")))
    found = {f.rule: f for f in consistency.check(ds)}
    assert found["bound"].status == consistency.OK and found["bound"].checked == 6
    assert found["resonance"].status == found["theory"].status == consistency.SKIPPED
    relabelled = ds.copy()
    relabelled.attrs["method_settings"] = json.dumps({"effects": {"viscous_damping": 0.2}})
    assert {f.rule: f for f in consistency.check(relabelled)}["bound"].violations >= 3


@pytest.mark.parametrize("excitation, effect", [("force", {"ratio": 0.1, "to": "base"}),
                                                ("joined", {"ratio": 0.1, "to": "ground"}),
                                                ("base", {"ratio": 0.1}),
                                                ("base", {"ratio": 0.1, "to": "base", "x": 1})])
def test_fsweep_check_refuses_a_place_the_model_does_not_have(excitation, effect):
    r, beta = np.array([1.5]), np.array([0.1])
    ds = cube.build_dataset(
        {"transmissibility": np.ones((1, 1))}, frequency_ratio=r, force_ratio=beta, excitation=excitation,
        title="t", history="h", attrs=provenance.attributes(
            spec_text="", spec_path="s.yaml", excitation=excitation, method="event",
            settings={"effects": {"viscous_damping": effect}}))
    with pytest.raises(consistency.CubeError, match="viscous_damping"):
        consistency.check(ds)


# --- the spec: accepted shapes and every refusal -------------------------------------------------------


def spec_text(excitation: str, damping: str, method: str = "event") -> str:
    """Line 3 holds the effects: `  effects: {viscous_damping: ` is 29 characters, the value at column 30."""
    return (f"scene:\n  excitation: {excitation}\n  effects: {{viscous_damping: {damping}}}\n"
            f"grid:\n  frequency_ratio: [0.5, 1.0]\n  force_ratio: [0.1]\nmethod: {method}\n")


def problem(text: str):
    with pytest.raises(SpecError) as info:
        parse_spec_text(text, "t.yaml")
    assert len(info.value.errors) == 1, str(info.value)
    return info.value.errors[0]


@pytest.mark.parametrize("excitation, to", [("force", "ground"), ("base", "ground"), ("base", "base"),
                                            ("joined", "base")])
def test_each_allowed_place_is_accepted(excitation, to):
    spec = parse_spec_text(spec_text(excitation, f"{{ratio: 0.05, to: {to}}}"))
    assert spec.scene.effects == {"viscous_damping": {"ratio": 0.05, "to": to}}
    assert parse_spec_text(spec_text(excitation, "0")).scene.effects == {"viscous_damping": 0.0}


@pytest.mark.parametrize("excitation, damping, key, column, reason", [
    ("force", "{ratio: 0.05, to: base}", "scene.effects.viscous_damping.to", 48,
     "excitation 'force' allows only to: ground (from the mass to the ground) (got 'base')"),
    ("joined", "{ratio: 0.05, to: ground}", "scene.effects.viscous_damping.to", 48,
     "excitation 'joined' allows only to: base (from the mass to the moving base and wall, on the relative "
     "velocity) (got 'ground')"),
    ("base", "{ratio: 0.05, to: wall}", "scene.effects.viscous_damping.to", 48,
     "must be one of: ground, base (got 'wall')"),
    ("base", "{ratio: 0.05, to: 1}", "scene.effects.viscous_damping.to", 48,
     "must be one of: ground, base (got 1)"),
    ("base", "{to: base}", "scene.effects.viscous_damping", 13,
     "required key 'ratio' is missing (give {ratio: number, to: ground | base}, or a bare number)"),
    ("base", "{ratio: 0.05}", "scene.effects.viscous_damping", 13,
     "required key 'to' is missing (give {ratio: number, to: ground | base}, or a bare number)"),
    ("base", "{ratio: 0.05, to: base, at: 2}", "scene.effects.viscous_damping.at", 54,
     "unknown key 'at' (allowed: ratio, to)"),
    ("base", "{ratio: 1.0, to: base}", "scene.effects.viscous_damping.ratio", 38,
     "must be between 0 and 1 (1 excluded) (got 1.0): the damping ratio zeta of the dashpot's force 2 zeta v, "
     "v the velocity across it (underdamped)"),
    ("base", "{ratio: -0.1, to: base}", "scene.effects.viscous_damping.ratio", 38, "must be between 0 and 1"),
    ("base", "{ratio: .nan, to: base}", "scene.effects.viscous_damping.ratio", 38, "must be a finite number"),
    ("base", "{ratio: '0.1', to: base}", "scene.effects.viscous_damping.ratio", 38, "must be a number (got '0.1')"),
    ("base", "[0.1, base]", "scene.effects.viscous_damping", 13,
     "must be a number or {ratio: number, to: ground | base} (got [0.1, 'base'])"),
])
def test_each_refusal_is_located(excitation, damping, key, column, reason):
    p = problem(spec_text(excitation, damping))
    assert (p.path, p.line, p.key) == ("t.yaml", 3, key)
    assert p.reason.startswith(reason), p.reason
    assert p.column == column, (p.column, str(p))


def test_every_problem_of_a_placed_damper_is_reported_at_once():
    with pytest.raises(SpecError) as info:
        parse_spec_text(spec_text("force", "{ratio: 2, to: base, at: 1}"), "t.yaml")
    assert sorted(e.key for e in info.value.errors) == ["scene.effects.viscous_damping.at",
                                                        "scene.effects.viscous_damping.ratio",
                                                        "scene.effects.viscous_damping.to"]


@pytest.mark.parametrize("method", ["theory", "auto", "paper"])
def test_methods_without_damping_refuse_it_in_either_shape(method):
    p = problem(spec_text("base", "{ratio: 0.05, to: base}", method))
    assert p.key == "scene.effects.viscous_damping"
    assert p.reason == f"method {method!r} does not model viscous_damping (methods that do: event, rk4)"


def test_the_cli_says_where_the_dashpot_sits_and_refuses_with_exit_2(runner, tmp_path):
    path = tmp_path / "spec.yaml"
    path.write_text(spec_text("base", "{ratio: 0.05, to: base}"))
    res = runner.invoke(main, ["validate", str(path)])
    assert res.exit_code == 0, res.output
    assert ("  effect viscous_damping 0.05, to: base (from the mass to the moving base, in parallel with the "
            "spring)") in res.output.splitlines()
    path.write_text(spec_text("joined", "{ratio: 0.05, to: ground}"))
    res = runner.invoke(main, ["validate", str(path)])
    assert res.exit_code == 2
    assert f"{path}:3:48: scene.effects.viscous_damping.to: excitation 'joined' allows only" in res.output
    shape = "{ratio: number, to: ground | base} (force ground; base ground | base; joined base)"
    assert shape in runner.invoke(main, ["info", "--methods"]).output
    assert f"effect viscous_damping: a number in 0 or [1e-06, 1) (the ratio, at the first place listed), or {shape}" in \
        runner.invoke(main, ["settings", "event"]).output
