"""Issue 31 items 1-2: structures from a reduced model's matrices (.npz, .mat) or its modes, and structures in
physical units. The truths: the same structure written as masses and springs (the cube bit for bit), the
modal relations Phi^T M Phi = I, Phi^T K Phi = Omega^2, Phi^T C Phi = 2 zeta Omega (SciPy's eigh, not the
code's), and the dimensionless map written out here from the module's equations."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from scipy.linalg import eigh

import friction_sweep as fs
from friction_sweep.batch.structure_sweep import structure_def
from friction_sweep.cli import main
from friction_sweep.spec.parse import load_spec, parse_spec_text
from friction_sweep.structures import assemble

#: a 3-mass chain (ground - a - b - c) with a rigid contact at c and a Jenkins contact at a, force on a
MASSES = {"a": 1.0, "b": 0.5, "c": 0.1}
SPRINGS = (("ground", "a", 1.0), ("a", "b", 2.0), ("b", "c", 3.0))
DASHPOT = 0.01  # ground - a

CONTACTS = """\
  contacts:
    - {name: platform, between: [c, ground], friction: 0.3}
    - {name: root, between: [a, base], friction: 0.2, stiffness: 20}
  forcing: {a: 1.0}
grid:
  frequency: {start: 0.3, stop: 2.5, num: 6}
  friction_scale: [0.5, 2.0]
"""
AS_MASSES = """\
scene: {excitation: force}
structure:
  masses: {a: 1.0, b: 0.5, c: 0.1}
  springs: [[ground, a, 1.0], [a, b, 2.0], [b, c, 3.0]]
  dampers: [[ground, a, 0.01]]
""" + CONTACTS


def _chain() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The chain's M, K, C written out by hand (each entry the sum assemble's springs make, in their order)."""
    k1, k2, k3 = (s[2] for s in SPRINGS)
    M = np.diag(list(MASSES.values()))
    K = np.array([[0.0 + k1 + k2, -k2, 0.0], [-k2, 0.0 + k2 + k3, -k3], [0.0, -k3, 0.0 + k3]])
    C = np.zeros((3, 3))
    C[0, 0] = DASHPOT
    return M, K, C


def _as_matrices(file: str, extra: str = "") -> str:
    return f"scene: {{excitation: force}}\nstructure:\n  matrices: {{file: {file}, dofs: [a, b, c]{extra}}}\n" + CONTACTS


def _same_cube(a: xr.Dataset, b: xr.Dataset) -> None:
    assert set(a.data_vars) == set(b.data_vars)
    for name in [*a.data_vars, "frequency", "friction_scale", "dof", "contact"]:
        assert np.array_equal(a[name].values, b[name].values, equal_nan=a[name].dtype.kind == "f"), name


@pytest.fixture(scope="module")
def masses_cube(tmp_path_factory) -> xr.Dataset:
    path = tmp_path_factory.mktemp("masses") / "spec.yaml"
    path.write_text(AS_MASSES)
    return fs.sweep(path)


