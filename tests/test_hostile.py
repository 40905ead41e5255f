"""Hostile input and faults: every case ends in one line, its documented exit code, no leftover file
and no damaged result (README, "What fsweep guarantees when things go wrong").

To add a case, add a row to CASES: the spec text (None: a good one), the command line, what to set
up first, the exit code, words the message must hold, and the files that must and must not exist
afterwards (paths relative to the case's folder; `*` globs). Every row also checks: no traceback,
one message line on failure, no temporary file anywhere in the folder.
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import hostile_cubes as hc
import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir
from structure_specs import two_mass

from friction_sweep.cli import main
from friction_sweep.codes import Regime, SteadyState

GOOD = """\
scene: {excitation: base}
grid:
  frequency_ratio: {start: 0.5, stop: 2.0, num: 40}
  force_ratio: [0.1, 0.4]
method: theory
output: out.h5
"""
EVENT = GOOD.replace("method: theory", "method: event")


def _nested(kind: str, depth: int) -> str:
    inner = "[" * depth + "]" * depth if kind == "list" else "{a: " * depth + "1" + "}" * depth
    return f"scene: {{excitation: base}}\ngrid: {{frequency_ratio: 1, force_ratio: 0.1}}\nx: {inner}\n"


def _alias_bomb() -> str:
    lines = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for i, name in enumerate("bcdefghi"):
        prev = "abcdefghi"[i]
        lines.append(f"{name}: &{name} [" + ", ".join(f"*{prev}" for _ in range(9)) + "]")
    return "\n".join(lines) + "\n"


def _merge_bomb() -> str:
    lines = ["a0: &a0 {k0: 1, k1: 1, k2: 1, k3: 1}"]
    for i in range(1, 9):
        lines.append(f"a{i}: &a{i} {{" + ", ".join(f"m{j}: *a{i - 1}" for j in range(10)) + "}")
    return "\n".join(lines) + "\n"


def _settings(method: str, text: str) -> str:
    return GOOD.replace("method: theory", f"method: {method}\nsettings: {{{text}}}")


# ---- set-ups: each gets the case folder --------------------------------------------------------


def _good_cube(d: Path) -> None:
    assert CliRunner().invoke(main, ["run", str(d / "spec.yaml"), "-o", str(d / "out.h5"), "-q"]).exit_code == 0
    (d / "before.bytes").write_bytes((d / "out.h5").read_bytes())


def _fifo(d: Path) -> None:
    os.mkfifo(d / "out.h5")


def _device(d: Path) -> None:
    try:
        os.mknod(d / "out.h5", stat.S_IFCHR | 0o600, os.makedev(1, 3))
    except PermissionError:
        pytest.skip("making a device node needs root")


def _socket(d: Path) -> None:
    import socket

    s = socket.socket(socket.AF_UNIX)
    s.bind(str(d / "out.h5"))
    s.close()


def _symlink_to_cube(d: Path) -> None:
    _good_cube(d)
    (d / "out.h5").rename(d / "real.h5")
    (d / "out.h5").symlink_to("real.h5")


def _dangling(d: Path) -> None:
    (d / "out.h5").symlink_to("nowhere/else.h5")


def _file_parent(d: Path) -> None:
    (d / "afile").write_text("not a folder")


def _partial_is_file(d: Path) -> None:
    (d / ".out.h5.partial").write_text("not a folder")


def _lock_is_folder(d: Path) -> None:
    (d / ".out.h5.lock").mkdir()


def _interrupted(d: Path, spec: str = EVENT, env: dict | None = None) -> None:
    """An event run stopped after two of its tiles (kill -9), with its checkpoint left."""
    code = (
        "import sys\n"
        "import friction_sweep.methods.event as e\n"
        "real, n = e.compute_tile, [0]\n"
        "def once(*a, **k):\n"
        "    n[0] += 1\n"
        "    if n[0] > 2:\n"
        "        import os, signal; os.kill(os.getpid(), signal.SIGKILL)\n"
        "    return real(*a, **k)\n"
        "e.compute_tile = once\n"
        "from friction_sweep.cli import main\n"
        "main(['run', 'spec.yaml', '-q', '--executor', 'serial'])\n"
    )
    (d / "spec.yaml").write_text(spec)
    subprocess.run([sys.executable, "-c", code], cwd=d, capture_output=True, check=False,
                   env={**os.environ, **(env or {})})
    assert len(list((d / ".out.h5.partial").glob("tile-*.npz"))) == 2


def _bad_manifest(d: Path) -> None:
    _interrupted(d, EVENT_LONG)
    (d / ".out.h5.partial" / "manifest.json").write_text("{not json")


def _truncated_tile(d: Path) -> None:
    _interrupted(d, EVENT_LONG)
    tile = d / ".out.h5.partial" / "tile-00001.npz"
    tile.write_bytes(tile.read_bytes()[:100])


def _other_sweep(d: Path) -> None:
    _interrupted(d, EVENT_LONG)
    (d / "spec.yaml").write_text(EVENT_LONG.replace("0.1, 0.4", "0.1, 0.5"))


EVENT_LONG = EVENT.replace("num: 40", "num: 100")


def _lock_to_victim(d: Path) -> None:
    (d / "victim.txt").write_text("precious")
    (d / ".out.h5.lock").symlink_to("victim.txt")


def _tile_folder(d: Path) -> None:
    _interrupted(d, EVENT_LONG)
    (d / ".out.h5.partial" / "tile-00003.npz").mkdir()


def _same_text(path: Path, text: str) -> None:
    assert path.read_text() == text, f"{path} was changed"


def _tamper(d: Path, value, name: str = "transmissibility") -> None:
    """A finished tile of the right shape whose `name` holds `value` everywhere (not computed)."""
    _interrupted(d, EVENT_LONG)
    tile = d / ".out.h5.partial" / "tile-00000.npz"
    with np.load(tile) as data:
        arrays = {k: data[k] for k in data.files}
    arrays[name] = np.full(arrays[name].shape, value)
    np.savez(tile, **arrays)


def _physical(system: str, force: str | None = "friction_force: [1 N]", ratio: str | None = "[1.0]",
              frequency: str | None = None) -> str:
    """A spec with `system:` (flow text), a force axis and a frequency axis (ratios, or physical)."""
    axes = [f"frequency_ratio: {ratio}" if ratio is not None else frequency, force]
    return (f"scene: {{excitation: {'force' if 'excitation_force' in system else 'base'}}}\nsystem: {system}\n"
            "grid: {" + ", ".join(a for a in axes if a is not None) + "}\nmethod: theory\noutput: out.h5\n")


def _calibration(prior: str) -> Callable[[Path], None]:
    """A calibration spec (cal.yaml) on a small data file whose parameters hold `prior`."""

    def make(d: Path) -> None:
        (d / "rig.csv").write_text("r,beta,phase\n0.7,0.2,10\n1.3,0.2,170\n")
        (d / "cal.yaml").write_text(
            "data:\n  file: rig.csv\n  columns: {frequency_ratio: r, force_ratio: beta, phase: phase}\n"
            "scene: {excitation: base}\nsystem: {natural_frequency: 10 Hz, excitation_force: 1 N}\nmethod: theory\n"
            f"parameters:\n  friction_ratio: {{uniform: [0.01, 1]}}\n  noise_phase: {{half_normal: 5 deg}}\n  {prior}\n")

    return make


@dataclass
class Case:
    id: str
    spec: str | None = GOOD
    args: tuple[str, ...] = ("run", "{spec}", "-q")
    setup: Callable[[Path], None] | None = None
    exit: int = 2
    words: tuple[str, ...] = ()
    exist: tuple[str, ...] = ()
    absent: tuple[str, ...] = ("out.h5", ".out.h5.partial", ".out.h5.lock")
    check: Callable[[Path], None] | None = None
    lines: int | None = 1  # message lines on stderr after "invalid spec" (None: any number)
    extra: dict = field(default_factory=dict)
    env: dict = field(default_factory=dict)  # environment of the command ({d}: the case's folder)


def _cube_unchanged(d: Path) -> None:
    assert (d / "out.h5").read_bytes() == (d / "before.bytes").read_bytes()


def _real_unchanged(d: Path) -> None:
    assert (d / "out.h5").is_symlink() and os.readlink(d / "out.h5") == "real.h5"
    assert (d / "real.h5").read_bytes() == (d / "before.bytes").read_bytes()


def _still(kind: Callable[[int], bool]) -> Callable[[Path], None]:
    return lambda d: kind(os.lstat(d / "out.h5").st_mode) or pytest.fail("the special file was replaced")


def _resumed_cube_is_complete(d: Path) -> None:
    """The damaged tile was computed again: the cube equals an uninterrupted run's, bit for bit."""
    assert CliRunner().invoke(main, ["run", str(d / "spec.yaml"), "-o", str(d / "ref.h5"), "-q"]).exit_code == 0
    with xr.open_dataset(d / "out.h5", engine="h5netcdf") as got, xr.open_dataset(d / "ref.h5", engine="h5netcdf") as ref:
        assert set(got.data_vars) == set(ref.data_vars)
        for name in ref.data_vars:
            np.testing.assert_array_equal(got[name].values, ref[name].values)

# ---- set-ups and checks of issue 28 (files and checkpoints) ------------------------------------------

ACCURATE = EVENT_LONG + "accuracy: 1.0e-3\n"


def _user_calibration(d: Path) -> Path:
    from friction_sweep.bench.workprecision import PACKAGED_CALIBRATION

    path = d / "xdg" / "friction_sweep" / "calibration.json"
    path.parent.mkdir(parents=True)
    path.write_text(PACKAGED_CALIBRATION.read_text())
    return path


def _calibration_changed(d: Path) -> None:
    """A run with `accuracy:` interrupted, then the user's calibration changed so that `accuracy:` chooses
    other settings (the cheapest row that met 1e-3 now misses it)."""
    import json

    path = _user_calibration(d)
    _interrupted(d, ACCURATE, env={"XDG_DATA_HOME": str(d / "xdg")})
    table = json.loads(path.read_text())
    for row in table["event"]:
        if row["worst_error"] is not None and row["worst_error"] <= 1e-3:
            row["worst_error"] = 0.5
            break
    path.write_text(json.dumps(table))


def _tile_arrays(path: Path) -> dict:
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


def _edit_tile(change: Callable[[dict], dict]) -> Callable[[Path], None]:
    """An interrupted run whose first finished tile is changed (its proof entries kept unless changed)."""
    def setup(d: Path) -> None:
        _interrupted(d, EVENT_LONG)
        tile = d / ".out.h5.partial" / "tile-00000.npz"
        np.savez(tile, **change(_tile_arrays(tile)))
    return setup


def _foreign_tile(d: Path) -> None:
    """The first tile replaced by the first tile of another sweep of the same shape."""
    (d / "other").mkdir()
    _interrupted(d / "other", EVENT_LONG.replace("0.1, 0.4", "0.1, 0.5"))
    _interrupted(d, EVENT_LONG)
    (d / ".out.h5.partial" / "tile-00000.npz").write_bytes((d / "other/.out.h5.partial/tile-00000.npz").read_bytes())
    import shutil

    shutil.rmtree(d / "other")


def _swapped_tile(d: Path) -> None:
    """Tile 0's file copied over tile 1 (right shape, right sweep, wrong place)."""
    _interrupted(d, EVENT_LONG)
    part = d / ".out.h5.partial"
    (part / "tile-00001.npz").write_bytes((part / "tile-00000.npz").read_bytes())


def _hard_linked_lock(d: Path) -> None:
    (d / "victim.txt").write_text("precious")
    os.link(d / "victim.txt", d / ".out.h5.lock")


def _cube_linked_as_lock(d: Path) -> None:
    _good_cube(d)
    os.link(d / "out.h5", d / ".out.h5.lock")


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def _stale_temporaries(d: Path) -> None:
    """What a kill -9 leaves: the cube's temporary, a staged copy and its temporary, and the probe."""
    pid = _dead_pid()
    for name in (f".out.h5.{pid}-abcd_123.tmp", f".out.h5.{pid}-staged.tmp",
                 f"..out.h5.{pid}-staged.tmp.{pid}-x1y2z3w4.tmp"):
        (d / name).write_bytes(b"\0" * 100_000)


def _calibration_spec(d: Path, data: str, output: str, name: str = "rig.yaml") -> None:
    from friction_sweep.validation import DEFAULT_DATA

    text = (Path(__file__).parents[1] / "configs/calibration/rig.yaml").read_text()
    text = text.replace("package:data/experiment_phase_fixed_wall.csv", data)
    (d / name).write_text(text.replace("output: results/calibration/rig", f"output: {output}"))
    if data.startswith("rigdir/"):
        (d / "rigdir").mkdir(exist_ok=True)
        (d / data).write_text(DEFAULT_DATA.read_text())


def _unchanged_as(path: str, source: Callable[[], str]) -> Callable[[Path], None]:
    return lambda d: _same_text(d / path, source())


def _rig_data() -> str:
    from friction_sweep.validation import DEFAULT_DATA

    return DEFAULT_DATA.read_text()


def _packaged_calibration() -> str:
    from friction_sweep.bench.workprecision import PACKAGED_CALIBRATION

    return PACKAGED_CALIBRATION.read_text()


def _bench_notes(d: Path) -> None:
    (d / "notes.md").write_text("my notes")
    (d / "notes.png").write_text("my picture")


def _partial_holding(*names: str) -> Callable[[Path], None]:
    """A checkpoint folder holding a user's files `names` (and nothing of fsweep's)."""
    def setup(d: Path) -> None:
        for name in names:
            path = d / ".out.h5.partial" / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text("precious")
    return setup


def _kept_in_partial(name: str, top: bool = False) -> Callable[[Path], None]:
    def check(d: Path) -> None:
        assert (d / name if top else d / ".out.h5.partial" / name).read_text() == "precious"
    return check


def _partial_link(d: Path) -> None:
    (d / "victim.txt").write_text("precious")
    (d / ".out.h5.partial").mkdir()
    (d / ".out.h5.partial" / "tile-00000.npz").symlink_to(d / "victim.txt")


