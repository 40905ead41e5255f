"""The resonance peak (fs.peak) and the optimum friction (fs.optimize) against independent truths: a dense
grid of the plain sweep, Den Hartog's closed form maximised by SciPy, and brute-force scans of friction."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import friction_sweep as fs
from friction_sweep.codes import Regime


def _spec(excitation, r, beta, method="event", effects=None):
    scene = {"excitation": excitation, **({"effects": effects} if effects else {})}
    return {"scene": scene, "grid": {"frequency_ratio": r, "force_ratio": beta}, "method": method}


@pytest.mark.parametrize("method", ["event", "auto"])
def test_exact_peak_never_below_a_dense_grid_and_within_its_resolution(method):
    """Joined scene, stick-slip peaks: from a coarse grid (0.05 apart) the refined peak is at least a dense
    plain sweep's maximum (1001 points over the same range) and above it by no more than the dense grid's
    step in T next to its maximum; its frequency within one dense step of the dense maximum's."""
    beta = [0.9, 0.95, 1.0]
    coarse = fs.peak(_spec("joined", {"start": 1.05, "stop": 2.05, "num": 21}, beta, method))
    dense = fs.sweep(_spec("joined", {"start": 1.05, "stop": 2.05, "num": 1001}, beta, method))
    t = dense.transmissibility.transpose("force_ratio", "frequency_ratio").values
    r = dense.frequency_ratio.values
    for j in range(len(beta)):
        k = int(np.argmax(t[j]))
        assert 0 < k < r.size - 1, "the dense grid must hold the peak inside"
        resolution = max(t[j, k] - t[j, k - 1], t[j, k] - t[j, k + 1])
        peak = float(coarse.resonance_peak[j])
        assert peak >= t[j, k] - 1e-12 * t[j, k]
        assert peak - t[j, k] <= resolution
        assert abs(float(coarse.resonance_frequency_ratio[j]) - r[k]) <= r[1] - r[0]
        assert not bool(coarse.resonance_at_edge[j])
        assert coarse.resonance_regime[j] == dense.regime.transpose("force_ratio", "frequency_ratio").values[j, k]


def _den_hartog_amplitude(r, b):
    """Den Hartog's continuous amplitude x0 = sqrt(V^2 - b^2 U^2), V = 1/(1 - r^2), U = tan(pi/(2r))/r
    (written here, not the package's theory)."""
    v = 1.0 / (1.0 - r * r)
    u = np.tan(np.pi / (2.0 * r)) / r
    return np.sqrt(v * v - b * b * u * u)


@pytest.mark.parametrize("method", ["event", "rk4", "auto"])
def test_peak_of_continuous_motion_against_den_hartog(method):
    """Force scene, b = 0.05, r between the singular points 1/5 and 1/3 of U: the motion is continuous
    and max|x| (peak_transmissibility) has a local maximum near r = 0.279. The exact peak equals the closed
    form's maximum (SciPy's bounded search to 1e-12 in r) to 1e-8 (rk4, a fourth-order integrator at its
    default steps, to 1e-6), and lies where it does to 1e-4 (a
    smooth maximum locates only to the square root of the value's accuracy)."""
    b = 0.05
    truth = minimize_scalar(lambda r: -_den_hartog_amplitude(r, b), bounds=(0.26, 0.30), method="bounded",
                            options={"xatol": 1e-12})
    ds = fs.peak(_spec("force", {"start": 0.24, "stop": 0.31, "num": 15}, [b], method),
                 variable="peak_transmissibility")
    assert not bool(ds.resonance_at_edge[0])
    assert float(ds.resonance_peak[0]) == pytest.approx(-truth.fun, rel=1e-6 if method == "rk4" else 1e-8)
    assert float(ds.resonance_frequency_ratio[0]) == pytest.approx(truth.x, abs=1e-4)
    assert ds.resonance_regime[0] == Regime.CONTINUOUS


def test_unbounded_resonance_is_an_infinite_peak_at_r_1():
    """Undamped, b below pi/4: the amplitude at r = 1 grows without bound (Den Hartog); above, finite."""
    ds = fs.peak(_spec("force", {"start": 0.5, "stop": 1.5, "num": 41}, [0.5, 0.9]))
    assert np.isposinf(float(ds.resonance_peak[0]))
    assert float(ds.resonance_frequency_ratio[0]) == pytest.approx(1.0, abs=1e-9)
    assert np.isfinite(float(ds.resonance_peak[1]))