def test_an_npz_model_gives_the_cube_of_its_masses_and_springs_bit_for_bit(masses_cube, tmp_path):
    np.savez(tmp_path / "rom.npz", **dict(zip("MKC", _chain(), strict=True)))
    (tmp_path / "spec.yaml").write_text(_as_matrices("rom.npz"))
    spec = load_spec(tmp_path / "spec.yaml")
    a, b = assemble(structure_def(spec)), assemble(structure_def(load_spec(_write(tmp_path, AS_MASSES))))
    for name in ("M", "K", "C", "W", "F_cos", "F_sin_per_w", "mu", "mu_s", "kt", "e"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    res = CliRunner().invoke(main, ["run", str(tmp_path / "spec.yaml"), "-o", str(tmp_path / "out.h5"), "-q"])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(tmp_path / "out.h5", engine="h5netcdf") as got:
        _same_cube(got.load(), masses_cube)
        assert got.attrs["structure"].startswith('{"matrices": {"file": "rom.npz"')


def test_a_mat_model_with_a_sparse_stiffness_gives_the_same_cube(masses_cube, tmp_path):
    import scipy.sparse

    M, K, C = _chain()
    scipy.io.savemat(tmp_path / "rom.mat", {"M": M, "K": scipy.sparse.csc_matrix(K), "C": C})
    sub = tmp_path / "models"
    sub.mkdir()
    (sub / "rom.mat").write_bytes((tmp_path / "rom.mat").read_bytes())
    # a relative file is found beside the spec, wherever the command runs
    _same_cube(fs.sweep(_write(tmp_path, _as_matrices("models/rom.mat"))), masses_cube)


def _write(d: Path, text: str, name: str = "other.yaml") -> Path:
    (d / name).write_text(text)
    return d / name


def test_modal_damping_ratios_give_the_damping_of_each_mode(tmp_path):
    M, K, _ = _chain()
    np.savez(tmp_path / "rom.npz", M=M, K=K)
    zeta = [0.01, 0.02, 0.05]
    spec = load_spec(_write(tmp_path, _as_matrices("rom.npz", f", damping_ratios: {zeta}")))
    C = assemble(structure_def(spec)).C
    lam, phi = eigh(K, M)
    np.testing.assert_allclose(phi.T @ C @ phi, np.diag(2 * np.array(zeta) * np.sqrt(lam)), atol=1e-13)
    one = load_spec(_write(tmp_path, _as_matrices("rom.npz", ", damping_ratios: [0.02]")))
    np.testing.assert_allclose(phi.T @ assemble(structure_def(one)).C @ phi, np.diag(0.04 * np.sqrt(lam)), atol=1e-13)


def test_a_structure_known_by_its_modes_is_the_structure_of_those_modes(tmp_path):
    M, K, _ = _chain()
    lam, phi = eigh(K, M)  # mass-normalised: phi^T M phi = I
    zeta = np.array([0.01, 0.02, 0.03])
    shapes = ", ".join(f"{name}: [{', '.join(map(repr, row))}]" for name, row in zip("abc", phi.tolist(), strict=True))
    text = (f"scene: {{excitation: force}}\nstructure:\n  modes:\n    frequencies: {np.sqrt(lam).tolist()}\n"
            f"    damping_ratios: {zeta.tolist()}\n    shapes: {{{shapes}}}\n" + CONTACTS)
    a = assemble(structure_def(load_spec(_write(tmp_path, text))))
    np.testing.assert_allclose(a.M, M, atol=1e-12)
    np.testing.assert_allclose(a.K, K, atol=1e-12)
    np.testing.assert_allclose(phi.T @ a.C @ phi, np.diag(2 * zeta * np.sqrt(lam)), atol=1e-12)
    assert a.dof_names == ("a", "b", "c")


# ---- physical units ----------------------------------------------------------------------------------------

PHYSICAL = """\
scene: {excitation: force}
structure:
  masses: {blade: 2 kg, damper: 0.25 kg}
  springs: [[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]
  dampers: [[ground, blade, 4 N*s/m]]
  contacts:
    - {name: platform, between: [damper, ground], friction: {coefficient: 0.5, normal_load: 40 N}}
    - {name: root, between: [blade, base], friction: 8 N, stiffness: 400 kN/m}
  forcing: {blade: 30 N}
grid:
  frequency: {start: 10 Hz, stop: 60 Hz, num: 6}
  friction_scale: [0.5, 1.0]
"""


def _dimensionless(cube: xr.Dataset) -> str:
    """The plain spec PHYSICAL maps to: every value over the cube's recorded scales, as the map divides."""
    m0, k0 = float(cube["mass_scale"]), float(cube["stiffness_scale"])
    c0, f0 = m0 * float(cube["reference_frequency"]), float(cube["force_scale"])

    def r(x: float) -> str:
        return repr(float(x))

    return f"""\
scene: {{excitation: force}}
structure:
  masses: {{blade: {r(2.0 / m0)}, damper: {r(0.25 / m0)}}}
  springs: [[ground, blade, {r(40e3 / k0)}], [blade, damper, {r(80e3 / k0)}]]
  dampers: [[ground, blade, {r(4.0 / c0)}]]
  contacts:
    - {{name: platform, between: [damper, ground], friction: {r(0.5 * 40.0 / f0)}}}
    - {{name: root, between: [blade, base], friction: {r(8.0 / f0)}, stiffness: {r(400e3 / k0)}}}
  forcing: {{blade: {r(30.0 / f0)}}}
grid:
  frequency: [{', '.join(map(r, cube['frequency'].values))}]
  friction_scale: [0.5, 1.0]
"""


@pytest.fixture(scope="module")
def physical_cube(tmp_path_factory) -> xr.Dataset:
    path = tmp_path_factory.mktemp("physical") / "spec.yaml"
    path.write_text(PHYSICAL)
    return fs.sweep(path)


def _stuck_and_free() -> tuple[float, float]:
    """The first natural angular frequencies, contacts stuck (the platform rigid, the root its spring) and free."""
    M = np.diag([2.0, 0.25])
    K = np.array([[120e3, -80e3], [-80e3, 80e3]])
    free = math.sqrt(eigh(K, M, eigvals_only=True)[0])
    stuck = math.sqrt((120e3 + 400e3) / 2.0)  # the damper held: the blade alone on its springs and the root's
    return stuck, free


def test_a_physical_spec_gives_the_cube_of_the_dimensionless_spec_it_maps_to(physical_cube, tmp_path):
    _same_cube(fs.sweep(_write(tmp_path, _dimensionless(physical_cube))), physical_cube)


def test_the_physical_cube_records_its_scales_and_both_frequency_ratios(physical_cube):
    stuck, free = _stuck_and_free()
    c = physical_cube
    assert float(c["reference_frequency"]) == pytest.approx(stuck, rel=1e-12)
    assert float(c["mass_scale"]) == 2.0 and float(c["force_scale"]) == 30.0
    assert float(c["length_scale"]) == pytest.approx(30.0 / (2.0 * stuck**2), rel=1e-12)
    hz = np.linspace(10.0, 60.0, 6)
    np.testing.assert_allclose(c["frequency_hz"].values, hz, rtol=1e-11)
    np.testing.assert_allclose(c["frequency_ratio_stuck"].values, 2 * np.pi * hz / stuck, rtol=1e-11)
    np.testing.assert_allclose(c["frequency_ratio_free"].values, 2 * np.pi * hz / free, rtol=1e-11)
    np.testing.assert_array_equal(c["friction_force"].values, [[10.0, 4.0], [20.0, 8.0]])
    assert c["frequency_hz"].attrs["units"] == "Hz" and c["length_scale"].attrs["units"] == "m"


def test_frequency_ratios_against_the_free_structure_and_rad_per_s_units(physical_cube, tmp_path):
    stuck, free = _stuck_and_free()
    text = PHYSICAL.replace("frequency: {start: 10 Hz, stop: 60 Hz, num: 6}",
                            "frequency_ratio: [0.5, 1.0, 1.5]\n  reference: free")
    spec = load_spec(_write(tmp_path, text))
    assert spec.physical is not None and spec.physical.omega == pytest.approx(free, rel=1e-12)
    np.testing.assert_array_equal(spec.frequency, [0.5, 1.0, 1.5])
    in_rad = load_spec(_write(tmp_path, PHYSICAL.replace("{start: 10 Hz, stop: 60 Hz, num: 6}",
                                                         f"[{2 * math.pi * 10.0!r} rad/s]")))
    assert in_rad.frequency[0] == pytest.approx(physical_cube["frequency"].values[0], rel=1e-12)


def test_a_plain_structure_takes_frequency_ratios_too(tmp_path):
    spec = load_spec(_write(tmp_path, AS_MASSES.replace("frequency: {start: 0.3, stop: 2.5, num: 6}",
                                                        "frequency_ratio: [1.0]")))
    M, K, _ = _chain()
    N = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])  # the rigid platform holds c; the root is a spring on a
    Ks = N.T @ (K + np.diag([20.0, 0.0, 0.0])) @ N
    assert spec.frequency[0] == pytest.approx(math.sqrt(eigh(Ks, N.T @ M @ N, eigvals_only=True)[0]), rel=1e-12)


