"""Issue 32 item 4 for structures: the exact harmonics of every mass's displacement and every contact's force
(outputs: harmonics; friction_sweep.structures.harmonics), against truths that need no engine: the moments'
exact series (in 80-digit decimal arithmetic), the linear structure without friction, a slipping rigid contact's
square wave, the half-period symmetry of a symmetric structure's orbit; and the spec, run and cube around them.
The independent integrator's orbit checks them in test_structure_reference.py.
"""

from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir
from structure_specs import two_mass

from friction_sweep.cli import main
from friction_sweep.kernels.structure.flow import KT
from friction_sweep.kernels.structure.fourier import moments
from friction_sweep.structures import StructureDef, assemble, solve_points
from friction_sweep.structures.harmonics import orbit_harmonics
from friction_sweep.structures.model import ContactDef

#: the issue's blade and under-platform damper with its rigid platform contact (symmetric under x -> -x)
CHAIN = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.02),),
                     (ContactDef(name="platform", between=("damper", "ground"), friction=0.3),), {"blade": 1.0})


def _series(x: float, j: int) -> complex:
    """m_j(x) = int_0^1 u^j / j! e^{-i x u} du = sum_n (-i x)^n / (n! j! (j + n + 1)), in 80 digits."""
    with localcontext() as ctx:
        ctx.prec = 80
        X = Decimal(x)
        parts = [Decimal(0), Decimal(0)]
        power = Decimal(1)  # x^n
        for n in range(300):
            term = power / (Decimal(math.factorial(n)) * Decimal(math.factorial(j)) * (j + n + 1))
            parts[n % 2] += term if n % 4 < 2 else -term
            power *= X
        return complex(float(parts[0]), -float(parts[1]))


@pytest.mark.parametrize("x", [0.0, 1e-9, 1e-3, 0.7, 1.0, 2.5, 2 * math.pi, 9.3, 4 * math.pi, 15.99, 16.0, 16.5,
                               25.1, 32.0])
def test_moments_are_the_exact_series(x):
    """Every moment up to the flow's Taylor degree, forward where j < x, backward from the tail series above,
    to rounding against its scale 1/(j+1)! (the bound of |m_j|), from x = 0 to the largest a step reaches
    (k w h <= 64 x 1/2)."""
    out = np.empty(KT + 1, dtype=complex)
    moments(x, out)
    for j in range(KT + 1):
        assert abs(out[j] - _series(x, j)) * math.factorial(j + 1) < 1e-15, j