def test_every_local_maximum_with_the_largest_marked():
    """Joined, beta = 1.2 from r = 0.05: the stuck mass rides the wall at low frequency (T = 1 on the
    grid's first point, unrefined, at_edge) and the stick-slip resonance below 1 near r = 1.37: two maxima,
    the largest (1, the edge) marked."""
    ds = fs.peak(_spec("joined", {"start": 0.05, "stop": 3.0, "num": 60}, [1.2]))
    values = ds.local_peak[0].values
    assert np.count_nonzero(np.isfinite(values)) == 2
    largest = ds.local_largest[0].values
    assert largest.sum() == 1
    assert values[largest][0] == 1.0 and ds.local_at_edge[0].values[largest][0]
    inner = np.isfinite(values) & ~largest
    assert 0.5 < values[inner][0] < 1.0
    assert float(ds.resonance_peak[0]) == 1.0


def _peak_of(excitation, beta, effects=None, r=None):
    r = r or {"start": 0.05, "stop": 4.0, "num": 80}
    return fs.peak(_spec(excitation, r, list(beta), effects=effects)).resonance_peak.values


def test_joined_optimum_is_the_least_friction_whose_peak_is_the_wall_motion():
    """Joined: the stuck mass moves with the wall (T = 1), so the peak never falls below 1; it falls to 1 at
    a finite friction and stays there. The optimum is interior to the friction range (the peak is higher
    on both sides' first levels below it, and no lower above), and a brute-force scan of friction
    (0.002 apart) crosses to 1 within one step of it."""
    ds = fs.optimize(_spec("joined", {"start": 0.05, "stop": 4.0, "num": 80}, {"start": 0.8, "stop": 1.6, "num": 9}))
    assert ds.attrs["optimum_kind"] == "plateau"
    b_opt = float(ds.optimum_force_ratio)
    assert 1.0 < b_opt < 1.1
    assert float(ds.optimum_peak) == 1.0
    scan = np.arange(1.0, 1.1, 0.002)
    p = _peak_of("joined", scan)
    assert np.all(p >= 1.0)
    first = scan[np.argmax(p <= 1.0)]
    assert p[0] > 1.0 and abs(first - b_opt) <= 0.002 + 1e-8
    assert np.all(p[scan > b_opt + 1e-6] == 1.0)


def test_base_optimum_is_no_motion_at_beta_1():
    """Base (wall fixed): friction always lowers the peak, down to 0 where the mass never moves (beta >= 1,
    the force never overcomes friction): no interior optimum. A scan shows the curve falling."""
    ds = fs.optimize(_spec("base", {"start": 0.05, "stop": 4.0, "num": 80}, {"start": 0.5, "stop": 1.2, "num": 8}))
    assert ds.attrs["optimum_kind"] == "plateau"
    assert float(ds.optimum_force_ratio) == pytest.approx(1.0, abs=1e-6)
    assert float(ds.optimum_peak) == 0.0
    scan = np.linspace(0.8, 0.99, 9)
    p = _peak_of("base", scan)
    assert np.all(np.diff(p) < 0) and np.all(p > 0)


@pytest.mark.slow
def test_jenkins_optimum_against_a_brute_force_scan():
    """Jenkins contact, kappa = 1, base: stuck, the mass is an undamped oscillator of stiffness 1 + kappa
    (infinite peak at r = sqrt 2); slipping freely, of stiffness 1 (infinite at r = 1): the peak has an
    interior minimum in beta. The golden-section optimum is no higher than every level of a scan 0.01 apart
    around it and within 0.01 of the scan's best."""
    effects = {"contact_stiffness": 1.0}
    r = {"start": 0.5, "stop": 2.0, "num": 61}
    ds = fs.optimize(_spec("base", r, {"start": 0.2, "stop": 2.0, "num": 10}, effects=effects))
    assert ds.attrs["optimum_kind"] == "interior"
    b_opt, p_opt = float(ds.optimum_force_ratio), float(ds.optimum_peak)
    scan = np.arange(b_opt - 0.05, b_opt + 0.0501, 0.01)
    p = _peak_of("base", scan, effects, r)
    assert p_opt <= p.min() * (1 + 1e-9)
    assert abs(scan[np.argmin(p)] - b_opt) <= 0.01


