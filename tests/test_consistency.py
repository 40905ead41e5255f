"""`fsweep check`: the consistency rules pass on correct cubes and catch one planted fault each."""

import json

import numpy as np
import pytest
from click.testing import CliRunner
from conftest import in_dir

from friction_sweep import codes
from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.methods import event
from friction_sweep.storage import cube, provenance

# r = 1 exactly, one ulp above it (inside the tie) and 1e-11 either side of it (outside); 0.2 with
# joined beta = 0.04 = r*r on paper (one ulp off in binary); beta = 1 (the force/base no-motion tie) and
# pi/4 (the resonance tie)
R_GRID = [0.04, 0.2, 0.5, 0.8, 1 - 1e-11, 1.0, float(np.nextafter(1.0, 2.0)), 1 + 1e-11, 1.5, 2.0, 3.0]
BETA_GRID = [0.0, 0.0016, 0.04, 0.3, float(np.pi / 4), 0.9, 1.0, 1.2]
SPEC = """\
scene:
  excitation: {excitation}
grid:
  frequency_ratio: {r}
  force_ratio: {beta}
method: theory
output: {output}
"""


def check(path, *args):
    return CliRunner().invoke(main, ["check", str(path), *args])


def findings(path):
    res = check(path, "--json")
    return res.exit_code, {f["rule"]: f for f in json.loads(res.output)}


@pytest.fixture(scope="module")
def theory_cubes(tmp_path_factory):
    """Theory cubes written by `fsweep run`, one per excitation."""
    folder = tmp_path_factory.mktemp("cubes")
    with in_dir(folder):
        for exc in ("force", "base", "joined"):
            spec = folder / f"{exc}.yaml"
            spec.write_text(SPEC.format(excitation=exc, r=R_GRID, beta=BETA_GRID, output=f"{exc}.h5"))
            res = CliRunner().invoke(main, ["run", str(spec), "--quiet"])
            assert res.exit_code == 0, res.output
    return {exc: folder / f"{exc}.h5" for exc in ("force", "base", "joined")}


@pytest.fixture(scope="module")
def event_cube():
    """A small cube from the exact event simulation, labelled as `fsweep run` labels it."""
    r = np.array([0.8, 1.5, 2.0, 3.0])
    beta = np.array([0.0, 0.1, 0.3, 0.45, 1.0])
    arrays = event.compute_tile("base", r, beta, ("transmissibility", "regime"))
    return cube.build_dataset(
        arrays, frequency_ratio=r, force_ratio=beta, excitation="base", title="t",
        history=provenance.history_line("test"),
        attrs=provenance.attributes(spec_text="", spec_path="s.yaml", excitation="base", method="event",
                                    settings={**event.CATALOGUE.defaults, "effects": {}}))


def at(ds, r, beta):
    return {"frequency_ratio": r, "force_ratio": beta}


def planted(ds, tmp_path, name="planted.h5", **changes):
    """Write a copy of ds with point values changed: changes = {var: [(r, beta, value), ...]}."""
    ds = ds.copy(deep=True)
    for var, points in changes.items():
        for r, beta, value in points:
            ds[var].loc[at(ds, r, beta)] = value
    path = tmp_path / name
    ds.to_netcdf(path, engine="h5netcdf")
    return path


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
def test_a_theory_cube_passes_every_rule_at_and_next_to_the_ties(theory_cubes, excitation):
    res = check(theory_cubes[excitation])
    assert res.exit_code == 0, res.output
    lines = res.output.splitlines()
    # r = 1 and its neighbouring ulp only: 1 +- 1e-11 is past the tie
    assert lines[0].split()[:3] == ["resonance", "ok", str(2 * len(BETA_GRID))]
    assert lines[1].split()[:2] == ["bound", "ok"]
    assert lines[2] == "theory      skipped (the theory itself)"
    assert lines[3] == "energy      skipped (method theory: not a simulation with a stated accuracy)"
    assert lines[4].split()[:2] == ["unsettled", "ok"]
    assert lines[5] == "family      skipped (no steady_state)"
    assert lines[6].startswith(f"{theory_cubes[excitation]}: ok")


def test_json_parses_and_lists_every_rule(theory_cubes):
    code, found = findings(theory_cubes["base"])
    assert code == 0
    assert list(found) == ["resonance", "bound", "theory", "energy", "unsettled", "family"]
    for f in found.values():
        assert {"rule", "status", "checked", "violations", "examples"} <= set(f)
    # every finite point is checked against the bound: all but r = 1 (infinite bound) and NaN points
    ds = cube.open_cube(theory_cubes["base"])
    finite = np.isfinite(ds["transmissibility"].values)
    finite[:, list(ds["frequency_ratio"].values).index(1.0)] = False
    assert found["bound"]["checked"] == finite.sum()