def test_without_friction_the_harmonics_are_the_linear_response():
    """friction_scale 0: x = Re[(K - w^2 M + i w C)^-1 F e^{i w t}]: X_1 that complex amplitude, every other
    harmonic (the mean too) zero, the contact force zero."""
    a = assemble(CHAIN)
    w = np.array([0.6, 1.1, 2.5])
    got = orbit_harmonics(a, w, np.zeros(3), 12)
    for i, wi in enumerate(w):
        X = np.linalg.solve(a.K - wi ** 2 * a.M + 1j * wi * a.C, a.F_cos)
        scale = np.abs(X).max()
        np.testing.assert_allclose(got["displacement"][i, 1], X, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(np.delete(got["displacement"][i], 1, axis=0), 0.0, atol=1e-12 * scale)
        assert (got["contact_force"][i] == 0).all()


def test_a_slipping_rigid_contact_is_a_square_wave():
    """The chain at w = 2, friction x 0.1: the damper never sticks, so its contact force is +-mu, a square wave
    of half-period symmetry: |F_k| = 4 mu / (pi k) for odd k, and 0 for even k to the orbit's own symmetry
    (a converged orbit repeats to steady_tol, 1e-10)."""
    a = assemble(CHAIN)
    got = orbit_harmonics(a, [2.0], [0.1], 63)
    solved = solve_points(a, [2.0], [0.1])
    assert solved["stops_per_period"][0, 0] == 0 and solved["stuck_fraction"][0, 0] == 0  # slipping throughout
    mu = 0.3 * 0.1
    k = np.arange(64)
    F = got["contact_force"][0, :, 0]
    np.testing.assert_allclose(np.abs(F[1::2]), 4 * mu / (np.pi * k[1::2]), rtol=1e-12)
    np.testing.assert_allclose(F[0::2], 0.0, atol=1e-10 * mu)


def test_a_symmetric_orbit_has_odd_harmonics_only():
    """The chain is symmetric under x -> -x, and so is its stick-slip orbit at w = 0.8 over half a period: every
    even harmonic of x and of the contact force vanishes, to rounding."""
    got = orbit_harmonics(assemble(CHAIN), [0.8], [1.0], 64)
    X, F = got["displacement"][0], got["contact_force"][0]
    np.testing.assert_allclose(X[0::2], 0.0, atol=1e-13 * np.abs(X).max())
    np.testing.assert_allclose(F[0::2], 0.0, atol=1e-13 * np.abs(F).max())
    assert np.abs(X[1:10:2]).min() > 1e-6 * np.abs(X).max()  # and the odd ones do not


def test_first_harmonic_is_the_engines_amplitude_and_phase():
    """|X_1| and -arg X_1 are the solve's amplitude and phase (those by Gauss-Legendre quadrature on the flow's
    steps, these in closed form), in every regime of the chain (the phase where the mass moves: the damper held
    stuck at w = 0.8, friction x 5, has none)."""
    a = assemble(CHAIN)
    w = np.array([0.4, 0.8, 1.2, 2.0, 0.8])
    s = np.array([1.0, 1.0, 0.1, 0.1, 5.0])
    solved = solve_points(a, w, s)
    X1 = orbit_harmonics(a, w, s, 1, solved=solved)["displacement"][:, 1]
    np.testing.assert_allclose(np.abs(X1), solved["amplitude"], rtol=1e-12, atol=1e-14)
    lag = np.degrees(-np.angle(X1))
    moving = solved["amplitude"] > 1e-9 * solved["amplitude"].max()
    np.testing.assert_allclose(((lag - solved["phase"] + 180.0) % 360.0 - 180.0)[moving], 0.0, atol=1e-9)


HARMONICS = two_mass(5, "[0.0, 1.0]", "[amplitude, phase, regime, harmonics]").replace(
    "method: event\n", "method: event\nsettings: {harmonics: 6}\n")


def test_run_writes_the_harmonics_with_their_coordinate(tmp_path):
    """fsweep run: each mass's and each contact's coefficients on (friction_scale, frequency, dof | contact,
    harmonic), the harmonic numbers 0..H as a coordinate; X_1 is the cube's amplitude; with static above kinetic
    friction the moving start's twins too."""
    spec = tmp_path / "h.yaml"
    spec.write_text(HARMONICS.replace("stiffness: 20", "stiffness: 20, static_friction_ratio: 1.5"))
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "h.h5"), "-q"])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(tmp_path / "h.h5", engine="h5netcdf") as ds:
        assert ds["harmonic"].values.tolist() == list(range(7))
        assert ds["response_harmonic_real"].dims == ("friction_scale", "frequency", "dof", "harmonic")
        assert ds["friction_harmonic_imag_moving"].dims == ("friction_scale", "frequency", "contact", "harmonic")
        for suffix in ("", "_moving"):
            X1 = (ds["response_harmonic_real" + suffix] + 1j * ds["response_harmonic_imag" + suffix]).sel(harmonic=1)
            np.testing.assert_allclose(np.abs(X1), ds["amplitude" + suffix], rtol=1e-12, atol=1e-14)
        # friction_scale 0: no contact force at all
        assert (ds["friction_harmonic_real"].sel(friction_scale=0.0) == 0).all()


@pytest.mark.parametrize("change, key, reason", [
    (("method: event\nsettings: {harmonics: 6}\n", "method: rk4\n"), "method", "integrated exactly"),
    (("outputs: [amplitude, phase, regime, harmonics]", "outputs: [amplitude]"), "settings.harmonics",
     "harmonics is not listed in outputs"),
    (("settings: {harmonics: 6}", "settings: {harmonics: 65}"), "settings.harmonics", "64"),
    (("settings: {harmonics: 6}\n", "settings: {harmonics: 6}\nsweep: {direction: up}\n"), "sweep",
     "does not store harmonics"),
])
def test_spec_errors_name_the_key(tmp_path, change, key, reason):
    spec = tmp_path / "bad.yaml"
    text = HARMONICS.replace(*change)
    assert text != HARMONICS
    spec.write_text(text)
    with in_dir(tmp_path):
        res = CliRunner().invoke(main, ["run", str(spec), "-o", "bad.h5"])
        assert res.exit_code == 2 and isinstance(res.exception, SystemExit), res.output
        head, line = res.stderr.splitlines()
        assert head == "fsweep: error: invalid spec"
        assert line.startswith(f"{spec}:") and f": {key}: " in line and reason in line, line
        assert not (tmp_path / "bad.h5").exists()


def test_a_grid_of_frequency_ratios_takes_harmonics_and_histories(tmp_path):
    """With `grid: {frequency_ratio: ...}` the harmonics' size check reads that axis (it read `frequency`, and
    validation failed with a KeyError), and a time history's point is a ratio like the grid's: it lies at the
    grid's engine frequency of the same ratio."""
    spec = tmp_path / "r.yaml"
    spec.write_text(HARMONICS.replace("frequency: {start: 0.2, stop: 3.0, num: 5}",
                                      "frequency_ratio: [0.5, 1.0, 1.5]")
                    .replace("harmonics]", "harmonics, time_history]")
                    + "time_history: {points: [[1.0, 1.0]], samples_per_period: 32}\n")
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(tmp_path / "r.h5"), "-q"])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(tmp_path / "r.h5", engine="h5netcdf") as ds:
        assert ds.sizes["harmonic"] == 7 and ds.sizes["frequency"] == 3
        assert float(ds["history_frequency"][0]) == float(ds["frequency"][1])