def _partial_stale_temporary(d: Path) -> None:
    """What a run killed while writing its manifest leaves: a temporary whose writer is gone."""
    (d / ".out.h5.partial").mkdir()
    (d / ".out.h5.partial" / ".manifest.json.2147483646-abcdefgh.tmp").write_text("{")


def _user_tile_folder(d: Path) -> None:
    _interrupted(d, EVENT_LONG)
    (d / ".out.h5.partial" / "tile-00003.npz").mkdir()
    (d / ".out.h5.partial" / "tile-00003.npz" / "x").write_text("precious")


KEEP = ("out.h5", ".out.h5.partial", ".out.h5.lock")  # the default `absent`
RESUME = ("run", "{spec}", "--resume", "-q")
RESUMED = {"spec": None, "args": RESUME, "exit": 0, "exist": ("out.h5",), "absent": (".out.h5.partial", ".out.h5.lock"),
           "check": _resumed_cube_is_complete}



# issue 28, r = 1/(2n): specs whose grids hold r next to 1/(2n) (12-digit grid values, a few ulps and
# 1e-9 off, binary 1/(2n)); each is run, then audited by fsweep check
NEAR_FAMILY = """\
scene: {{excitation: {excitation}}}
grid:
  frequency_ratio: {r}
  force_ratio: {beta}
method: {method}
output: out.h5
"""


def _near_family(excitation="base", r="{start: 0.1, stop: 0.2, num: 31}", beta="{start: 0.001, stop: 0.025, num: 25}",
                 method="event") -> str:
    return NEAR_FAMILY.format(excitation=excitation, r=r, beta=beta, method=method)


def _continuous_next_to_the_family(d: Path) -> None:
    """Every point within 1e-6 of r = 1/(2n) and below 0.98 beta*(r) (the scene's convention) is
    continuous, from a steady state the method found (converged, or the family at the tie)."""
    with xr.open_dataset(d / "out.h5", engine="h5netcdf") as ds:
        r = ds["frequency_ratio"].values
        n = np.rint(0.5 / r)
        near = np.abs(2.0 * n * r - 1.0) <= 1e-6
        inside = ds["force_ratio"].values[:, None] <= 0.98 * ds["continuous_limit"].values[None, :]
        sel = near[None, :] & inside
        assert sel.any()
        assert (ds["regime"].values[sel] == 2).all(), ds["regime"].values
        if "steady_state" in ds:
            assert np.isin(ds["steady_state"].values[sel],
                           (SteadyState.CONVERGED, SteadyState.FAMILY, SteadyState.NOT_SIMULATED)).all()