@pytest.mark.parametrize("beta, regime, expected", [
    (0.3, Regime.CONTINUOUS, "unbounded"),  # b < pi/4 at r = 1: the amplitude grows without bound
    (float(np.pi / 4), Regime.STICK_SLIP, "unbounded"),  # the tie b = pi/4 is unbounded too
    (0.9, Regime.UNBOUNDED, "finite"),  # b > pi/4: friction outweighs the forcing's work
    (1.0, Regime.STICK_SLIP, "stuck"),  # the force never leaves the static band
])
def test_resonance_fault_is_caught(theory_cubes, tmp_path, beta, regime, expected):
    ds = cube.open_cube(theory_cubes["base"])
    # the peak planted with the amplitude: a transmissibility above 4/pi x the peak is refused by the reader
    path = planted(ds, tmp_path, regime=[(1.0, beta, regime)], transmissibility=[(1.0, beta, 1e15)],
                   peak_transmissibility=[(1.0, beta, 1e15)])
    code, found = findings(path)
    assert code == 1
    res = found["resonance"]
    assert (res["status"], res["violations"], res["checked"]) == ("failed", 1, 2 * len(BETA_GRID))
    (ex,) = res["examples"]
    assert (ex["r"], ex["beta"], ex["found"]) == (1.0, beta, codes.name_of(Regime, regime))
    assert ex["expected"].startswith(expected)
    assert [f["status"] for n, f in found.items() if n != "resonance"] == ["ok", "skipped", "skipped", "ok", "skipped"]


def test_resonance_fault_is_caught_in_the_text_report(theory_cubes, tmp_path):
    ds = cube.open_cube(theory_cubes["joined"])
    path = planted(ds, tmp_path, regime=[(1.0, 0.3, Regime.CONTINUOUS)], transmissibility=[(1.0, 0.3, 1e15)])
    res = check(path)
    assert res.exit_code == 1
    assert res.output.splitlines()[0] == (
        f"resonance   FAILED   1 of {2 * len(BETA_GRID)}: (r=1.0, beta=0.3: continuous, expected unbounded (b <= pi/4))")
    assert res.output.splitlines()[-1].startswith(f"{path}: FAILED: 1 failed")


def test_bound_fault_is_caught(theory_cubes, tmp_path):
    ds = cube.open_cube(theory_cubes["base"])
    # bound at r = 2, beta = 0.3: (1 + 1.2/pi) / 3 = 0.46066...
    bound = (1 + 4 / np.pi * 0.3) / 3
    path = planted(ds, tmp_path, transmissibility=[(2.0, 0.3, 1.01 * bound)],
                   peak_transmissibility=[(2.0, 0.3, 1.01 * bound)])
    code, found = findings(path)
    assert code == 1
    f = found["bound"]
    assert (f["status"], f["violations"]) == ("failed", 1)
    assert f["examples"][0]["found"] == pytest.approx(1.01 * bound, rel=1e-15)
    assert f["examples"][0]["expected"] == f"<= {bound:.6g}"
    assert found["resonance"]["status"] == "ok"


def test_bound_is_attained_by_the_linear_response(theory_cubes, tmp_path):
    """Without friction the first harmonic is exactly 1/|1 - r^2| (the bound): 1e-5 more is caught."""
    ds = cube.open_cube(theory_cubes["force"])
    r = 1 + 1e-11
    assert float(ds["transmissibility"].sel(at(ds, r, 0.0))) == pytest.approx(1 / abs((1 - r) * (1 + r)),
                                                                            rel=1e-9)
    path = planted(ds, tmp_path, transmissibility=[(r, 0.0, float(ds["transmissibility"].sel(at(ds, r, 0.0)))
                                                     * (1 + 1e-5))])
    code, found = findings(path)
    assert code == 1 and found["bound"]["violations"] == 1


