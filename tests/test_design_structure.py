"""The designer's answers for a structure (fs.peak, fs.optimize, fs.backbone on a structure spec,
friction_sweep.design.structure) against independent truths: a dense plain sweep, the linear structure's
response (K - w^2 M + i w C)^-1 F with the contact free and stuck (matrices written here by hand, maximised
by SciPy), a brute-force scan of friction_scale, and the energy balance of the exact orbit."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from scipy.optimize import brentq, minimize_scalar

import friction_sweep as fs
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.errors import FsweepError

#: the blade of configs/blade_damper.yaml (tip, platform, damper; a Jenkins contact damper-platform)
BLADE = {"masses": {"tip": 1.0, "platform": 0.5, "damper": 0.05},
         "springs": [["ground", "platform", 3.0], ["platform", "tip", 2.0], ["ground", "damper", 5.0]],
         "dampers": [["ground", "tip", 0.01]],
         "contacts": [{"name": "damper", "between": ["damper", "platform"], "friction": 1.0, "stiffness": 5.0}],
         "forcing": {"tip": 1.0}}
#: its matrices in the dof order (tip, platform, damper), written out here, and the contact's direction
M = np.diag([1.0, 0.5, 0.05])
K = np.array([[2.0, -2.0, 0.0], [-2.0, 5.0, 0.0], [0.0, 0.0, 5.0]])
C = np.diag([0.01, 0.0, 0.0])
F = np.array([1.0, 0.0, 0.0])
KT, WD = 5.0, np.array([0.0, -1.0, 1.0])


def _spec(scale, w=(0.6, 1.6, 21), structure=BLADE, settings=None):
    spec = {"scene": {"excitation": "force"}, "structure": structure,
            "grid": {"frequency": {"start": w[0], "stop": w[1], "num": w[2]}, "friction_scale": list(scale)}}
    if settings:
        spec["settings"] = settings
    return spec


def _linear(w, stuck=False):
    k = K + KT * np.outer(WD, WD) if stuck else K
    return np.linalg.solve(k - w * w * M + 1j * w * C, F)


def test_exact_peak_never_below_a_dense_grid_and_within_its_resolution():
    """The tip's peak from a coarse grid (0.05 apart) at two normal loads (the contact held and stick-slip
    there): at least the dense plain sweep's maximum (0.0005 apart) and above it by no more than the dense
    grid's step in amplitude next to its maximum, its frequency within a dense step of the dense maximum's,
    and each contact's regime there the dense sweep's."""
    scale = [1.0, 3.0]
    coarse = fs.peak(_spec(scale))
    dense = fs.sweep(_spec(scale, (0.95, 1.25, 601)))
    amp = dense.amplitude.sel(dof="tip").transpose("friction_scale", "frequency").values
    w = dense.frequency.values
    for j in range(len(scale)):
        k = int(np.argmax(amp[j]))
        assert 0 < k < w.size - 1, "the dense grid must hold the peak inside"
        resolution = max(amp[j, k] - amp[j, k - 1], amp[j, k] - amp[j, k + 1])
        peak = float(coarse.resonance_peak[j])
        assert peak >= amp[j, k] * (1 - 1e-12)
        assert peak - amp[j, k] <= resolution
        assert abs(float(coarse.resonance_frequency[j]) - w[k]) <= w[1] - w[0]
        assert not bool(coarse.resonance_at_edge[j])
        expected = dense.regime.transpose("friction_scale", "frequency", "contact").values[j, k]
        np.testing.assert_array_equal(coarse.resonance_regime.values[j], expected)
    assert coarse.attrs["dof"] == "tip"


@pytest.mark.parametrize("scale, stuck", [(0.0, False), (1e4, True)])
def test_without_friction_and_stuck_the_peak_is_the_linear_structures(scale, stuck):
    """friction_scale 0: the contact exerts nothing, the free linear structure; friction_scale 1e4: the
    contact never slips, the linear structure with its Jenkins spring. The exact peak of the tip equals the
    linear |X_tip| maximised by SciPy (bounded, to 1e-12 in w) to 1e-8, at its frequency to 1e-4 (a smooth
    maximum locates to the square root of the value's accuracy), and the phase resonance (lag 90 degrees)
    is the linear one's, by brentq."""
    grid = (1.1, 1.3, 21) if stuck else (0.95, 1.15, 21)
    ds = fs.peak(_spec([scale], grid))
    truth = minimize_scalar(lambda x: -abs(_linear(x, stuck)[0]), bounds=grid[:2], method="bounded",
                            options={"xatol": 1e-12})
    assert float(ds.resonance_peak[0]) == pytest.approx(-truth.fun, rel=1e-8)
    assert float(ds.resonance_frequency[0]) == pytest.approx(truth.x, abs=1e-4)
    regime = Regime.STUCK if stuck else Regime.CONTINUOUS
    assert ds.resonance_regime.values[0].tolist() == [regime]
    lag = brentq(lambda x: np.angle(_linear(x, stuck)[0], deg=True) + 90.0, grid[0], grid[1], xtol=1e-14)
    found = ds.phase_resonance_frequency.values[0]
    assert found[np.isfinite(found)] == pytest.approx([lag], abs=1e-9)


def test_the_optimum_against_a_brute_force_scan_of_friction_scale():
    """The blade's peak has an interior minimum in the normal load (free: the bare blade's resonance; stuck:
    the stiffened blade's, both lightly damped). The optimum from 4 loads is at most the least peak of a
    13-load scan (each peak exact), and lies within a scan step of where that scan's least peak is. (The
    tolerances are looser than the defaults, 1e-6 in the load and 1e-8 in w, to keep the test's stick-slip
    points few: the search is the same.)"""
    w = (1.0, 1.25, 11)
    opt = fs.optimize(_spec([2.0, 3.0, 4.0, 5.0], w), beta_tol=1e-6, r_tol=1e-8)
    assert opt.attrs["optimum_kind"] == "interior"
    scan = np.linspace(2.5, 4.0, 13)
    brute = fs.peak(_spec(scan, w), r_tol=1e-8).resonance_peak.values
    j = int(np.argmin(brute))
    assert 0 < j < scan.size - 1
    assert float(opt.optimum_peak) <= brute[j] * (1 + 1e-12)
    assert abs(float(opt.optimum_friction_scale) - scan[j]) <= scan[1] - scan[0]
    assert opt.optimum_regime.dims == ("contact",)


def _elastic_max(X, k):
    """max over one period of 1/2 x^T k x, x = Re(X e^{i t}), by sampling 20001 phases."""
    t = np.linspace(0.0, 2.0 * np.pi, 20001)
    x = np.real(X[:, None] * np.exp(1j * t)[None, :])
    return float(np.max(0.5 * np.einsum("it,ij,jt->t", x, k, x)))


@pytest.mark.parametrize("scale, stuck", [(0.0, False), (1e4, True)])
def test_backbone_of_the_linear_limits_is_their_phase_resonance_and_damping(scale, stuck):
    """Free and stuck, the structure is linear: its backbone point is where X_tip lags 90 degrees (brentq),
    E_d the dashpot's pi w X^H C X, E_p the largest elastic energy of the harmonic orbit (sampled), the
    stuck one's with the Jenkins spring."""
    grid = (1.1, 1.3, 21) if stuck else (0.95, 1.15, 21)
    ds = fs.backbone(_spec([scale], grid))
    lag = brentq(lambda x: np.angle(_linear(x, stuck)[0], deg=True) + 90.0, grid[0], grid[1], xtol=1e-14)
    X = _linear(lag, stuck)
    k = K + KT * np.outer(WD, WD) if stuck else K
    e_d = np.pi * lag * np.real(np.conj(X) @ C @ X)
    e_p = _elastic_max(X, k)
    one = ds.isel(friction_scale=0, crossing=0)
    assert float(one.backbone_frequency) == pytest.approx(lag, abs=1e-9)
    assert float(one.backbone_amplitude) == pytest.approx(abs(X[0]), rel=1e-8)
    assert float(one.backbone_dissipated_energy) == pytest.approx(e_d, rel=1e-7)
    assert float(one.backbone_damping_ratio) == pytest.approx(e_d / (4 * np.pi * e_p), rel=1e-6)


#: a 2-mass chain without dashpots (benchmarks/structures.py's blade and damper, dashpot removed): friction
#: alone dissipates
CHAIN = {"masses": {"blade": 1.0, "damper": 0.1}, "springs": [["ground", "blade", 1.0], ["blade", "damper", 2.0]],
         "contacts": [{"name": "c", "between": ["damper", "ground"], "friction": 0.3}], "forcing": {"blade": 1.0}}


def test_backbone_damping_is_the_friction_energy_over_the_largest_elastic_energy():
    """Without dashpots the forcing's work is the friction energy, exactly (the engine measures each
    separately); zeta_eq is then friction_energy / (4 pi E_max), E_max sampled here from the exact orbit's
    first harmonics (structures.solve_points at the backbone's points)."""
    from friction_sweep.structures import ContactDef, StructureDef, assemble, solve_points

    scales = [3.0, 4.0]
    ds = fs.backbone(_spec(scales, (0.5, 1.5, 21), CHAIN))
    kc = np.array([[3.0, -2.0], [-2.0, 2.0]])
    a = assemble(StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0),
                                                                       ("blade", "damper", 2.0)), (),
                              (ContactDef("c", ("damper", "ground"), 0.3),), {"blade": 1.0}))
    checked = 0
    for j, s in enumerate(scales):
        for k in np.nonzero(np.isfinite(ds.backbone_frequency.values[j]))[0]:
            one = ds.isel(friction_scale=j, crossing=k)
            e_f = float(one.backbone_friction_energy.sum())
            assert float(one.backbone_dissipated_energy) == pytest.approx(e_f, rel=1e-7)
            res = solve_points(a, [float(one.backbone_frequency)], [s])
            X = res["amplitude"][0] * np.exp(-1j * np.radians(res["phase"][0]))
            assert float(one.backbone_damping_ratio) == pytest.approx(e_f / (4 * np.pi * _elastic_max(X, kc)),
                                                                      rel=1e-6)
            checked += 1
    assert checked >= 2