def _creep_at_the_family(d: Path) -> None:
    """An event cube at r = 1/2 and 1/4 in binary whose point (0.5, 0.1) says `stick_slip`, one stop a
    period, as a march that creeps towards the family would (every stick-free orbit there is continuous)."""
    _good_cube(d)
    with xr.open_dataset(d / "out.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    at = {"frequency_ratio": 0.5, "force_ratio": 0.1}
    ds["regime"].loc[at] = 1
    ds["stops_per_period"].loc[at] = 1.0
    (d / "out.h5").unlink()
    ds.to_netcdf(d / "out.h5", engine="h5netcdf")

def _damped(excitation: str, damping: str, method: str = "event") -> str:
    """The issue's spec: a damping ratio next to resonance (issue 28, class 1)."""
    return (f"scene: {{excitation: {excitation}, effects: {{viscous_damping: {damping}}}}}\n"
            "grid:\n  frequency_ratio: [0.999999, 1.0, 1.000001]\n  force_ratio: [0]\n"
            f"method: {method}\noutput: out.h5\n")


def _wrong_orbit_cube(path: Path) -> None:
    """The cube main wrote for the issue's spec (now refused): computed by the method directly, with r = 1 as
    main wrote it, T = 68 labelled converged where the exact value is 1/(2 zeta) = 5e17 (the kernel now
    labels it unsettled)."""
    from friction_sweep import catalogue
    from friction_sweep.methods import event
    from friction_sweep.storage import cube, provenance

    effects = {"viscous_damping": 1e-18}
    r = np.array([0.999999, 1.0, 1.000001])
    arrays = event.compute_tile("base", r, np.array([0.0]), ("transmissibility", "phase", "regime"), effects)
    at_one = 1  # r = 1, as main wrote it
    arrays["transmissibility"][0, at_one], arrays["phase"][0, at_one] = 68.02467467134679, -63.11680981
    arrays["regime"][0, at_one], arrays["steady_state"][0, at_one] = Regime.CONTINUOUS, SteadyState.CONVERGED
    settings = {**event.CATALOGUE.defaults, "effects": catalogue.resolved_effects("base", effects)}
    cube.build_dataset(arrays, frequency_ratio=r, force_ratio=np.array([0.0]), excitation="base", title="t",
                       history=provenance.history_line("test"),
                       attrs=provenance.attributes(spec_text="", spec_path="s.yaml", excitation="base",
                                                   method="event", settings=settings)
                       ).to_netcdf(path, engine="h5netcdf")


# ---- issue 30: structure specs (the issue's spec; each row changes one thing) ------------------------

STRUCTURE = two_mass(561, "[0.25, 0.5, 1.0, 2.0]", "[amplitude, phase, regime]", static_friction_ratio=1.2,
                     output="out.h5")
#: the same structure under base excitation (no forcing; the root contact moves with the base)
STRUCTURE_BASE = STRUCTURE.replace("{excitation: force}", "{excitation: base}").replace("  forcing: {blade: 1.0}\n",
                                                                                        "  base_amplitude: 0.5\n")

#: the same on a small plane (4 x 8 points), for cubes
SMALL_STRUCTURE = STRUCTURE.replace("num: 561", "num: 8")

# ---- issue 31: reduced models and physical units (each row changes one thing) -----------------------------

#: a reduced model: M and K of the blade and damper from rom.npz, which each row's set-up writes
ROM = """\
scene: {excitation: force}
structure:
  matrices: {file: rom.npz, dofs: [blade, damper]}
  contacts:
    - {name: platform, between: [damper, ground], friction: 0.3}
  forcing: {blade: 1.0}
grid:
  frequency: {start: 0.2, stop: 3.0, num: 8}
output: out.h5
"""
ROM_ARRAYS = {"M": [[1.0, 0.0], [0.0, 0.1]], "K": [[3.0, -2.0], [-2.0, 2.0]]}
#: the structure as modes (frequencies and mass-normalised shapes at blade and damper)
MODES = ROM.replace("  matrices: {file: rom.npz, dofs: [blade, damper]}\n",
                    "  modes: {frequencies: [1.0, 2.0], shapes: {blade: [0.6, 0.8], damper: [0.8, -0.6]}}\n")
#: the same structure in physical units
PHYSICAL = """\
scene: {excitation: force}
structure:
  masses: {blade: 2 kg, damper: 0.2 kg}
  springs: [[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]
  contacts:
    - {name: platform, between: [damper, ground], friction: 12 N}
  forcing: {blade: 30 N}
grid:
  frequency: {start: 10 Hz, stop: 60 Hz, num: 8}
output: out.h5
"""


def _rom_file(name: str = "rom.npz", **arrays) -> Callable[[Path], None]:
    """A set-up writing the model file `name`: ROM_ARRAYS with `arrays` over them (None: left out)."""
    def setup(d: Path) -> None:
        given = {k: v for k, v in {**ROM_ARRAYS, **arrays}.items() if v is not None}
        if name.endswith(".mat"):
            import scipy.io

            scipy.io.savemat(d / name, {k: np.asarray(v, dtype=float) for k, v in given.items()})
        else:
            np.savez(d / name, **{k: np.asarray(v) for k, v in given.items()})
    return setup


def _bytes_file(data: bytes, size: int | None = None) -> Callable[[Path], None]:
    def setup(d: Path) -> None:
        with open(d / "rom.npz", "wb") as fh:
            fh.write(data)
            if size is not None:
                fh.truncate(size)  # sparse: the size without the disk
    return setup


def _edited(text: str, *edits: tuple[str, str]) -> str:
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    return text


def _rom_case(name: str, where: str, *edits: tuple[str, str], setup=None, words: tuple[str, ...] = (),
              text: str = ROM) -> Case:
    """A reduced-model or physical spec refused by run, at `where` (line:column: key)."""
    return Case(name, _edited(text, *edits), setup=setup, words=(f"spec.yaml:{where}: ", *words))


_FILE = "3:20: structure.matrices.file"
ROM_CASES = [
    _rom_case("rom: no such file", _FILE, words=("rom.npz: cannot read it: No such file",)),
    _rom_case("rom: not a model file", _FILE, ("rom.npz", "rom.csv"), words=("a .npz or a .mat file",)),
    _rom_case("rom: a damaged file", _FILE, setup=_bytes_file(b"not a zip"), words=("cannot read it as .npz",)),
    _rom_case("rom: over the size", _FILE, setup=_bytes_file(b"PK", 64 * 2**20 + 1), words=("over the 64 MiB",)),
    _rom_case("rom: a pickled array", _FILE, setup=lambda d: np.savez(d / "rom.npz", M=np.array([{}], dtype=object),
                                                                     K=np.eye(2)), words=("cannot read it",)),
    _rom_case("rom: no M", _FILE, setup=_rom_file(M=None), words=("no M in it (it holds: K)",)),
    _rom_case("rom: not square", _FILE, setup=_rom_file(K=[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]),
              words=("K is not square (shape 2x3)",)),
    _rom_case("rom: not symmetric", _FILE, setup=_rom_file(K=[[3.0, -2.0], [-2.1, 2.0]]),
              words=("K is not symmetric", "over 1e-10 x max|K|")),
    _rom_case("rom: a mass matrix not positive definite", _FILE, setup=_rom_file(M=[[1.0, 0.0], [0.0, -0.1]]),
              words=("M is not positive definite",)),
    _rom_case("rom: a negative stiffness", _FILE, setup=_rom_file(K=[[-3.0, 0.0], [0.0, 2.0]]),
              words=("K is not positive semi-definite",)),
    _rom_case("rom: NaN", _FILE, setup=_rom_file(K=[[3.0, float("nan")], [-2.0, 2.0]]),
              words=("K[0, 1] is nan: every entry must be finite",)),
    _rom_case("rom: NaN in a .mat", "3:20: structure.matrices.file", ("rom.npz", "rom.mat"),
              setup=_rom_file("rom.mat", C=[[0.0, 0.0], [0.0, float("nan")]]), words=("rom.mat: C[1, 1] is nan",)),
    _rom_case("rom: DoF names not matching", _FILE, ("dofs: [blade, damper]", "dofs: [blade, damper, tip]"),
              setup=_rom_file(), words=("M is 2x2, but dofs names 3 DoFs",)),
    _rom_case("rom: a DoF named twice", "3:43: structure.matrices.dofs[1]", ("dofs: [blade, damper]", "dofs: [blade, blade]"),
              setup=_rom_file(), words=("DoF 'blade' is named twice",)),
    _rom_case("rom: C and damping ratios", "3:52: structure.matrices.damping_ratios",
              ("dofs: [blade, damper]}", "dofs: [blade, damper], damping_ratios: [0.01]}"),
              setup=_rom_file(C=[[0.1, 0.0], [0.0, 0.0]]), words=("give damping by C or by damping_ratios",)),
    _rom_case("rom: damping ratios not one per mode", "3:52: structure.matrices.damping_ratios",
              ("dofs: [blade, damper]}", "dofs: [blade, damper], damping_ratios: [0.01, 0.02, 0.03]}"),
              setup=_rom_file(), words=("3 damping ratios for 2 modes",)),
    _rom_case("rom: springs beside matrices", "4:3: structure.springs",
              ("  contacts:", "  springs: [[ground, blade, 1.0]]\n  contacts:"), setup=_rom_file(),
              words=("a reduced model's stiffness and damping are in its matrices",)),
    _rom_case("rom: masses and matrices", "3:3: structure.matrices",
              ("  contacts:", "  masses: {blade: 1.0, damper: 0.1}\n  contacts:"), setup=_rom_file(),
              words=("give the structure one way",)),
    _rom_case("rom: an unrestrained DoF", "3:43: structure.matrices.dofs[1]",
              ("between: [damper, ground]", "between: [blade, ground]"), setup=_rom_file(K=[[1.0, 0.0], [0.0, 0.0]]),
              words=("nothing holds the motion of 'damper'",)),
    _rom_case("modes: singular shapes", "3:36: structure.modes.shapes", ("[0.8, -0.6]", "[1.2, 1.6]"), text=MODES,
              words=("the shapes are singular",)),
    _rom_case("modes: fewer DoFs than modes", "3:36: structure.modes.shapes", (", damper: [0.8, -0.6]", ""),
              ("[damper, ground]", "[blade, ground]"), text=MODES,
              words=("1 DoFs for 2 modes",)),
    # physical units: every quantity with its unit, of its dimension
    _rom_case("physical: a mass without its unit", "3:33: structure.masses.damper", ("0.2 kg", "0.2"),
              text=PHYSICAL, words=("must be a mass with its unit", "a number without a unit")),
    _rom_case("physical: a stiffness in kg", "4:29: structure.springs[0][2]", ("40 kN/m", "40 kg"),
              text=PHYSICAL, words=("must be a stiffness such as '40 kN/m'",)),
    _rom_case("physical: a friction of a coefficient without a load", "6:51: structure.contacts[0].friction",
              ("friction: 12 N", "friction: {coefficient: 0.3}"), text=PHYSICAL, words=("a friction is a force",)),
    _rom_case("physical: a frequency without its unit", "9:22: grid.frequency.start", ("start: 10 Hz", "start: 10"),
              text=PHYSICAL, words=("must be a frequency with its unit",)),
    _rom_case("plain: a frequency with a unit", "8:3: grid.frequency", ("{start: 0.2, stop: 3.0, num: 8}", "[2 Hz]"),
              setup=_rom_file(),
              words=("a frequency with a unit needs a physical structure",)),
    _rom_case("physical: frequency and frequency_ratio", "10:3: grid.frequency_ratio",
              ("num: 8}\n", "num: 8}\n  frequency_ratio: [1.0]\n"), text=PHYSICAL,
              words=("give the frequencies one way",)),
    _rom_case("physical: a free reference with a mass held only by a contact", "10:14: grid.reference",
              ("[[ground, blade, 40 kN/m], [blade, damper, 80 kN/m]]", "[[ground, blade, 40 kN/m]]"),
              ("frequency: {start: 10 Hz, stop: 60 Hz, num: 8}", "frequency_ratio: [1.0]\n  reference: free"),
              text=PHYSICAL, words=("with every contact free, the structure has a rigid-body motion",)),
]


def _structure(*edits: tuple[str, str], base: bool = False) -> str:
    text = STRUCTURE_BASE if base else STRUCTURE
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    return text


def _structure_case(name: str, where: str, *edits: tuple[str, str], words: tuple[str, ...] = (),
                    base: bool = False, lines: int | None = 1) -> Case:
    """A structure spec refused by run (validate: the same line), at `where` (line:column: key)."""
    return Case(name, _structure(*edits, base=base), words=(f"spec.yaml:{where}: ", *words), lines=lines)


CASES = [
    # ---- spec files that cost without bound, or crash the reader
    Case("alias bomb", _alias_bomb(), words=("aliases repeat more than",)),
    Case("merge-key alias bomb", _merge_bomb(), words=("aliases repeat more than",)),
    Case("recursive alias in a map", "scene: &s {excitation: base, x: *s}\ngrid: {frequency_ratio: 1, "
         "force_ratio: 0.1}\n", words=("recursive YAML alias", "line 1")),
    Case("recursive alias in a list", "scene: {excitation: base}\ngrid: &g {frequency_ratio: [1, *g], "
         "force_ratio: 0.1}\n", words=("recursive YAML alias", "line 2")),
    Case("5000-deep list", _nested("list", 5000), words=("nested deeper",)),
    Case("3000-deep map", _nested("map", 3000), words=("nested deeper",)),
    Case("40-deep map", _nested("map", 40), words=("nested deeper than 32 levels",)),
    Case("frequency ratio 1e-10", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "[1.0e-10]"),
         words=("frequency_ratio[0]", "must be >= 0.01", "cost")),
    Case("frequency ratio 1e-300", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "[1.0e-300]"),
         words=("must be >= 0.01",)),
    Case("frequency ratio 1e-6", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "[1.0e-6, 1]"),
         words=("must be >= 0.01",)),
    Case("frequency ratio 1e20", GOOD.replace("stop: 2.0", "stop: 1.0e20"), words=("must be <= 100",)),
    Case("force ratio 1e300", GOOD.replace("[0.1, 0.4]", "[0.1, 1.0e300]"), words=("must be <= 1000000",)),
    Case("force ratio 1e-16", GOOD.replace("[0.1, 0.4]", "[0, 1.0e-16, 0.4]"),
         words=("force_ratio[1]", "must be 0 or at least 1e-12")),
    Case("400-digit integer", GOOD.replace("[0.1, 0.4]", "1" + "0" * 400),
         words=("force_ratio", "too large", "401 digits")),
    Case("history too large", EVENT.replace("output: out.h5", "output: out.h5\noutputs: [regime, time_history]\n"
                                            "time_history: {points: [" + ", ".join(["[1, 0.1]"] * 200)
                                            + "], samples_per_period: 100000}"),
         words=("samples per variable",)),
    Case("negative history force ratio", EVENT.replace(
        "output: out.h5", "outputs: [regime, time_history]\ntime_history: {points: [[1, 0.1], [2, 0.1], [3, -0.1]]}"),
        words=("time_history.points[2][1]", "force ratio must be 0 or between 1e-12 and")),
    Case("a key named like a union tag", "'<range>': 1\n" + GOOD, words=("<range>", "unknown key")),
    Case("binary spec file", "\x00\xff\xfe binary", words=("not UTF-8",)),
    Case("empty spec", "", words=("must be a mapping",)),
    # ---- settings outside their meaningful range (all reported at once)
    Case("steady_tol 10", _settings("event", "steady_tol: 10"), words=("settings.steady_tol", "between 1e-13 and 1e-06")),
    Case("work_budget int64 max", _settings("event", "work_budget: 9223372036854775807"),
         words=("settings.work_budget", "between 1 and")),
    Case("max_periods 1e23", _settings("event", "max_periods: 99999999999999999999999"),
         words=("settings.max_periods",)),
    Case("paper transient_fraction 1.5", _settings("paper", "transient_fraction: 1.5"),
         words=("settings.transient_fraction", "between 0 and 0.9")),
    Case("initial displacement 1e300", _settings("event", "initial_displacement: 1.0e300"),
         words=("settings.initial_displacement",)),
    Case("rk4 a billion steps", _settings("rk4", "steps_per_period: 1000000000"),
         words=("settings.steps_per_period",)),
    Case("three bad settings", _settings("event", "steady_tol: -1, stop_tol: 1, max_periods: 0"),
         words=("settings.steady_tol", "settings.stop_tol", "settings.max_periods"), lines=3),
    Case("a setting of the wrong type", _settings("event", "max_periods: 1.5"), words=("must be an integer",)),
    # ---- outputs that are not regular files, or cannot be made
    Case("FIFO as output", args=("run", "{spec}", "--overwrite", "-q"), setup=_fifo,
         words=("named pipe",), absent=(".out.h5.partial", ".out.h5.lock"), check=_still(stat.S_ISFIFO)),
    Case("device node as output", args=("run", "{spec}", "--overwrite", "-q"), setup=_device,
         words=("character device",), absent=(".out.h5.partial",), check=_still(stat.S_ISCHR)),
    Case("socket as output", args=("run", "{spec}", "--overwrite", "-q"), setup=_socket,
         words=("socket",), absent=(".out.h5.partial",), check=_still(stat.S_ISSOCK)),
    Case("folder as output", args=("run", "{spec}", "-o", "{d}/afolder", "--overwrite", "-q"),
         setup=lambda d: (d / "afolder").mkdir(), words=("is a directory",), absent=("out.h5",)),
    Case("symlink as output", args=("run", "{spec}", "--overwrite", "-q"), setup=_symlink_to_cube,
         words=("symbolic link to real.h5", "never replaces links"), absent=(".out.h5.partial",),
         check=_real_unchanged),
    Case("dangling symlink as output", args=("run", "{spec}", "--overwrite", "-q"), setup=_dangling,
         words=("symbolic link",), absent=(".out.h5.partial",)),
    Case("parent is a file", args=("run", "{spec}", "-o", "{d}/afile/out.h5", "-q"), setup=_file_parent,
         words=("afile is a file, not a folder",)),
    Case("validate: parent is a file", args=("validate", "{spec}", "-o", "{d}/afile/out.h5"), setup=_file_parent,
         words=("afile is a file, not a folder",)),
    Case("existing output", setup=_good_cube, words=("exists", "--overwrite"), absent=(".out.h5.partial",),
         check=_cube_unchanged),
    Case("--resume --overwrite", args=("run", "{spec}", "--resume", "--overwrite", "-q"), setup=_good_cube,
         words=("not both",), absent=(".out.h5.partial",), check=_cube_unchanged),
    Case("--resume on a complete output", args=("run", "{spec}", "--resume", "-q"), setup=_good_cube,
         words=("nothing to resume", "instead of --resume"), absent=(".out.h5.partial",), check=_cube_unchanged),
    # ---- checkpoints and locks in a bad state
    Case(".partial is a file", setup=_partial_is_file, words=("is not a folder", "rm -r"),
         absent=("out.h5", ".out.h5.lock"), exist=(".out.h5.partial",)),
    Case(".lock is a folder", setup=_lock_is_folder, words=("is a folder, not a lock file",),
         absent=("out.h5", ".out.h5.partial"), exist=(".out.h5.lock",)),
    Case("bad manifest.json", spec=None, args=("run", "{spec}", "--resume", "-q"), setup=_bad_manifest,
         words=("manifest.json cannot be read", "rm -r"), absent=("out.h5", ".out.h5.lock"),
         exist=(".out.h5.partial/tile-00000.npz",)),
    Case("truncated tile", spec=None, args=("run", "{spec}", "--resume", "-q"), setup=_truncated_tile, exit=0,
         words=("tile-00001.npz was damaged",), exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"),
         check=_resumed_cube_is_complete),
    Case("checkpoint of another sweep", spec=None, setup=_other_sweep,
         words=("different sweep", "rm -r"), absent=("out.h5", ".out.h5.lock"), exist=(".out.h5.partial",)),
    # ---- found by an independent hostile review after the first fixes
    Case("lock is a symlink to a victim", setup=_lock_to_victim, words=("symbolic link, which fsweep never writes",),
         absent=("out.h5", ".out.h5.partial"), check=lambda d: _same_text(d / "victim.txt", "precious")),
    Case("lock is a FIFO", setup=lambda d: os.mkfifo(d / ".out.h5.lock"), words=("is not a regular file",),
         absent=("out.h5", ".out.h5.partial")),
    Case("output is the spec", args=("run", "{spec}", "-o", "{spec}", "--overwrite", "-q"),
         words=("is the spec", "destroy"), absent=(".out.h5.partial",), check=lambda d: _same_text(d / "spec.yaml", GOOD)),
    Case("spec is its own lock", spec=None, args=("run", "{d}/.out.h5.lock", "-o", "{d}/out.h5", "-q"),
         setup=lambda d: (d / ".out.h5.lock").write_text(GOOD), words=("is the spec",), absent=("out.h5",),
         check=lambda d: _same_text(d / ".out.h5.lock", GOOD)),
    Case("NUL in the spec's output", GOOD.replace("output: out.h5", 'output: "out\\0.h5"'),
         words=("control character",)),
    Case("newline in -o", args=("run", "{spec}", "-o", "out\n.h5", "-q"), words=("control character",)),
    Case("-o ending in a slash", args=("run", "{spec}", "-o", "newdir/", "-q"), words=("names a folder",),
         absent=("newdir", "out.h5")),
    Case("spec output ending in a slash", GOOD.replace("output: out.h5", "output: newdir/"),
         words=("names a folder",), absent=("newdir",)),
    Case("spec is a FIFO", spec=None, args=("validate", "{d}/f.yaml"), setup=lambda d: os.mkfifo(d / "f.yaml"),
         words=("not a regular file",), absent=()),
    Case("spec is /dev/zero", spec=None, args=("validate", "/dev/zero"), words=("not a regular file",), absent=()),
    Case("a 300 kB spec", GOOD + "# " + "x" * 300_000 + "\n", words=("a spec is at most",)),
    Case("info on a FIFO", args=("info", "{d}/c.h5"), setup=lambda d: os.mkfifo(d / "c.h5"),
         words=("not a regular file",), absent=()),
    Case("a megabyte method name", GOOD.replace("method: theory", "method: " + "m" * 1_000_000),
         words=("a spec is at most",)),
    Case("a long method name", GOOD.replace("method: theory", "method: " + "m" * 5000), words=("...",)),
    Case("static friction 1.7e308", EVENT.replace("{excitation: base}",
                                                  "{excitation: base, effects: {static_friction_ratio: 1.7e308}}"),
         words=("static_friction_ratio", "between 1 and 100")),
    Case("usage error", args=("run", "{spec}", "-j", "0"), words=("fsweep: error: Invalid value for '-j'",)),
    Case("a folder named like a tile", spec=None, args=("run", "{spec}", "--resume", "-q"),
         setup=_tile_folder, exit=0,
         words=("tile-00003.npz was damaged",), exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock")),
    Case("a tile of strings", spec=None, args=("run", "{spec}", "--resume", "-q"), setup=lambda d: _tamper(d, "abc"),
         exit=0, exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"), check=_resumed_cube_is_complete),
    Case("a tile of regime 1e300", spec=None, args=("run", "{spec}", "--resume", "-q"),
         setup=lambda d: _tamper(d, 1e300, name="regime"), exit=0, exist=("out.h5",),
         absent=(".out.h5.partial", ".out.h5.lock"), check=_resumed_cube_is_complete),
    # ---- Dask that cannot run
    Case("scheduler on a closed port", args=("run", "{spec}", "--scheduler", "tcp://127.0.0.1:9", "-q"),
         words=("cannot reach the Dask scheduler", "refused")),
    Case("scheduler not an address", args=("run", "{spec}", "--scheduler", "not an address", "-q"),
         words=("is not a scheduler address",)),
    # ---- cubes that cannot be trusted
    Case("info on a foreign file", args=("info", "{d}/spec.yaml"), words=("not a readable result cube",),
         absent=()),
    # ---- issue 28: physics: r=1/(2n) labels (a creep towards the stick-free family taken for a
    # stick-slip orbit; the cube must pass its own audit at any grid)
    Case("issue 28: 31-point grid holding r = 0.166666666667", _near_family(), args=("check", "{d}/out.h5"),
         setup=_good_cube, exit=0, words=("theory      ok",), exist=("out.h5",), absent=(),
         check=_continuous_next_to_the_family),
    Case("issue 28: joined at 0.166666666667, beta 1e-12", _near_family("joined", "[0.166666666667]",
                                                                         "[1.0e-12, 1.0e-6, 7.0e-4]"),
         args=("check", "{d}/out.h5"), setup=_good_cube, exit=0, words=("unsettled   ok",), exist=("out.h5",),
         absent=(), check=_continuous_next_to_the_family),
    Case("issue 28: force, 1/(2n) for n = 1..5 rounded and detuned", _near_family(
        "force", "[0.0999999999999, 0.1, 0.100000001, 0.125000000001, 0.16666666666666666, 0.166666666667, "
        "0.1666666667, 0.2499999999, 0.250000000001, 0.499999999999, 0.5, 0.500000001]",
        "[1.0e-12, 1.0e-9, 0.0005, 0.005, 0.0095]"),
         args=("check", "{d}/out.h5"), setup=_good_cube, exit=0, words=("theory      ok",), exist=("out.h5",),
         absent=(), check=_continuous_next_to_the_family),
    Case("issue 28: joined next to 1/4 and 1/6", _near_family(
        "joined", "[0.1666666666, 0.166666666667, 0.1666666667, 0.249999999999, 0.25, 0.250000000001]",
        "[1.0e-12, 1.0e-5, 1.0e-4, 5.0e-4]"),
         args=("check", "{d}/out.h5"), setup=_good_cube, exit=0, words=("theory      ok",), exist=("out.h5",),
         absent=(), check=_continuous_next_to_the_family),
    Case("issue 28: auto simulating next to beta* on the 31-point grid",
         _near_family(method="auto\nsettings: {theory_margin: 0.99}", beta="{start: 0.0, stop: 0.03, num: 31}"),
         args=("check", "{d}/out.h5"), setup=_good_cube, exit=0, words=("theory      ok",), exist=("out.h5",),
         absent=(), check=_continuous_next_to_the_family),
    Case("issue 28: a stick-slip label on the r = 1/2 family fails check", _near_family(
        r="[0.25, 0.5]", beta="[0.01, 0.1]"), args=("check", "{d}/out.h5"), setup=_creep_at_the_family, exit=1,
         words=("theory      FAILED   1 of 3", "r=0.5, beta=0.1: stick_slip, expected continuous"), exist=("out.h5",),
         absent=(), lines=None),
    # ---- issue 28: inputs: units, specs and the Python API
    Case("unit bomb of 30 characters", _physical("{natural_frequency: '(((9**99)**99)**99)**99 Hz', stiffness: 1 N/m, "
                                                 "base_amplitude: 1 mm}"),
         words=("spec.yaml:2:", "system.natural_frequency", "power is at most 4")),
    Case("unit power of a power", _physical("{natural_frequency: '(9**99)**99 Hz', stiffness: 1 N/m, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "power is at most 4")),
    Case("unit powers that overflow a double", _physical("{natural_frequency: '((9**4)**4)**4 Hz', stiffness: 1 N/m, "
                                                         "base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "between 1e-30 and 1e+30 Hz")),
    Case("unit product that overflows", _physical("{natural_frequency: '(((9**4)**4)**4)**3 * (((9**4)**4)**4)**3 Hz', "
                                                  "stiffness: 1 N/m, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "must be finite")),
    Case("unit power that overflows", _physical("{natural_frequency: '((((10**4)**4)**4)**4)**4 Hz', stiffness: 1 N/m, "
                                                "base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "must be finite")),
    Case("unit division by zero", _physical("{natural_frequency: '5 / 0 Hz', stiffness: 1 N/m, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "divides by zero")),
    Case("unit with a decimal comma", _physical("{natural_frequency: '1,5 Hz', stiffness: 1 N/m, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "a comma")),
    Case("prior unit bomb", None, args=("calibrate", "{d}/cal.yaml", "-o", "{d}/cal"), setup=_calibration(
        "natural_frequency: {normal: ['(((9**99)**99)**99)**99 Hz', 1 Hz]}"),
         words=("parameters.natural_frequency.normal[0]", "power is at most 4"), absent=("cal",), lines=2),
    Case("prior beyond the physical range", None, args=("calibrate", "{d}/cal.yaml", "-o", "{d}/cal"),
         setup=_calibration("natural_frequency: {normal: [1e200 Hz, 1 Hz]}"),
         words=("parameters.natural_frequency.normal[0]", "between 1e-30 and 1e+30 Hz"), absent=("cal",), lines=2),
    Case("f_n and m of 1e200", _physical("{natural_frequency: 1e200 Hz, mass: 1e200 kg, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "system.mass", "between 1e-30 and 1e+30"), lines=2),
    Case("f_n and m of 1e-200", _physical("{natural_frequency: 1e-200 Hz, mass: 1e-200 kg, base_amplitude: 1 mm}"),
         words=("system.natural_frequency", "system.mass"), lines=2),
    Case("k and Y of 1e200", _physical("{natural_frequency: 10 Hz, stiffness: 1e200 N/m, base_amplitude: 1e200 m}"),
         words=("system.stiffness", "system.base_amplitude"), lines=2),
    Case("k and Y whose product leaves the range", _physical("{natural_frequency: 10 Hz, stiffness: 1e20 N/m, "
                                                             "base_amplitude: 1e20 m}"),
         words=("system.base_amplitude", "F_k = k Y is 1e+40 N", "F_k L is 1e+60 J"), lines=2),
    Case("k derived from m and f_n out of range", _physical("{natural_frequency: 1e25 Hz, mass: 1e25 kg, "
                                                            "base_amplitude: 1e-25 m}"),
         words=("system.mass", "k = m (2 pi f_n)^2 is 3.95e+76 N/m"), lines=2),
    Case("F_k of zero on a tiny stiffness", _physical("{natural_frequency: 10 Hz, stiffness: 1e-200 N/m, "
                                                      "base_amplitude: 1e-200 m}", "friction_force: [0 N]"),
         words=("system.stiffness", "system.base_amplitude"), lines=2),
    Case("a denormal excitation force", _physical("{natural_frequency: 10 Hz, excitation_force: 1e-320 N}",
                                                  "friction_force: [0 N]"),
         words=("system.excitation_force", "between 1e-30 and 1e+30 N")),
    Case("mu N beyond the range", _physical("{natural_frequency: 10 Hz, excitation_force: 1 N, "
                                            "friction_coefficient: 1e20, normal_load: 1e20 N}", None),
         words=("system.normal_load", "mu N is 1e+40 N")),
    Case("a frequency r f_n below the range", _physical("{natural_frequency: 1e-29 Hz, excitation_force: 1 N}",
                                                        "force_ratio: 0.1", "0.01"),
         words=("grid.frequency_ratio", "f = r f_n is 1e-31 Hz")),
    Case("a base acceleration whose amplitude leaves the range", _physical(
        "{natural_frequency: 1e-10 Hz, stiffness: 1e-20 N/m, base_acceleration: 1e20 m/s^2}", "friction_force: [1e18 N]",
        None, "frequency: [1e-10 Hz]"),
         words=("system.base_acceleration", "Y = a / omega^2 is 2.53e+38 m", "F_k Y is 6.42e+56 J"), lines=2),
    Case("a time-history point below the frequency range", _physical(
        "{natural_frequency: 1e-29 Hz, excitation_force: 1 N}", "force_ratio: 0.1").replace(
        "method: theory", "method: event\noutputs: [regime, time_history]\ntime_history: {points: [[0.01, 0.1]]}"),
         words=("time_history.points", "f = r f_n of a time-history point is 1e-31 Hz")),
    Case("a friction force of 1e-35 N", _physical("{natural_frequency: 10 Hz, excitation_force: 1 N}",
                                                  "friction_force: [0 N, 1e-35 N]"),
         words=("grid.friction_force[1]", "between 1e-30 and 1e+30 N")),
    Case("!!float of a word", GOOD.replace("[0.1, 0.4]", '!!float "abc"'),
         words=("spec.yaml:4:16: invalid YAML: !!float cannot hold 'abc'",)),
    Case("!!bool of a word", GOOD.replace("[0.1, 0.4]", "!!bool maybe"),
         words=("spec.yaml:4:16: invalid YAML: !!bool cannot hold 'maybe'",)),
    Case("!!int of a word in a list", GOOD.replace("[0.1, 0.4]", '[0.1, !!int "x"]'),
         words=("spec.yaml:4:22: invalid YAML: !!int cannot hold 'x'",)),
    Case("!!str value shown as written", GOOD.replace("[0.1, 0.4]", "!!str 0.1"),
         words=("grid.force_ratio: must be a number, not a string (got '0.1')",)),
    Case("a custom tag shown as written", GOOD.replace("[0.1, 0.4]", "!custom 0.1"),
         words=("(got '!custom 0.1')",)),
    Case("num beyond the points on the frequency axis", GOOD.replace("num: 40", "num: 10000001"),
         words=("grid.frequency_ratio.num: must be <= 10000000 (got 10000001): an axis has at most 10000000 points",)),
    Case("num beyond the points on the force axis", GOOD.replace("[0.1, 0.4]", "{start: 0, stop: 1, num: 10000001}"),
         words=("grid.force_ratio.num: must be <= 10000000 (got 10000001): an axis has at most 10000000 points",)),
    # ---- issue 28: cubes, readers and calibration inputs
    # one reader (storage.cube.open_cube) audits every cube before info, check, plot or the API sees it
    Case("plot: regime 9", args=("plot", "{d}/c.h5"), setup=hc.value("regime", (0, 0), 9),
         words=("regime: 1 of 80 values are not valid regime codes (e.g. 9",), absent=("c.png",)),
    Case("plot: transmissibility -1", args=("plot", "{d}/c.h5"), setup=hc.value("transmissibility", (0, 0), -1.0),
         words=("transmissibility: 1 of 80 values lie outside the valid range",), absent=("c.png",)),
    Case("plot: transmissibility inf", args=("plot", "{d}/c.h5"),
         setup=hc.value("transmissibility", (1, 5), np.inf), words=("are infinite",), absent=("c.png",)),
    Case("plot --kind phase: phase 1e300", args=("plot", "{d}/c.h5", "--kind", "phase"),
         setup=hc.value("phase", (0, 2), 1e300), words=("phase: 1 of 80 values lie outside",), absent=("c.png",)),
    Case("plot: NaN frequency ratio", args=("plot", "{d}/c.h5"), setup=hc.value("frequency_ratio", 3, np.nan),
         words=("frequency_ratio: 1 of 40 values are NaN",), absent=("c.png",)),
    Case("plot: frequency ratios out of order", args=("plot", "{d}/c.h5"), setup=hc.value("frequency_ratio", 3, 5.0),
         words=("not strictly increasing",), absent=("c.png",)),
    Case("plot: float16 transmissibility", args=("plot", "{d}/c.h5"),
         setup=hc.rewritten(lambda ds: ds.assign(transmissibility=ds["transmissibility"].astype("f2"))),
         words=("stored as float16",), absent=("c.png",)),
    Case("plot: two faults in one line", args=("plot", "{d}/c.h5"),
         setup=hc.edited(lambda f: (f["regime"].__setitem__((0, 0), 9), f["phase"].__setitem__((0, 0), -1e9))),
         words=("and 1 more problems: fsweep info lists them",), absent=("c.png",)),
    Case("info: two faults, a line each and no summary", args=("info", "{d}/c.h5"),
         setup=hc.edited(lambda f: (f["regime"].__setitem__((0, 0), 9), f["phase"].__setitem__((0, 0), -1e9))),
         words=("not valid regime codes", "phase: 1 of 80"), lines=2, absent=()),
    Case("info: a string variable", args=("info", "{d}/c.h5"), absent=(),
         setup=hc.rewritten(lambda ds: ds.assign(transmissibility=ds["transmissibility"].astype(str))),
         words=("variable 'transmissibility' holds strings, not numbers",)),
    Case("plot: a string variable", args=("plot", "{d}/c.h5"), absent=("c.png",),
         setup=hc.rewritten(lambda ds: ds.assign(note=ds["regime"].astype(str))), words=("holds strings",)),
    Case("check: a string coordinate", args=("check", "{d}/c.h5"), absent=(),
         setup=hc.rewritten(lambda ds: ds.assign_coords(force_ratio=ds["force_ratio"].astype(str))),
         words=("variable 'force_ratio' holds strings",)),
    # what a reader loads is bounded on the file's metadata (storage.bounds), before any value is read
    Case("info: three unwritten 4000 x 5000 variables", args=("info", "{d}/c.h5"), setup=hc.declared(4000, 5000),
         words=("declares 20000000 values (4000 x 5000)", "at most 10000000"), absent=()),
    Case("plot: three unwritten 4000 x 5000 variables", args=("plot", "{d}/c.h5"), setup=hc.declared(4000, 5000),
         words=("declares 20000000 values",), absent=("c.png",)),
    Case("info: an unwritten variable reads as zeros", args=("info", "{d}/c.h5"), setup=hc.declared(2, 40),
         words=("'transmissibility' declares 80 values but stores 0 of their 640 bytes",), absent=()),
    Case("check: an unwritten variable", args=("check", "{d}/c.h5"), setup=hc.declared(2, 40, names=("regime",)),
         words=("stores 0 of",), absent=()),
    Case("info: external storage", args=("info", "{d}/c.h5"), setup=hc.external("ext.bin"),
         words=("'peak_phase' keeps its values in an external file",), absent=()),
    Case("plot: external storage", args=("plot", "{d}/c.h5"), setup=hc.external("ext.bin"),
         words=("external file",), absent=("c.png",)),
    Case("info: a virtual dataset", args=("info", "{d}/c.h5"), setup=hc.virtual, words=("virtual dataset",),
         absent=()),
    Case("info: a soft link", args=("info", "{d}/c.h5"), setup=hc.linked("soft"), words=("SoftLink", "never links"),
         absent=()),
    Case("plot: an external link", args=("plot", "{d}/c.h5"), setup=hc.linked("external"),
         words=("ExternalLink",), absent=("c.png",)),
    Case("info: a group", args=("info", "{d}/c.h5"), setup=hc.linked("group"), words=("'extra' is a group",),
         absent=()),
    Case("info on a folder", args=("info", "{d}"), words=("not a regular file", "a directory"), absent=()),
    # a cube's text is data: printed with its control characters escaped
    Case("info: OSC, BEL and CR in the history", args=("info", "{d}/c.h5"), exit=0, absent=(),
         setup=hc.with_attribute("history", "\x1b]0;owned\x07ok\rX"), words=("history: \\x1b]0;owned\\x07ok\\x0dX",)),
    Case("info: CSI, C1, bidi and U+2028 in the spec path", args=("info", "{d}/c.h5"), exit=0, absent=(),
         setup=hc.with_attribute("spec_path", "\x1b[2J\x9b1m\u202eevil\u2028.yaml"),
         words=("spec: \\x1b[2J\\x9b1m\\u202eevil\\u2028.yaml",)),
    Case("info: an escape in the units", args=("info", "{d}/c.h5"), exit=0, absent=(),
         setup=hc.with_attribute("units", "\x1b[8m", "frequency_ratio"), words=("0.5 .. 2 \\x1b[8m",)),
    Case("info: an escape in a variable's name", args=("info", "{d}/c.h5"), absent=(),
         setup=hc.edited(lambda f: f.move("peak_phase", "peak\x1b[31m")),
         words=("peak\\x1b[31m: is not a variable of the result cube schema",)),
    Case("info: an escape in the file's name", args=("info", "{d}/n\x1b[2Jo\u2028.h5"), absent=(),
         words=("n\\x1b[2Jo\\u2028.h5: No such file",)),
    # a name holding a control character is refused (class 15), and the refusal prints it escaped
    Case("plot: a C1 control in the file's name", args=("plot", "{d}/n\x9bo.h5"), absent=(),
         words=("n\\x9bo.png' holds a control character (U+009B",)),
    Case("validate: an OSC in the spec's name", spec=None, args=("validate", "{d}/s\x1b]0;x\x07.yaml"),
         setup=lambda d: (d / "s\x1b]0;x\x07.yaml").write_text(GOOD),
         words=("s\\x1b]0;x\\x07.yaml' holds a control character (U+001B",)),
    # ---- issue 28: physics: energy balance (viscous_damping 0 or >= 1e-6; check's energy rule)
    Case("damping 1e-18 next to resonance", _damped("base", "1.0e-18"),
         words=("spec.yaml:1:", "scene.effects.viscous_damping", "must be 0 or at least 1e-06")),
    Case("damping 1e-20, force", _damped("force", "1.0e-20"), words=("must be 0 or at least 1e-06",)),
    Case("damping 1e-17 to the base, joined", _damped("joined", "{ratio: 1.0e-17, to: base}"),
         words=("scene.effects.viscous_damping.ratio", "must be 0 or at least 1e-06")),
    Case("damping 1e-9 spring-parallel", _damped("base", "{ratio: 1.0e-9, to: base}"),
         words=("viscous_damping.ratio", "at least 1e-06")),
    Case("damping 5e-324 (subnormal)", _damped("base", "5.0e-324"), words=("at least 1e-06",)),
    Case("damping 1e-12 with rk4", _damped("base", "1.0e-12", "rk4"), words=("at least 1e-06",)),
    Case("damping 1e-18 with the Jenkins contact", _damped("base", "1.0e-18, contact_stiffness: 100"),
         words=("viscous_damping", "at least 1e-06")),
    Case("damping 1e-18 in a stepped sweep", _damped("base", "1.0e-18") + "sweep: {direction: up}\n",
         words=("at least 1e-06",)),
    Case("damping 1e-18, validate", _damped("base", "1.0e-18"), args=("validate", "{spec}"),
         words=("at least 1e-06",)),
    # main's wrong orbit records a damping below the floor: no run writes that cube, every reader refuses it
    # (round 2); the energy rule's failure on it is tests/test_energy_balance.py's
    Case("check refuses main's wrong orbit at zeta 1e-18", spec=None, args=("check", "{d}/wrong.h5"),
         setup=lambda d: _wrong_orbit_cube(d / "wrong.h5"),
         words=("effect viscous_damping is not a number in 0 or [1e-06, 1): 1e-18",), absent=()),
    # ---- issue 28: files and checkpoints
    # a checkpoint is one sweep's: its key covers what `accuracy:` resolved, and the calibration
    Case("resume after the user calibration changed", spec=None, args=RESUME, setup=_calibration_changed,
         env={"XDG_DATA_HOME": "{d}/xdg"}, words=("different sweep", "calibration"), absent=("out.h5", ".out.h5.lock"),
         exist=(".out.h5.partial/tile-00000.npz",), lines=2),  # the first line says what accuracy: chose
    # a tile proves it belongs (fingerprint, index, grid values) and holds the sweep's variables, exactly typed
    Case("a tile of another sweep of the same shape", setup=_foreign_tile,
         words=("tile-00000.npz does not carry this sweep's fingerprint",), **RESUMED),
    Case("a tile in another tile's place", setup=_swapped_tile, words=("tile-00001.npz carries another tile's index",),
         **RESUMED),
    Case("a tile without its proof", setup=_edit_tile(lambda t: {k: v for k, v in t.items() if k != "fsweep_key"}),
         words=("does not carry this sweep's fingerprint",), **RESUMED),
    Case("a tile claiming other grid values", setup=_edit_tile(
        lambda t: {**t, "fsweep_frequency_ratio": t["fsweep_frequency_ratio"] * (1 + 1e-15)}),
        words=("other frequency_ratio values",), **RESUMED),
    Case("a tile cast to float16", setup=_edit_tile(lambda t: {**t, "transmissibility": t["transmissibility"].astype(
        np.float16)}), words=("other dtypes",), **RESUMED),
    Case("a tile of int64 regimes", setup=_edit_tile(lambda t: {**t, "regime": t["regime"].astype(np.int64)}),
         words=("other dtypes",), **RESUMED),
    Case("a tile missing phase", setup=_edit_tile(lambda t: {k: v for k, v in t.items() if "phase" not in k}),
         words=("lacks peak_phase, phase",), **RESUMED),
    Case("a tile with an extra variable", setup=_edit_tile(lambda t: {**t, "friction_energy": t["transmissibility"]}),
         words=("holds friction_energy too",), **RESUMED),
    Case("a tile with a 1-D transmissibility", setup=_edit_tile(
        lambda t: {**t, "transmissibility": t["transmissibility"][0]}), words=(), **RESUMED),
    # no command replaces a file without --overwrite, and none ever writes over its own input
    Case("calibrate into its data's folder", spec=None, args=("calibrate", "{d}/rig.yaml", "-q"),
         setup=lambda d: _calibration_spec(d, "rigdir/map.csv", "rigdir"), words=("map.csv is", "an input"),
         check=_unchanged_as("rigdir/map.csv", _rig_data)),
    Case("calibrate --overwrite onto its data", spec=None, args=("calibrate", "{d}/rig.yaml", "-q", "--overwrite"),
         setup=lambda d: _calibration_spec(d, "rigdir/map.csv", "rigdir"),
         words=("an input of this command", "not even with --overwrite"), check=_unchanged_as("rigdir/map.csv", _rig_data)),
    Case("calibrate: a spec named report.md", spec=None, args=("calibrate", "{d}/report.md", "-q", "--overwrite"),
         setup=lambda d: _calibration_spec(d, "rigdir/data.csv", str(d), name="report.md"),
         words=("report.md is", "an input of this command")),
    Case("calibrate into a folder of earlier results", spec=None, args=("calibrate", "{d}/rig.yaml", "-q"),
         setup=lambda d: (_calibration_spec(d, "rigdir/data.csv", "res"), (d / "res").mkdir(),
                          (d / "res" / "corner.png").write_text("earlier")),
         words=("corner.png exists",), check=lambda d: _same_text(d / "res" / "corner.png", "earlier")),
    Case("validate-data onto its own data", spec=None,
         args=("validate-data", "--data", "{d}/v/table.csv", "-o", "{d}/v", "--overwrite"),
         setup=lambda d: ((d / "v").mkdir(), (d / "v" / "table.csv").write_text(_rig_data())),
         words=("table.csv is", "an input of this command"), check=_unchanged_as("v/table.csv", _rig_data)),
    Case("validate-data over an earlier table", spec=None, args=("validate-data", "-o", "{d}/v"),
         setup=lambda d: ((d / "v").mkdir(), (d / "v" / "table.md").write_text("mine")),
         words=("table.md exists", "--overwrite"), check=lambda d: _same_text(d / "v" / "table.md", "mine")),
    Case("bench over notes beside its dataset", spec=None, args=("bench", "--quick", "-o", "{d}/notes.h5"),
         setup=_bench_notes, words=("notes.png exists", "--overwrite"), absent=("notes.h5",),
         check=lambda d: (_same_text(d / "notes.md", "my notes"), _same_text(d / "notes.png", "my picture"))),
    Case("bench --calibrate over a calibration", spec=None,
         args=("bench", "--calibrate", "--calibration", "{d}/cal.json", "-o", "{d}/wp.h5"),
         setup=lambda d: (d / "cal.json").write_text("{}"), words=("cal.json exists",), absent=("wp.h5",),
         check=lambda d: _same_text(d / "cal.json", "{}")),
    Case("plot over an existing PNG", args=("plot", "{d}/out.h5"), setup=lambda d: (_good_cube(d), (
        d / "out.png").write_text("mine")), words=("out.png exists", "--overwrite"), absent=(),
        check=lambda d: _same_text(d / "out.png", "mine")),
    Case("run over the calibration accuracy: reads", ACCURATE, env={"XDG_DATA_HOME": "{d}/xdg"},
         args=("run", "{spec}", "-o", "{d}/xdg/friction_sweep/calibration.json", "--overwrite", "-q"),
         setup=_user_calibration, words=("calibration.json is", "an input of this command"),
         check=_unchanged_as("xdg/friction_sweep/calibration.json", lambda: _packaged_calibration())),
    Case("validate: output the calibration accuracy: reads", ACCURATE, env={"XDG_DATA_HOME": "{d}/xdg"},
         args=("validate", "{spec}", "-o", "{d}/xdg/friction_sweep/calibration.json"), setup=_user_calibration,
         words=("an input of this command",)),
    Case("plot onto a hard link of its cube", args=("plot", "{d}/out.h5", "-o", "{d}/link.png", "--overwrite"),
         setup=lambda d: (_good_cube(d), os.link(d / "out.h5", d / "link.png")), words=("an input of this command",),
         absent=(), check=_cube_unchanged),
    # a lock with other names, or content fsweep did not write, is never written into
    Case("lock hard-linked to a victim", setup=_hard_linked_lock, words=("2 names", "hard link"),
         absent=("out.h5", ".out.h5.partial"), check=lambda d: _same_text(d / "victim.txt", "precious")),
    Case("lock hard-linked to the previous cube", args=("run", "{spec}", "--overwrite", "-q"),
         setup=_cube_linked_as_lock, words=("2 names",), absent=(".out.h5.partial",), check=_cube_unchanged),
    Case("lock holding a user's text", setup=lambda d: (d / ".out.h5.lock").write_text("my notes\n"),
         words=("holds data fsweep did not write",), absent=("out.h5", ".out.h5.partial"),
         check=lambda d: _same_text(d / ".out.h5.lock", "my notes\n")),
    # temporaries of a killed writer are removed by the next run on the same output
    Case("temporaries of a killed run", setup=_stale_temporaries, exit=0, exist=("out.h5",),
         absent=(".out.h5.partial", ".out.h5.lock")),
    Case("temporaries of a killed run, output refused", setup=lambda d: (_good_cube(d), _stale_temporaries(d)),
         args=("run", "{spec}", "--resume", "-q"), words=("nothing to resume",), absent=(".out.h5.partial",)),
    Case("temporaries of a killed run, output exists", setup=lambda d: (_good_cube(d), _stale_temporaries(d)),
         words=("exists", "--overwrite"), absent=(".out.h5.partial",), check=_cube_unchanged),
    # names: UTF-8 without controls, short enough for fsweep's hidden files, a file; the same for validate
    Case("spec name not UTF-8", spec=None, args=("run", "{d}/sp\udcff.yaml", "-q"),
         setup=lambda d: (d / "sp\udcff.yaml").write_text(GOOD), words=("spec", "not valid UTF-8")),
    Case("validate: spec name not UTF-8", spec=None, args=("validate", "{d}/sp\udcff.yaml"),
         setup=lambda d: (d / "sp\udcff.yaml").write_text(GOOD), words=("not valid UTF-8",)),
    Case("-o not UTF-8", args=("run", "{spec}", "-o", "\udced\udca0\udc80.h5", "-q"), words=("not valid UTF-8",)),
    Case("validate: -o not UTF-8", args=("validate", "{spec}", "-o", "\udced\udca0\udc80.h5"),
         words=("not valid UTF-8",)),
    Case("output: a lone surrogate", GOOD.replace("output: out.h5", 'output: "\\ud800.h5"'), words=("not valid UTF-8",)),
    Case("validate: output a lone surrogate", GOOD.replace("output: out.h5", 'output: "\\ud800.h5"'),
         args=("validate", "{spec}"), words=("not valid UTF-8",)),
    Case("validate-data: data name not UTF-8", spec=None, args=("validate-data", "--data", "{d}/d\udcff.csv", "-o",
                                                                 "{d}/v"),
         setup=lambda d: (d / "d\udcff.csv").write_text(_rig_data()), words=("data", "not valid UTF-8"), absent=("v",)),
    Case("calibrate: spec name not UTF-8", spec=None, args=("calibrate", "{d}/r\udcff.yaml", "-q"),
         setup=lambda d: (_calibration_spec(d, "rigdir/data.csv", "res"), (d / "rig.yaml").rename(d / "r\udcff.yaml")),
         words=("spec", "not valid UTF-8"), absent=("res",)),
    Case("plot -o not UTF-8", args=("plot", "{d}/out.h5", "-o", "\udcff.png"), setup=_good_cube,
         words=("not valid UTF-8",), absent=()),
    Case("validate: a 240-character name", args=("validate", "{spec}", "-o", "a" * 237 + ".h5"),
         words=("240 bytes long", "at most 215")),
    Case("a 217-byte name", args=("run", "{spec}", "-o", "é" * 107 + ".h5", "-q"), words=("217 bytes long",)),
    Case("DEL in -o", args=("run", "{spec}", "-o", "out\x7f.h5", "-q"), words=("control character", "U+007F")),
    Case("NEL in -o", args=("validate", "{spec}", "-o", "out\x85.h5"), words=("control character", "U+0085")),
    Case("line separator in -o", args=("run", "{spec}", "-o", "out\u2028.h5", "-q"), words=("U+2028",)),
    Case("paragraph separator in the spec's output", GOOD.replace("output: out.h5", 'output: "out\\u2029.h5"'),
         words=("U+2029",)),
    Case("right-to-left override in -o", args=("run", "{spec}", "-o", "out\u202egnp.h5", "-q"), words=("U+202E",)),
    Case("zero-width space in bench -o", spec=None, args=("bench", "--quick", "-o", "{d}/wp\u200b.h5"),
         words=("U+200B",)),
    Case("-o x.h5/.", args=("run", "{spec}", "-o", "x.h5/.", "-q"), words=("names a folder",), absent=("x.h5",)),
    Case("validate: -o x.h5/..", args=("validate", "{spec}", "-o", "x.h5/.."), words=("names a folder",)),
    # ---- issue 28: signals, executors and the estimate (signals, Dask faults and the estimate's model:
    # tests/test_signals.py, tests/test_estimate.py)
    Case("--scheduler empty", args=("run", "{spec}", "--scheduler", "", "-q"), words=("is not a scheduler address",)),
    Case("--scheduler empty beside another executor",
         args=("run", "{spec}", "--executor", "threads", "-j", "2", "--scheduler", "", "-q"),
         words=("is not a scheduler address",)),
    Case("-j 1024 threads: as many workers as help", args=("run", "{spec}", "-j", "1024"), exit=0,
         words=("(not 1024:", "wrote"), exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"), lines=None),
    Case("-j 1024 processes: as many workers as help", args=("run", "{spec}", "--executor", "processes", "-j", "1024"),
         exit=0, words=("(not 1024:", "wrote"), exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"),
         lines=None),
    Case("-j 24 dask on one point: one worker", spec=GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "[1.5]")
         .replace("[0.1, 0.4]", "[0.3]"), args=("run", "{spec}", "--executor", "dask", "-j", "24"), exit=0,
         words=("with 1 worker(s) (not 24: the run has 1 tile(s))", "wrote"), exist=("out.h5",),
         absent=(".out.h5.partial", ".out.h5.lock"), lines=None),
    Case("-j 1024 serial: one worker", args=("run", "{spec}", "--executor", "serial", "-j", "1024"), exit=0,
         words=("with 1 worker(s) (not 1024: --executor serial runs one)",), exist=("out.h5",),
         absent=(".out.h5.partial", ".out.h5.lock"), lines=None),
    # ---- issue 28, round 2: files, names and the API
    # fsweep removes only a checkpoint folder that is provably its own (its names, its manifest, regular files);
    # anything else in .out.h5.partial is refused (exit 2, named, with the rm -r command) and left as it was
    Case("a user's file in an empty checkpoint folder", setup=_partial_holding("thesis.tex"),
         words=("thesis.tex", "did not write", "rm -r"), absent=("out.h5", ".out.h5.lock"),
         check=_kept_in_partial("thesis.tex")),
    Case("validate: a user's file in the checkpoint folder", args=("validate", "{spec}"),
         setup=_partial_holding("thesis.tex"), words=("thesis.tex", "did not write"),
         absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("thesis.tex")),
    Case("--overwrite: a user's file in the checkpoint folder", args=("run", "{spec}", "-q", "--overwrite"),
         setup=_partial_holding("thesis.tex"), words=("thesis.tex",), absent=("out.h5", ".out.h5.lock"),
         check=_kept_in_partial("thesis.tex")),
    Case("a user's folder in the checkpoint folder", setup=_partial_holding("chapters/one.tex"),
         words=("chapters",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("chapters/one.tex")),
    Case("a user's hidden file in the checkpoint folder", setup=_partial_holding(".notes"),
         words=(".notes",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial(".notes")),
    Case("a file named like fsweep's but not its", setup=_partial_holding("tile-1.npz"),
         words=("tile-1.npz",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("tile-1.npz")),
    Case("a manifest.json that is not fsweep's", setup=_partial_holding("manifest.json"),
         words=("manifest.json cannot be read", "rm -r"), absent=("out.h5", ".out.h5.lock"),
         check=_kept_in_partial("manifest.json")),
    Case("a manifest.json of JSON not fsweep's", setup=lambda d: ((d / ".out.h5.partial").mkdir(),
                                                                 (d / ".out.h5.partial/manifest.json").write_text('{"a": 1}')),
         words=("manifest.json cannot be read",), absent=("out.h5", ".out.h5.lock"),
         check=lambda d: _same_text(d / ".out.h5.partial/manifest.json", '{"a": 1}')),
    Case("a link in the checkpoint folder", setup=_partial_link, words=("tile-00000.npz", "did not write"),
         absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("victim.txt", top=True)),
    Case("five strangers in the checkpoint folder", setup=_partial_holding("a", "b", "c", "d", "e"),
         words=("a, b, c and 2 more",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("e")),
    Case("an empty checkpoint folder is fsweep's to remove", setup=lambda d: (d / ".out.h5.partial").mkdir(),
         exit=0, exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"), lines=None),
    Case("a checkpoint of only a killed writer's temporary", setup=_partial_stale_temporary, exit=0,
         exist=("out.h5",), absent=(".out.h5.partial", ".out.h5.lock"), lines=None),
    Case("--resume: a user's file among the finished tiles", spec=None, args=RESUME,
         setup=lambda d: (_interrupted(d, EVENT_LONG), (d / ".out.h5.partial" / "thesis.tex").write_text("precious")),
         words=("thesis.tex",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("thesis.tex")),
    Case("--resume: a user's folder named like a tile", spec=None, args=RESUME, setup=_user_tile_folder,
         words=("tile-00003.npz",), absent=("out.h5", ".out.h5.lock"), check=_kept_in_partial("tile-00003.npz/x")),
    # one rule for every name fsweep checks: UTF-8 without controls, format characters, separators, private-use
    # characters, noncharacters or unassigned code points; and a refusal says "output:" once
    Case("output: a noncharacter", GOOD.replace("output: out.h5", 'output: "a\\uFFFEb.h5"'), args=("validate", "{spec}"),
         words=("noncharacter (U+FFFE)",)),
    Case("-o U+FFFF", args=("run", "{spec}", "-o", "a\uffff.h5", "-q"), words=("noncharacter (U+FFFF)",)),
    Case("-o U+FDD0", args=("validate", "{spec}", "-o", "a\ufdd0.h5"), words=("noncharacter (U+FDD0)",)),
    Case("-o U+10FFFF", args=("run", "{spec}", "-o", "a\U0010ffff.h5", "-q"), words=("noncharacter (U+10FFFF)",)),
    Case("-o a private-use character", args=("run", "{spec}", "-o", "a\ue000.h5", "-q"),
         words=("private-use character (U+E000)",)),
    Case("output: a plane-15 private-use character", GOOD.replace("output: out.h5", 'output: "a\\U000F0000.h5"'),
         words=("private-use character (U+F0000)",)),
    Case("-o an unassigned code point", args=("validate", "{spec}", "-o", "a\u0378.h5"),
         words=("unassigned code point (U+0378)",)),
    Case("spec named with a private-use character", spec=None, args=("run", "{d}/s\uf8ff.yaml", "-q"),
         setup=lambda d: (d / "s\uf8ff.yaml").write_text(GOOD), words=("spec", "U+F8FF")),
    Case("plot -o a noncharacter", args=("plot", "{d}/out.h5", "-o", "p\ufffe.png"), setup=_good_cube,
         words=("error: output: the file name", "U+FFFE"), absent=()),
    Case("bench -o a private-use character", spec=None, args=("bench", "--quick", "-o", "{d}/wp\ue000.h5"),
         words=("error: output: the file name", "U+E000")),
    Case("validate-data -o a noncharacter", spec=None,
         args=("validate-data", "--data", "{d}/t.csv", "-o", "{d}/v\ufffe"),
         setup=lambda d: (d / "t.csv").write_text(_rig_data()), words=("error: output: the file name", "U+FFFE")),
    Case("a 253-byte name: output said once", args=("run", "{spec}", "-o", "a" * 250 + ".h5", "-q"),
         words=("error: output: the file name is 253 bytes",)),
    Case("plot -o not UTF-8: output said once", args=("plot", "{d}/out.h5", "-o", "p\udcff.png"), setup=_good_cube,
         words=("error: output: the file name 'p\\udcff.png' is not valid UTF-8",), absent=()),
    # a value in a message is shown as YAML by one formatter (spec.base.show): never a Python repr of an internal
    # type, never a huge integer converted to text whole
    Case("a !!set axis", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "!!set {a}"), words=("(got a set (!!set) {'a'})",)),
    Case("a !!set method", GOOD.replace("method: theory", "method: !!set {theory}"), words=("a set (!!set)",)),
    Case("a !!binary setting", _settings("event", "steady_tol: !!binary aGVsbG8="),
         words=("must be a number (got binary data of 5 bytes (!!binary))",)),
    Case("a timestamp setting", _settings("event", "steady_tol: 2001-12-14"),
         words=("must be a number (got a timestamp (2001-12-14))",)),
    Case("a 101-digit ratio", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "1" + "0" * 100),
         words=("(got an integer of 101 digits)",)),
    Case("a 5001-digit integer", GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "1" + "0" * 5000),
         words=("!!int cannot hold '1000", "000...",)),
    # ---- issue 28, round 2: cube readers and check
    # the provenance a reader relies on is read by one bounded reader and audited by open_cube: all refuse alike
    *(Case(f"{command}: method_settings nested 100000 deep", args=(command, "{d}/c.h5"),
           setup=hc.with_attribute("method_settings", "[" * 100_000 + "]" * 100_000),
           words=("provenance: attribute method_settings holds 200000 characters",), absent=("c.png",))
      for command in ("info", "check", "plot")),
    Case("check: method_settings nested 500 deep, short", args=("check", "{d}/c.h5"),
         setup=hc.with_attribute("method_settings", '{"a": ' * 500 + "1" + "}" * 500),
         words=("attribute method_settings nests deeper than 8 levels",)),
    Case("plot: physical_system nested 1000 deep", args=("plot", "{d}/c.h5"),
         setup=hc.with_attribute("physical_system", "[" * 1000 + "]" * 1000),
         words=("attribute physical_system nests deeper",), absent=("c.png",)),
    *(Case(f"{command}: excitation an escape sequence", args=(command, "{d}/c.h5"),
           setup=hc.with_attribute("excitation", "\x1b]0;pwn\x07"),
           words=("attribute excitation '\\x1b]0;pwn\\x07' is not one of force, base, joined",), absent=("c.png",))
      for command in ("info", "plot")),
    *(Case(f"{command}: method bogus", args=(command, "{d}/c.h5"), setup=hc.with_attribute("method", "bogus"),
           words=("attribute method 'bogus' is not a method of the catalogue",), absent=("c.png",))
      for command in ("info", "check", "plot")),
    *(Case(f"info: method_settings {text}", args=("info", "{d}/c.h5"), setup=hc.with_attribute("method_settings", text),
           words=(words,)) for text, words in (
        ("[]", "method_settings is not a JSON object"), ("null", "method_settings is not a JSON object"),
        ("{", "method_settings is not JSON"), ('{"effects": "x"}', "effects is not a JSON object"),
        ('{"effects": {}, "steady_tol": -1}', "steady_tol is not a setting of method theory"),
        ('{"effects": {"viscous_damping": 0.1}}', "method theory does not model it"))),
    Case("plot: an event cube's steady_tol -1", args=("plot", "{d}/c.h5"),
         setup=hc.edited(lambda f: f.attrs.update(method="event", method_settings='{"effects": {}, "steady_tol": -1}')),
         words=("steady_tol is not a number in [1e-13, 1e-06]: -1",), absent=("c.png",)),
    Case("check: a negative damping (was check FAILED, exit 1)", args=("check", "{d}/c.h5"),
         setup=hc.edited(lambda f: f.attrs.update(method="event",
                                                  method_settings='{"effects": {"viscous_damping": -0.5}}')),
         words=("effect viscous_damping is not a number in 0 or [1e-06, 1): -0.5",)),
    # a compressed file is read up to 64 times its size
    Case("info: a compressed bomb", args=("info", "{d}/c.h5"), setup=hc.compressed(1000, 2000),
         words=("compressed variables expand to 48000000 bytes", "up to 64 times their size")),
    # ---- issue 32: the resonance peak and the optimum friction (fsweep peak, fsweep optimize)
    *(Case(f"{command}: method theory (no per-point solve to refine on)", args=(command, "{spec}", "-o", "out.h5"),
           words=("method: the resonance peak is built on methods event, rk4, auto",)) for command in ("peak", "optimize")),
    Case("optimize: two force ratios bracket no optimum", spec=EVENT, args=("optimize", "{spec}", "-o", "out.h5"),
         words=("grid.force_ratio: the optimum is searched from at least 3 force ratios (got 2)",)),
    Case("peak: two frequency ratios", spec=EVENT.replace("{start: 0.5, stop: 2.0, num: 40}", "[0.5, 2.0]"),
         args=("peak", "{spec}"), words=("grid.frequency_ratio: the peak is searched from at least 3",)),
    Case("peak: a sweep section", spec=EVENT + "sweep: {direction: up}\n", args=("peak", "{spec}"),
         words=("sweep: the resonance peak solves each point on its own",)),
    Case("peak: -o over the spec itself", spec=EVENT, args=("peak", "{spec}", "-o", "{spec}", "--overwrite"),
         words=("an input of this command",), absent=()),
    # ---- issue 29/33: packaging and CLI
    # files shipped with the package are named package:PATH (friction_sweep/packaged.py); a name that is not
    # one of them is refused as itself, before anything is read
    *(Case(f"{command}: a packaged spec that is not there", spec=None, args=(command, "package:examples/nope.yaml"),
           words=("'package:examples/nope.yaml': no such file in the installed package", "package:examples/NAME.yaml"))
      for command in ("run", "validate", "calibrate")),
    *(Case(f"run: package:{rest}", spec=None, args=("run", f"package:{rest}"), words=("PATH inside the package",))
      for rest in ("../configs/demo.yaml", "/etc/hostname", "", "examples/../examples/demo.yaml")),
    Case("validate-data --data a packaged file that is not there", spec=None,
         args=("validate-data", "--data", "package:data/nope.csv", "-o", "{d}/v"),
         words=("'package:data/nope.csv': no such file",), absent=("v",)),
    Case("calibration spec: data package:data/nope.csv", spec=None, args=("calibrate", "{d}/cal.yaml", "-o", "{d}/cal"),
         setup=lambda d: (_calibration("discrepancy_phase: {normal: [0 deg, 3 deg]}")(d), (d / "cal.yaml").write_text(
             (d / "cal.yaml").read_text().replace("file: rig.csv", "file: package:data/nope.csv"))),
         words=("cal.yaml:2:", "data.file", "'package:data/nope.csv': no such file in the installed package"),
         absent=("cal",), lines=2),
    # "-" for an output is the command-line convention for standard output: it wrote a file named "-"
    *(Case(f"{args[0]} -o -", spec=spec, args=args, setup=setup, words=("'-' would be standard output",),
           absent=("-",))
      for spec, args, setup in (
          (GOOD, ("run", "{spec}", "-q", "-o", "-"), None),
          (GOOD, ("validate", "{spec}", "-o", "-"), None),
          (GOOD, ("plot", "{d}/out.h5", "-o", "-"), _good_cube),
          (None, ("bench", "--quick", "-o", "-"), None),
          (None, ("calibrate", "{d}/cal.yaml", "-q", "-o", "-"), _calibration("discrepancy_phase: {normal: [0 deg, 3 deg]}")),
          (None, ("validate-data", "-o", "-"), None))),
    Case("spec output: -", spec=GOOD.replace("output: out.h5", "output: '-'"), words=("output: '-' would be standard output",),
         absent=("-",)),
    # ---- issue 30: structure specs
    # an end, or a forced mass, that names no mass
    _structure_case("structure: a spring to an unknown mass", "4:43: structure.springs[1][1]",
                    ("[blade, damper, 2.0]", "[blade, dumper, 2.0]"), words=("'dumper' is no mass",)),
    _structure_case("structure: a spring from an unknown mass", "4:36: structure.springs[1][0]",
                    ("[blade, damper, 2.0]", "[blades, damper, 2.0]"), words=("'blades' is no mass",)),
    _structure_case("structure: a dashpot to an unknown mass", "5:22: structure.dampers[0][1]",
                    ("[[ground, blade, 0.004]]", "[[ground, blad, 0.004]]"), words=("'blad' is no mass",)),
    _structure_case("structure: a contact to an unknown mass", "7:34: structure.contacts[0].between[0]",
                    ("between: [damper, ground]", "between: [dampr, ground]"), words=("'dampr' is no mass",)),
    _structure_case("structure: forcing an unknown mass", "9:13: structure.forcing.blades",
                    ("forcing: {blade: 1.0}", "forcing: {blades: 1.0}"), words=("'blades' is no mass",)),
    # an element between a mass and itself, or between the two supports
    _structure_case("structure: a contact between a mass and itself", "7:42: structure.contacts[0].between[1]",
                    ("between: [damper, ground]", "between: [damper, damper]"), words=("and itself",)),
    _structure_case("structure: a spring between a mass and itself", "4:43: structure.springs[1][1]",
                    ("[blade, damper, 2.0]", "[blade, blade, 2.0]"), words=("a spring between 'blade' and itself",)),
    _structure_case("structure: a contact between ground and base", "7:40: structure.contacts[0].between[1]",
                    ("between: [damper, ground]", "between: [base, ground]"), words=("holds no mass",)),
    # masses that are not positive, stiffness, damping or friction that is negative
    *(_structure_case(f"structure: a mass of {text}", "3:32: structure.masses.damper",
                      ("damper: 0.1}", f"damper: {text}}}"), words=(words,))
      for text, words in (("0", "a mass must be > 0 (got 0)"), ("-1", "a mass must be > 0 (got -1)"),
                          (".nan", "must be a finite number"), ("heavy", "must be a number (got 'heavy')"),
                          ("true", "must be a number (got true)"))),
    _structure_case("structure: a negative spring", "4:51: structure.springs[1][2]",
                    ("[blade, damper, 2.0]", "[blade, damper, -2.0]"), words=("stiffness must be >= 0 (got -2.0)",)),
    _structure_case("structure: a negative dashpot", "5:29: structure.dampers[0][2]",
                    ("[[ground, blade, 0.004]]", "[[ground, blade, -0.004]]"), words=("damping must be >= 0",)),
    _structure_case("structure: a negative friction", "7:61: structure.contacts[0].friction",
                    ("friction: 0.3}", "friction: -0.3}"), words=("must be >= 0 (got -0.3)",)),
    *(_structure_case(f"structure: a Jenkins stiffness of {k}", "8:70: structure.contacts[1].stiffness",
                      ("stiffness: 20", f"stiffness: {k}"), words=(f"must be > 0 (got {k})",)) for k in ("-20", "0")),
    _structure_case("structure: a static friction ratio below 1", "8:97: structure.contacts[1].static_friction_ratio",
                    ("static_friction_ratio: 1.2", "static_friction_ratio: 0.5"), words=("must be >= 1",)),
    # an unrestrained rigid-body motion: with every contact stuck nothing holds it
    _structure_case("structure: a mass held by a dashpot only", "3:37: structure.masses.tip",
                    ("masses: {blade: 1.0, damper: 0.1}", "masses: {blade: 1.0, damper: 0.1, tip: 1}"),
                    ("[[ground, blade, 0.004]]", "[[ground, blade, 0.004], [ground, tip, 1]]"),
                    words=("unrestrained: with every contact stuck, nothing holds the motion of 'tip'",)),
    _structure_case("structure: a pair held only by each other", "3:37: structure.masses.a",
                    ("masses: {blade: 1.0, damper: 0.1}", "masses: {blade: 1.0, damper: 0.1, a: 1, b: 2}"),
                    ("[blade, damper, 2.0]]", "[blade, damper, 2.0], [a, b, 5]]"),
                    ("    - {name: root", "    - {name: ab, between: [a, b], friction: 1}\n    - {name: root"),
                    words=("nothing holds the motion of 'a', 'b'",)),
    _structure_case("structure: base excitation, a mass on a dashpot to the base", "3:37: structure.masses.tip",
                    ("masses: {blade: 1.0, damper: 0.1}", "masses: {blade: 1.0, damper: 0.1, tip: 1}"),
                    ("[[ground, blade, 0.004]]", "[[ground, blade, 0.004], [base, tip, 1]]"), base=True,
                    words=("nothing holds the motion of 'tip'",)),
    # the excitation and its amplitudes
    _structure_case("structure: forcing under base excitation", "9:3: structure.forcing",
                    ("  base_amplitude: 0.5\n", "  forcing: {blade: 1.0}\n"), base=True,
                    words=("forcing is for excitation force",)),
    _structure_case("structure: base_amplitude under force excitation", "10:19: structure.base_amplitude",
                    ("  forcing: {blade: 1.0}\n", "  forcing: {blade: 1.0}\n  base_amplitude: 1.0\n"),
                    words=("base_amplitude is for excitation base",)),
    _structure_case("structure: force excitation without forcing", "2:1: structure",
                    ("  forcing: {blade: 1.0}\n", ""), words=("a force excitation needs `forcing:",)),
    _structure_case("structure: forcing all zero", "9:3: structure.forcing",
                    ("forcing: {blade: 1.0}", "forcing: {blade: 0}"), words=("nothing drives the structure",)),
    _structure_case("structure: base excitation connected to nothing", "2:1: structure",
                    ("[blade, base]", "[blade, ground]"), base=True, words=("nothing connects to base",)),
    _structure_case("structure: a negative base amplitude", "9:19: structure.base_amplitude",
                    ("base_amplitude: 0.5", "base_amplitude: -0.5"), base=True, words=("must be > 0",)),
    # names: twice, or a support's
    _structure_case("structure: two contacts of one name", "8:14: structure.contacts[1].name",
                    ("name: root", "name: platform"), words=("contact name 'platform' is given twice",)),
    _structure_case("structure: a mass given twice", "3:37: structure.masses.damper",
                    ("damper: 0.1}", "damper: 0.1, damper: 1}"), words=("duplicate key 'damper'",)),
    *(_structure_case(f"structure: a mass named {name}", f"3:37: structure.masses.{name}",
                      ("damper: 0.1}", f"damper: 0.1, {name}: 1}}"), words=(f"'{name}' names a support",))
      for name in ("ground", "base")),
    _structure_case("structure: a contact named by a control character", "7:14: structure.contacts[0].name",
                    ("name: platform", 'name: "plat\\x07form"'), words=("holds a control character",)),
    # the grid: frequencies > 0, friction scales >= 0
    _structure_case("structure: a frequency range from 0", "11:22: grid.frequency.start",
                    ("start: 0.2", "start: 0"), words=("must be > 0 (got 0)",)),
    _structure_case("structure: a negative frequency in a list", "11:18: grid.frequency[1]",
                    ("{start: 0.2, stop: 3.0, num: 561}", "[1, -1]"), words=("must be > 0 (got -1)",)),
    _structure_case("structure: a frequency of 0", "11:14: grid.frequency",
                    ("{start: 0.2, stop: 3.0, num: 561}", "0"), words=("must be > 0 (got 0)",)),
    _structure_case("structure: a negative friction scale", "12:20: grid.friction_scale[0]",
                    ("[0.25, 0.5, 1.0, 2.0]", "[-0.25, 0.5]"), words=("must be >= 0 (got -0.25)",)),
    _structure_case("structure: friction scales not increasing", "12:25: grid.friction_scale[1]",
                    ("[0.25, 0.5, 1.0, 2.0]", "[0.5, 0.25]"), words=("not sorted",)),
    # empty structures
    _structure_case("structure: no masses", "3:3: structure.masses",
                    ("masses: {blade: 1.0, damper: 0.1}", "masses: {}"), words=("at least one mass",)),
    _structure_case("structure: no contacts", "6:3: structure.contacts",
                    ("  contacts:\n    - {name: platform, between: [damper, ground], friction: 0.3}\n    - {name: root, "
                     "between: [blade, base], friction: 0.2, stiffness: 20, static_friction_ratio: 1.2}\n",
                     "  contacts: []\n"), words=("at least one contact",)),
    # what a structure spec does not take
    _structure_case("structure: method theory", "13:9: method", ("method: event", "method: theory"),
                    words=("a structure is solved by method 'event'",)),
    _structure_case("structure: a 1-DoF output", "14:11: outputs[0]",
                    ("outputs: [amplitude, phase, regime]", "outputs: [transmissibility]"),
                    words=("unknown output 'transmissibility' for a structure",)),
    _structure_case("structure: excitation joined", "1:21: scene.excitation",
                    ("{excitation: force}", "{excitation: joined}"), words=("a structure's excitation is one of",)),
    _structure_case("structure: a contact's unknown key", "7:66: structure.contacts[0].mu",
                    ("friction: 0.3}", "friction: 0.3, mu: 1}"),
                    words=("unknown key 'mu' (allowed: name, between, friction, stiffness, static_friction_ratio)",)),
    _structure_case("structure: a spring of two items", "4:35: structure.springs[1]",
                    ("[blade, damper, 2.0]", "[blade, damper]"), words=("a spring is [a, b, stiffness]",)),
    _structure_case("structure: a setting out of its range", "14:24: settings.steady_tol",
                    ("method: event\n", "method: event\nsettings: {steady_tol: 1}\n"), words=("must be between",)),
    _structure_case("structure: a 1-DoF setting", "14:34: settings.initial_displacement",
                    ("method: event\n", "method: event\nsettings: {initial_displacement: 0.5}\n"),
                    words=("unknown setting 'initial_displacement' for a structure",)),
    # issue 32 for structures: the mass whose peak the design commands take
    _structure_case("structure: peak_dof names no mass", "14:22: settings.peak_dof",
                    ("method: event\n", "method: event\nsettings: {peak_dof: hub}\n"),
                    words=("'hub' is not a mass of the structure (masses: blade, damper)",)),
    _structure_case("structure: peak_dof not a name", "14:22: settings.peak_dof",
                    ("method: event\n", "method: event\nsettings: {peak_dof: 3}\n"), words=("must be a mass's name",)),
    Case("structure: backbone under base excitation", _structure(base=True), args=("backbone", "{spec}"),
         words=("scene: a structure's backbone is the phase resonance against a force: excitation force",)),
    Case("structure: validate refuses as run does", _structure(("damper: 0.1}", "damper: 0}")),
         args=("validate", "{spec}"), words=("spec.yaml:3:32: structure.masses.damper: a mass must be > 0",)),
    # a structure cube: audited against its own table (check and plot read it: tests/test_structure_commands.py)
    Case("structure: info on a regime code no run writes", SMALL_STRUCTURE, args=("info", "{d}/c.h5"),
         setup=hc.value("regime", (0, 1, 1), 9),
         words=("regime: 1 of 64 values are not valid regime codes (e.g. 9 at friction_scale=0.25, frequency=0.6, "
                "contact=root)",)),
    Case("structure: info on a negative amplitude", SMALL_STRUCTURE, args=("info", "{d}/c.h5"),
         setup=hc.value("amplitude", (1, 0, 0), -1.0), words=("amplitude: 1 of 64 values lie outside the valid range",)),
    Case("structure: info on a mass named twice", SMALL_STRUCTURE, args=("info", "{d}/c.h5"),
         setup=hc.value("dof", 1, "blade"), words=("dof: names one entry twice",)),
    Case("structure: calibrate a structure spec", STRUCTURE, args=("calibrate", "{spec}", "-o", "{d}/cal"),
         words=("spec.yaml:2:1: structure: a structure (several masses and contacts) is not calibrated yet",),
         absent=("cal",), lines=2),  # calibrate heads its problems with "invalid calibration spec"
    Case("structure: info on a structure nested 100 deep", SMALL_STRUCTURE, args=("info", "{d}/c.h5"),
         setup=hc.edited(lambda f: f.attrs.update(structure="[" * 100 + "]" * 100)),
         words=("attribute structure nests deeper than 8 levels",)),
]
CASES += ROM_CASES


# cases whose set-up interrupts a real event run in a child process (seconds each), and the deepest YAML
SLOW_CASES = {"bad manifest.json", "truncated tile", "checkpoint of another sweep", "lock is a symlink to a victim",
              "a folder named like a tile", "a tile of strings", "a tile of regime 1e300", "5000-deep list",
              "resume after the user calibration changed", "a tile of another sweep of the same shape",
              "a tile in another tile's place", "a tile without its proof", "a tile claiming other grid values",
              "a tile cast to float16", "a tile of int64 regimes", "a tile missing phase",
              "a tile with an extra variable", "a tile with a 1-D transmissibility",
              "--resume: a user's file among the finished tiles", "--resume: a user's folder named like a tile"}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.id in SLOW_CASES else c for c in CASES],
                         ids=lambda c: c.id)
def test_hostile_case(case: Case, tmp_path: Path, compiled) -> None:
    d = tmp_path
    if case.spec is not None:
        (d / "spec.yaml").write_bytes(case.spec.encode("latin-1") if "\x00" in case.spec else case.spec.encode())
    if case.setup is not None:
        case.setup(d)
    args = [a.format(spec=d / "spec.yaml", d=d) for a in case.args]
    with in_dir(d):
        res = CliRunner().invoke(main, args, env={k: v.format(d=d) for k, v in case.env.items()})
    assert res.exception is None or isinstance(res.exception, SystemExit), (
        f"traceback: {res.exception!r}\n{res.output}")
    assert "Traceback" not in res.output
    assert res.exit_code == case.exit, res.output
    for word in case.words:
        assert word in res.output, f"{word!r} not in {res.output!r}"
    if case.exit != 0 and case.lines is not None:
        lines = [ln for ln in res.output.splitlines() if ln != "fsweep: error: invalid spec"]
        assert len(lines) == case.lines, res.output
    for pattern in case.exist:
        assert list(d.glob(pattern)), f"{pattern} should exist: {sorted(p.name for p in d.iterdir())}"
    for name in case.absent:
        assert not os.path.lexists(d / name), f"{name} should not exist"
    leftovers = [p for p in d.rglob("*") if p.name.endswith((".tmp", ".probe", ".staged"))]
    assert not leftovers, leftovers
    if case.check is not None:
        case.check(d)


# ---- faults: a full disk, file modes, locks; and the estimate's honesty -------------------------

WIDE = GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "{start: 0.1, stop: 3.0, num: 300}").replace(
    "[0.1, 0.4]", "{start: 0, stop: 1, num: 30}")


def _fsweep(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """fsweep in its own process: a crash inside a library (h5py on a full disk) shows as its exit code."""
    code = "import sys; from friction_sweep.cli import main; sys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *args], cwd=cwd, capture_output=True, text=True, check=False)


@pytest.fixture
def small_disk(tmp_path):
    """A tmpfs of a given size (root only; skipped where mounting is not allowed), unmounted after."""
    mounted = []

    def make(size: str) -> Path:
        d = tmp_path / f"fs{len(mounted)}"
        d.mkdir()
        res = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(d)], capture_output=True,
                             check=False)
        if res.returncode != 0:
            pytest.skip("mounting a small tmpfs is not allowed here")
        mounted.append(d)
        return d

    yield make
    for d in mounted:
        subprocess.run(["umount", str(d)], check=False)


@pytest.mark.parametrize("size, where", [("64k", "checkpoint"), ("600k", "result")])
@pytest.mark.slow
def test_a_full_disk_ends_in_one_line_keeping_finished_tiles(small_disk, size, where):
    d = small_disk(size)
    (d / "spec.yaml").write_text(WIDE)
    (d / "one.yaml").write_text(GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "[1.5]").replace("[0.1, 0.4]", "0.1"))
    assert _fsweep("run", "one.yaml", "-o", "out.h5", "-q", cwd=d).returncode == 0
    before = (d / "out.h5").read_bytes()
    res = _fsweep("run", "spec.yaml", "--overwrite", "-q", cwd=d)
    assert res.returncode == 1, res.stderr
    assert len(res.stderr.splitlines()) == 1 and "No space left on device" in res.stderr
    assert "--resume" in res.stderr and "Traceback" not in res.stderr
    assert (d / "out.h5").read_bytes() == before
    assert not [p for p in d.rglob("*") if p.name.endswith(".tmp")]
    assert not (d / ".out.h5.lock").exists()
    tiles = list((d / ".out.h5.partial").glob("tile-*.npz"))
    assert tiles if where == "result" else len(tiles) < 10


@pytest.mark.slow
def test_a_full_disk_while_checkpointing_keeps_what_was_finished(tmp_path, monkeypatch):
    """The same by fault injection, where no tmpfs can be mounted; then --resume finishes the run."""
    from friction_sweep.batch import checkpoint

    (tmp_path / "spec.yaml").write_text(WIDE)
    real, calls = checkpoint.np.savez, []

    def savez(fh, **arrays):
        calls.append(1)
        if len(calls) == 3:
            fh.write(b"partial")
            raise OSError(28, "No space left on device")
        real(fh, **arrays)

    monkeypatch.setattr(checkpoint.np, "savez", savez)
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["run", "spec.yaml", "-q", "--executor", "serial"])
    assert res.exit_code == 1 and res.output.count("\n") == 1, res.output
    assert "No space left on device" in res.output and "2 finished tiles are kept" in res.output
    assert sorted(p.name for p in (tmp_path / ".out.h5.partial").iterdir()) == [
        "manifest.json", "tile-00000.npz", "tile-00001.npz"]
    monkeypatch.setattr(checkpoint.np, "savez", real)
    res = CliRunner().invoke(main, ["run", "spec.yaml", "-q", "--resume"])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.h5", "spec.yaml"]


@pytest.mark.parametrize("mask, mode", [(0o022, 0o644), (0o027, 0o640), (0o077, 0o600)])
@pytest.mark.slow
def test_written_files_get_the_mode_the_umask_gives(tmp_path, mask, mode):
    (tmp_path / "spec.yaml").write_text(EVENT_LONG)
    old = os.umask(mask)
    try:
        _interrupted(tmp_path, EVENT_LONG)
        tile = tmp_path / ".out.h5.partial" / "tile-00000.npz"
        assert stat.S_IMODE(tile.stat().st_mode) == mode
        res = CliRunner().invoke(main, ["run", str(tmp_path / "spec.yaml"), "-o", str(tmp_path / "out.h5"), "-q",
                                        "--resume"])
    finally:
        os.umask(old)
    assert res.exit_code == 0, res.output
    assert stat.S_IMODE((tmp_path / "out.h5").stat().st_mode) == mode


def test_a_lock_that_cannot_be_opened_is_one_line(tmp_path, monkeypatch):
    from friction_sweep.batch import checkpoint

    real = os.open

    def denied(path, *a, **k):
        if str(path).endswith(".lock"):
            raise PermissionError(13, "Permission denied")
        return real(path, *a, **k)

    (tmp_path / "spec.yaml").write_text(GOOD)
    monkeypatch.setattr(checkpoint.os, "open", denied)
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["run", "spec.yaml", "-q"])
    assert res.exit_code == 2 and "cannot be opened (Permission denied)" in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]


@pytest.mark.slow
def test_the_estimate_counts_tiles_and_workers_honestly():
    from friction_sweep.batch.estimate import HUGE_SECONDS, estimate
    from friction_sweep.spec import parse_spec_text

    spec = parse_spec_text(GOOD)
    serial = [estimate(spec, jobs=j, executor="serial").seconds for j in (1, 8)]
    assert serial[0] == serial[1]  # one worker however many were asked for
    # 40 frequency ratios are two tiles: never more workers than tiles, nor than cores
    assert estimate(spec, jobs=8, executor="threads").workers == min(2, os.cpu_count() or 1)
    # 7.5 million frequency ratios of one force ratio: per-tile and per-frequency work (the theory's
    # S(r), written beside every simulation) dominate, so they cost far more than as many force ratios
    # at one frequency ratio
    tall = parse_spec_text(GOOD.replace("{start: 0.5, stop: 2.0, num: 40}",
                                        "{start: 0.5, stop: 2.0, step: 0.0000002}").replace("[0.1, 0.4]", "0.1"))
    wide = parse_spec_text(GOOD.replace("{start: 0.5, stop: 2.0, num: 40}", "1.25")
                           .replace("[0.1, 0.4]", "{start: 0.0, stop: 1.5, step: 0.0000002}"))
    assert tall.frequency_ratio.size == wide.force_ratio.size
    assert estimate(tall, jobs=2, executor="threads").seconds > 5 * estimate(wide, jobs=2, executor="threads").seconds
    assert estimate(tall, jobs=2, executor="threads").seconds < HUGE_SECONDS < estimate(tall, jobs=1, executor="serial").seconds


@pytest.mark.slow
def test_sigterm_ends_like_ctrl_c_keeping_finished_tiles(tmp_path):
    code = (
        "import os, signal, sys, time\n"
        "import friction_sweep.methods.event as e\n"
        "real, n = e.compute_tile, [0]\n"
        "def once(*a, **k):\n"
        "    n[0] += 1\n"
        "    if n[0] > 2:\n"
        "        os.kill(os.getpid(), signal.SIGTERM)\n"
        "        time.sleep(600)  # the third tile never finishes: the stop must not wait for it\n"
        "    return real(*a, **k)\n"
        "e.compute_tile = once\n"
        "from friction_sweep.cli import main\n"
        "sys.exit(main(['run', 'spec.yaml', '-q', '--executor', 'serial']))\n"
    )
    (tmp_path / "spec.yaml").write_text(EVENT_LONG)
    res = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert res.returncode == 143, res.stderr
    assert res.stderr.strip() == ("fsweep: error: terminated; no result was written; 2 finished tiles are kept "
                                  "in .out.h5.partial: rerun with --resume to continue")
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.h5.partial", "spec.yaml"]


@pytest.mark.parametrize("r, beta, settings", [
    (1.0, 0.1, {"steady_tol": 1e-6}),  # `steady_tol: 10` called this continuous
    (1.0, 0.1, {"stop_tol": 1e-10, "max_orbit_period": 1024}),
    (1.5, 0.1, {"work_budget": 10**8}),  # 2^63 overflowed into `unsettled`
    (1.5, 0.1, {"initial_displacement": 2.0, "initial_velocity": -2.0}),
    (0.3, 0.3, {"steady_tol": 1e-13, "stop_tol": 1e-15}),
    (0.5, 0.25, {"max_periods": 100_000, "shoot_after": 1_000_000}),
])
def test_settings_at_the_ends_of_their_ranges_give_the_default_answer(compiled, r, beta, settings):
    from friction_sweep.methods import event

    def solve(**knobs):
        return event.compute_tile("base", np.array([r]), np.array([beta]), ("transmissibility", "regime"),
                                  settings=knobs)

    ref, got = solve(), solve(**settings)
    assert got["regime"].item() == ref["regime"].item()
    np.testing.assert_allclose(got["transmissibility"], ref["transmissibility"], rtol=1e-5)


@pytest.mark.parametrize("r", [0.5, 2.0, 3.7])
def test_no_friction_from_any_start_is_the_forced_orbit(compiled, r):
    """beta = 0: nothing dissipates, so the steady state meant is the forced one, |X| = 1/|1 - r^2|,
    whatever the start (a start with velocity used to keep its free vibration forever)."""
    from friction_sweep.methods import event

    out = event.compute_tile("base", np.array([r]), np.array([0.0]), ("transmissibility", "regime"),
                             settings={"initial_displacement": 1.5, "initial_velocity": 2.0})
    exact = 1.0 / abs(1.0 - r * r)
    np.testing.assert_allclose(out["transmissibility"].item(), exact, rtol=1e-12)
    np.testing.assert_allclose(out["peak_transmissibility"].item(), exact, rtol=1e-12)


@pytest.mark.slow
def test_ctrl_c_under_dask_is_one_line(tmp_path):
    """Ctrl-C reaches the whole process group; the Dask workers used to print a traceback each."""
    import signal
    import time

    pytest.importorskip("distributed")
    (tmp_path / "spec.yaml").write_text(EVENT.replace("num: 40", "step: 0.0005").replace("[0.1, 0.4]",
                                                                                      "{start: 0, stop: 1, num: 41}"))
    code = "import sys; from friction_sweep.cli import main; sys.exit(main(sys.argv[1:]))"
    p = subprocess.Popen([sys.executable, "-c", code, "run", "spec.yaml", "-q", "--executor", "dask", "-j", "2"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    deadline = time.monotonic() + 120
    while not list((tmp_path / ".out.h5.partial").glob("tile-*.npz")) and time.monotonic() < deadline:
        time.sleep(0.1)
    os.killpg(p.pid, signal.SIGINT)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert len(err.splitlines()) == 1 and "finished tiles are kept" in err, err


@pytest.mark.parametrize("r, beta, static", [
    (0.5, 0.5, 1.0), pytest.param(0.3, 0.11, 1.5, marks=pytest.mark.nojit_slow), (0.8, 0.3, 1.5), (2.0, 0.6, 1.0)
])
def test_no_point_exceeds_its_work_budget_and_calls_itself_converged(compiled, r, beta, static):
    """The measurement replays are part of the point's budget (they used to get the whole budget again)."""
    from friction_sweep.kernels import steady
    from friction_sweep.methods import event

    def solve(budget):
        out = np.empty((1, steady.OUT_SIZE))
        A, rr, bk, bs, zeta = (np.array([x]) for x in (1.0, r, beta, beta * static, 0.0))
        settings = event.kernel_settings({"work_budget": budget})
        steady.solve_points(A, rr, bk, bs, zeta, np.array([0.0]), settings,
                            *event.newton_guess(A, rr, bk, bs, zeta, settings), out, None)
        return out[0]

    full = solve(5_000_000)
    needed = int(full[steady.OUT_WORK])
    for budget in (needed, needed - 1, needed // 2):
        got = solve(budget)
        assert got[steady.OUT_WORK] <= budget or got[steady.OUT_STEADY_STATE] == SteadyState.EVENT_BUDGET, budget
    assert solve(needed)[steady.OUT_STEADY_STATE] == full[steady.OUT_STEADY_STATE]


def test_a_port_that_accepts_and_stays_silent_is_no_scheduler(tmp_path, monkeypatch):
    """Dask's client would wait on it forever: the check waits for the scheduler's greeting instead."""
    import socket
    import threading

    from friction_sweep.batch import executors

    monkeypatch.setattr(executors, "CONNECT_TIMEOUT_S", 0.5)
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    accepted = []
    threading.Thread(target=lambda: accepted.append(server.accept()), daemon=True).start()
    (tmp_path / "spec.yaml").write_text(GOOD)
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["run", "spec.yaml", "--scheduler", address, "-q"])
    server.close()
    assert res.exit_code == 2 and "cannot reach the Dask scheduler" in res.output and "no answer" in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]