@pytest.mark.parametrize("spec, message", [
    (_spec("force", [0.5, 1.0, 2.0], [0.5], "theory"), "method: the resonance peak is built on"),
    (_spec("force", [0.5, 2.0], [0.5]), "at least 3 frequency ratios"),
])
def test_refusals(spec, message):
    with pytest.raises(fs.FsweepError, match=message):
        fs.peak(spec)


def test_optimize_refuses_too_few_levels_and_a_bad_tolerance():
    spec = _spec("force", [0.5, 1.0, 2.0], [0.5, 0.6])
    with pytest.raises(fs.FsweepError, match="at least 3 force ratios"):
        fs.optimize(spec)
    with pytest.raises(fs.FsweepError, match="r_tol must be a positive number"):
        fs.peak(spec, r_tol=0)
    with pytest.raises(fs.FsweepError, match="variable must be one of"):
        fs.peak(spec, variable="phase")


def test_cli_optimize_prints_the_optimum_and_writes_the_curve(tmp_path):
    """fsweep optimize SPEC -o FILE: the optimum on one line, the Dataset in FILE as fs.optimize returns it."""
    import xarray as xr
    from click.testing import CliRunner

    from friction_sweep.cli import main

    spec = tmp_path / "base.yaml"
    spec.write_text("scene: {excitation: base}\ngrid: {frequency_ratio: {start: 0.05, stop: 4.0, num: 80}, "
                    "force_ratio: {start: 0.5, stop: 1.2, num: 8}}\nmethod: event\n")
    out = tmp_path / "opt.h5"
    done = CliRunner().invoke(main, ["optimize", str(spec), "-o", str(out)])
    assert done.exit_code == 0, done.output
    assert done.output.startswith("optimum (plateau): force_ratio ")
    with xr.open_dataset(out) as ds:
        direct = fs.optimize(str(spec))
        assert float(ds.optimum_force_ratio) == float(direct.optimum_force_ratio)
        np.testing.assert_array_equal(ds.resonance_peak.values, direct.resonance_peak.values)
        assert ds.attrs["optimum_kind"] == "plateau"


@pytest.mark.parametrize("zeta", [0.05, 0.2])
def test_linear_damped_peak_and_phase_resonance_against_the_closed_form(zeta):
    """No friction, viscous damping zeta (force scene): T = 1 / sqrt((1 - r^2)^2 + (2 zeta r)^2) peaks at
    r = sqrt(1 - 2 zeta^2) with 1 / (2 zeta sqrt(1 - zeta^2)); the lag is 90 degrees at r = 1 exactly, where
    T = 1 / (2 zeta)."""
    ds = fs.peak(_spec("force", {"start": 0.5, "stop": 1.5, "num": 11}, [0.0], effects={"viscous_damping": zeta}))
    assert float(ds.resonance_peak[0]) == pytest.approx(1 / (2 * zeta * np.sqrt(1 - zeta**2)), rel=1e-8)
    assert float(ds.resonance_frequency_ratio[0]) == pytest.approx(np.sqrt(1 - 2 * zeta**2), abs=1e-4)
    crossings = ds.phase_resonance_frequency_ratio[0].values
    assert np.count_nonzero(np.isfinite(crossings)) == 1
    assert crossings[0] == pytest.approx(1.0, abs=1e-9)
    assert float(ds.phase_resonance_value[0, 0]) == pytest.approx(1 / (2 * zeta), rel=1e-8)


def test_phase_jumping_across_90_at_an_unbounded_resonance_is_no_crossing():
    """Undamped, b = 0.3 < pi/4: the amplitude at r = 1 is unbounded and the lag jumps across 90 degrees
    there (Den Hartog: sin(phi) -> 4 b / pi from either side), so there is no phase resonance; b = 0.9:
    bounded stick-slip, the lag passes through 90 once, and a plain sweep at the r found lags by 90."""
    ds = fs.peak(_spec("force", {"start": 0.5, "stop": 2.0, "num": 31}, [0.3, 0.9]))
    r90 = ds.phase_resonance_frequency_ratio.values
    assert not np.isfinite(r90[0]).any()
    assert np.isfinite(r90[1]).sum() == 1
    plain = fs.sweep(_spec("force", [float(r90[1, 0])], [0.9]))
    assert float(plain.phase.squeeze()) == pytest.approx(90.0, abs=1e-6)