def test_a_free_reference_with_a_mass_held_only_by_a_contact_is_refused(tmp_path):
    text = PHYSICAL.replace("[[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]", "[[ground, blade, 40 kN/m]]")
    text = text.replace("frequency: {start: 10 Hz, stop: 60 Hz, num: 6}", "frequency_ratio: [1.0]\n  reference: free")
    with pytest.raises(fs.SpecError, match="rigid-body motion"):
        parse_spec_text(text)


@pytest.mark.parametrize("text", [PHYSICAL, AS_MASSES.replace(", [b, c, 3.0]]", "]")], ids=["physical", "held-by-contact"])
def test_the_written_cube_passes_the_readers_audit(text, tmp_path):
    """fsweep info audits a cube on opening: the physical coordinates and scales are the schema's; a structure
    with a mass held only by a contact has no free natural frequency, and no free frequency ratio."""
    spec = _write(tmp_path, text, "spec.yaml")
    out = tmp_path / "out.h5"
    assert CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "-q"]).exit_code == 0
    res = CliRunner().invoke(main, ["info", str(out)])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(out, engine="h5netcdf") as cube:
        assert ("frequency_ratio_free" in cube.coords) == (text == PHYSICAL)
        assert "frequency_ratio_stuck" in cube.coords


def test_a_physical_model_reads_its_matrices_in_si_and_gives_the_physical_cube(physical_cube, tmp_path):
    M = np.diag([2.0, 0.25])
    K = np.array([[0.0 + 40e3 + 80e3, -80e3], [-80e3, 0.0 + 80e3]])
    C = np.array([[4.0, 0.0], [0.0, 0.0]])
    np.savez(tmp_path / "rom.npz", M=M, K=K, C=C)
    text = PHYSICAL.replace("""  masses: {blade: 2 kg, damper: 0.25 kg}
  springs: [[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]
  dampers: [[ground, blade, 4 N*s/m]]
""", "  matrices: {file: rom.npz, dofs: [blade, damper]}\n")
    # the map divides the summed K where the masses' spec divides each spring: the same to rounding, not bit for
    # bit (the bit-for-bit claims are a model against its masses in one set of units, and a physical spec
    # against its dimensionless one)
    got = fs.sweep(_write(tmp_path, text))
    assert float(got["reference_frequency"]) == float(physical_cube["reference_frequency"])
    # the rigid platform's regimes agree; the Jenkins root's stop count at a near-grazing slider does not
    # survive a rounding change in K (0 or 1 stop, 2 or 3 slips, at one amplitude): the engine's, reported
    np.testing.assert_array_equal(got["regime"].sel(contact="platform").values,
                                  physical_cube["regime"].sel(contact="platform").values)
    np.testing.assert_allclose(got["amplitude"].values, physical_cube["amplitude"].values, rtol=1e-9, atol=1e-12)