def test_peak_dof_chooses_the_mass_and_a_bad_one_is_refused_at_its_key():
    ds = fs.peak(_spec([1.0], settings={"peak_dof": "platform"}))
    assert ds.attrs["dof"] == "platform"
    cube = fs.sweep(_spec([1.0], (0.9, 1.1, 3), settings={"peak_dof": "platform"}))  # a run ignores it
    assert "peak_dof" not in cube.attrs["method_settings"]
    with pytest.raises(FsweepError, match=r"settings\.peak_dof.*'hub' is not a mass"):
        fs.peak(_spec([1.0], settings={"peak_dof": "hub"}))


def test_the_backbone_of_a_base_excited_structure_is_refused():
    structure = {k: v for k, v in BLADE.items() if k != "forcing"}
    structure["springs"] = [["base", "platform", 3.0], ["platform", "tip", 2.0], ["ground", "damper", 5.0]]
    spec = {**_spec([1.0], structure=structure), "scene": {"excitation": "base"}}
    with pytest.raises(FsweepError, match="excitation force"):
        fs.backbone(spec)


def test_cli_optimize_prints_the_optimum_and_writes_the_curve(tmp_path):
    path = tmp_path / "blade.yaml"
    # heavy loads, the peak rising towards the stuck blade's: the least load is the optimum (the grid's edge)
    path.write_text(json.dumps(_spec([20.0, 40.0, 80.0], (1.1, 1.3, 9))))  # JSON is YAML
    out = tmp_path / "curve.nc"
    png = tmp_path / "curve.png"
    done = CliRunner().invoke(main, ["optimize", str(path), "-o", str(out), "--plot", str(png)])
    assert done.exit_code == 0, done.output
    assert done.output.startswith("optimum (edge): friction_scale 20, ")
    assert "damper: " in done.output
    assert png.stat().st_size > 0
    with xr.open_dataset(out, engine="h5netcdf") as written:
        assert set(written.dims) >= {"friction_scale", "peak", "contact"}
        assert float(written.optimum_peak) <= float(written.resonance_peak.min())