def test_an_event_cube_agrees_with_the_theory_and_a_1e6_change_is_caught(event_cube, tmp_path):
    path = tmp_path / "event.h5"
    event_cube.to_netcdf(path, engine="h5netcdf")
    code, found = findings(path)
    assert code == 0, found
    assert found["theory"]["status"] == "ok" and found["theory"]["checked"] >= 8
    assert found["family"]["status"] == "info" and found["family"]["violations"] == 0
    # a continuous point (beta = 0.1 < 0.98 beta*(1.5)), changed by 1e-6 relative
    assert int(event_cube["regime"].sel(at(event_cube, 1.5, 0.1))) == Regime.CONTINUOUS
    T = float(event_cube["transmissibility"].sel(at(event_cube, 1.5, 0.1)))
    path = planted(event_cube, tmp_path, transmissibility=[(1.5, 0.1, T * (1 + 1e-6))])
    code, found = findings(path)
    assert code == 1
    f = found["theory"]
    assert (f["status"], f["violations"]) == ("failed", 1)
    assert (f["examples"][0]["r"], f["examples"][0]["beta"]) == (1.5, 0.1)
    assert [found[n]["status"] for n in ("resonance", "bound", "unsettled")] == ["ok", "ok", "ok"]


def test_unsettled_fault_is_caught_with_its_reason(event_cube, tmp_path):
    path = planted(event_cube, tmp_path, regime=[(2.0, 0.3, Regime.UNSETTLED)],
                   steady_state=[(2.0, 0.3, SteadyState.PERIOD_CAP)])
    code, found = findings(path)
    assert code == 1
    f = found["unsettled"]
    assert (f["status"], f["violations"], f["checked"]) == ("failed", 1, event_cube["regime"].size)
    assert f["examples"][0]["found"] == "unsettled (period_cap)"
    assert found["theory"]["status"] == "ok"  # the unsettled point is left to this rule


def test_family_points_are_counted_never_failed(event_cube, tmp_path):
    family = SteadyState.FAMILY
    path = planted(event_cube, tmp_path, steady_state=[(0.8, 0.0, family), (2.0, 0.0, family)])
    code, found = findings(path)
    assert code == 0
    f = found["family"]
    assert (f["status"], f["violations"], len(f["examples"])) == ("info", 0, 2)
    assert f["note"].startswith("2 points")


def test_missing_variables_are_skipped_not_failed(event_cube, tmp_path):
    path = tmp_path / "regime_only.h5"
    event_cube.drop_vars(["transmissibility", "peak_transmissibility"]).to_netcdf(path, engine="h5netcdf")
    code, found = findings(path)
    assert code == 0
    assert (found["bound"]["status"], found["bound"]["note"]) == ("skipped", "no transmissibility")
    assert found["theory"]["note"] == "no transmissibility"
    assert check(path).output.splitlines()[1] == "bound       skipped (no transmissibility)"


def test_damped_cube_skips_resonance_and_theory(event_cube, tmp_path):
    ds = event_cube.copy()
    ds.attrs["method_settings"] = json.dumps({"effects": {"viscous_damping": 0.05}})
    path = tmp_path / "damped.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    _, found = findings(path)
    assert found["resonance"]["status"] == found["theory"]["status"] == "skipped"


def test_a_jenkins_cube_passes_the_rules_that_hold_for_it(tmp_path):
    """A contact spring (kappa = 100) passes on a force bounded by the static friction, so the friction's
    bound and the resonance rule at r = 1 hold as for the rigid contact, and are checked; Den Hartog's
    closed form is the rigid contact's, so rule `theory` is skipped."""
    spec = tmp_path / "jenkins.yaml"
    spec.write_text("scene: {excitation: base, effects: {contact_stiffness: 100}}\n"
                    "grid: {frequency_ratio: [0.5, 1.0, 3.0], force_ratio: [0.3, 0.9, 1.2]}\nmethod: event\n"
                    "output: j.h5\n")
    with in_dir(tmp_path):
        assert CliRunner().invoke(main, ["run", str(spec), "-q"]).exit_code == 0
    code, found = findings(tmp_path / "j.h5")
    assert code == 0
    assert (found["resonance"]["status"], found["resonance"]["checked"]) == ("ok", 3)
    assert (found["bound"]["status"], found["bound"]["violations"]) == ("ok", 0)
    assert found["theory"]["status"] == "skipped"


@pytest.mark.parametrize("content", [b"not a cube\n", None])
def test_a_foreign_file_is_bad_input(tmp_path, content):
    path = tmp_path / "junk.h5"
    if content is None:  # readable netCDF, but no friction_sweep provenance
        import xarray as xr

        xr.Dataset({"a": ("x", [1.0])}).to_netcdf(path, engine="h5netcdf")
    else:
        path.write_bytes(content)
    res = check(path)
    assert res.exit_code == 2
    assert len(res.output.splitlines()) == 1
    assert res.output.startswith("fsweep: error: ") and str(path) in res.output