def test_physical_modes_take_their_frequencies_in_hz(tmp_path):
    M = np.diag([2.0, 0.25])
    K = np.array([[120e3, -80e3], [-80e3, 80e3]])
    lam, phi = eigh(K, M)
    hz = (np.sqrt(lam) / (2 * np.pi)).tolist()
    shapes = ", ".join(f"{name}: [{', '.join(map(repr, row))}]" for name, row in
                       zip(("blade", "damper"), phi.tolist(), strict=True))
    text = PHYSICAL.replace("""  masses: {blade: 2 kg, damper: 0.25 kg}
  springs: [[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]
  dampers: [[ground, blade, 4 N*s/m]]
""", f"  modes: {{frequencies: [{hz[0]!r} Hz, {hz[1]!r} Hz], shapes: {{{shapes}}}}}\n")
    spec = load_spec(_write(tmp_path, text))
    M_got, K_got, _ = spec.structure.given_matrices
    np.testing.assert_allclose(M_got, M, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(K_got, K, rtol=1e-10, atol=1e-6)


def test_a_physical_base_excitation_maps_lengths_to_the_base_amplitude(tmp_path):
    """Under base excitation L = Y and F_0 = k_0 Y: the plain spec has base_amplitude 1 and the same cube."""
    text = (PHYSICAL.replace("{excitation: force}", "{excitation: base}").replace("  forcing: {blade: 30 N}\n",
                                                                                  "  base_amplitude: 0.5 mm\n")
            .replace("[[ground, blade, 40 kN/m]", "[[base, blade, 40 kN/m]"))
    cube = fs.sweep(_write(tmp_path, text, "physical.yaml"))
    assert float(cube["length_scale"]) == 0.5e-3
    assert float(cube["force_scale"]) == float(cube["stiffness_scale"]) * 0.5e-3
    plain = (_dimensionless(cube).replace("{excitation: force}", "{excitation: base}")
             .replace("springs: [[ground, blade,", "springs: [[base, blade,"))
    plain = "\n".join(line for line in plain.splitlines() if not line.startswith("  forcing:")) + "\n"
    _same_cube(fs.sweep(_write(tmp_path, plain.replace("grid:", "  base_amplitude: 1.0\ngrid:"))), cube)


def test_a_checkpoint_of_another_model_file_is_not_reused(tmp_path):
    """The matrices are no part of the spec's text: the checkpoint's fingerprint holds their digest."""
    from friction_sweep.batch.structure_sweep import checkpoint_key

    M, K, C = _chain()
    np.savez(tmp_path / "rom.npz", M=M, K=K, C=C)
    spec = _write(tmp_path, _as_matrices("rom.npz"))
    before = checkpoint_key(load_spec(spec), {}, {})
    assert checkpoint_key(load_spec(spec), {}, {}) == before
    np.savez(tmp_path / "rom.npz", M=M, K=K * 1.01, C=C)
    assert checkpoint_key(load_spec(spec), {}, {}) != before


@pytest.mark.parametrize("form", ["npz", "physical"])
def test_check_and_info_read_the_structure_a_reduced_or_physical_cube_solved(form, tmp_path):
    """A reduced model's cube records the matrices solved (its file may be gone), a physical cube its SI
    structure and the scales: `fsweep check` holds the cube to the linear limits of the structure the engine
    solved (the dimensionless one) and `fsweep info` gives its natural frequencies in the cube's frequency
    units (stuck: 1 where omega_0 is the stuck structure's, by the map's definition)."""
    if form == "npz":
        np.savez(tmp_path / "rom.npz", **dict(zip("MKC", _chain(), strict=True)))
        text = _as_matrices("rom.npz").replace("friction_scale: [0.5, 2.0]", "friction_scale: [0.0, 2.0, 1000.0]")
    else:
        text = PHYSICAL.replace("friction_scale: [0.5, 1.0]", "friction_scale: [0.0, 1.0, 1000.0]")
    spec = _write(tmp_path, text, "spec.yaml")
    out = tmp_path / "out.h5"
    assert CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "-q"]).exit_code == 0
    (tmp_path / "rom.npz").unlink(missing_ok=True)
    res = CliRunner().invoke(main, ["check", str(out)])
    assert res.exit_code == 0 and "free_limit  ok" in res.output, res.output
    info = CliRunner().invoke(main, ["info", str(out)]).output
    stuck = next(line for line in info.splitlines() if "every contact stuck" in line)
    if form == "physical":
        assert float(stuck.split(":")[-1]) == pytest.approx(1.0, rel=1e-12)
        assert "stuck_limit ok" in res.output
    else:  # the chain with c held and a's root stuck: K + 20 e_a e_a^T on (a, b) with c fixed
        M, K, _ = _chain()
        Ks = K[:2, :2] + np.diag([20.0, 0.0])
        assert float(stuck.split(":")[-1].split(",")[0]) == pytest.approx(math.sqrt(eigh(Ks, M[:2, :2],
                                                                                     eigvals_only=True)[0]), rel=1e-5)
        assert "reduced model (matrices) from rom.npz" in info
