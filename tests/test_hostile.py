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

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir

from friction_sweep.cli import main
from friction_sweep.codes import SteadyState

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


def _interrupted(d: Path, spec: str = EVENT) -> None:
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
    subprocess.run([sys.executable, "-c", code], cwd=d, capture_output=True, check=False)
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
         words=("control characters",)),
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
]


# cases whose set-up interrupts a real event run in a child process (seconds each), and the deepest YAML
SLOW_CASES = {"bad manifest.json", "truncated tile", "checkpoint of another sweep", "lock is a symlink to a victim",
              "a folder named like a tile", "a tile of strings", "a tile of regime 1e300", "5000-deep list"}


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
        res = CliRunner().invoke(main, args)
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
        "import os, signal, sys\n"
        "import friction_sweep.methods.event as e\n"
        "real, n = e.compute_tile, [0]\n"
        "def once(*a, **k):\n"
        "    n[0] += 1\n"
        "    if n[0] > 2:\n"
        "        os.kill(os.getpid(), signal.SIGTERM)\n"
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
                            *event.newton_guess(A, rr, bk, bs, zeta, settings), out)
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
