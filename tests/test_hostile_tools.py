"""Hostile input to `fsweep validate-data` and `fsweep bench` (issue 14).

Bad data files, missing matplotlib, special files where an output goes and a disk that fills up
mid-way: each ends with one line `fsweep: error: ...`, exit 2 (bad input, refused before any
computation) or 1 (a failure while writing), no traceback, and no output written or changed.
The computations themselves are replaced by fakes here: these tests are about what the commands
do around them, and stay fast.
"""

import json
import os
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import ROOT, one_error_line, write_spec

from friction_sweep import validation
from friction_sweep.bench import workprecision as wp
from friction_sweep.cli import main
from friction_sweep.storage.outputs import refuse_special_output, write_all

GOOD = "force_ratio,frequency_ratio,phase_deg\n0.5741,0.6487,46.4635\n0.3920,1.2525,150.1044\n"


def fake_predict(table: pd.DataFrame) -> pd.DataFrame:
    """validation.predict's columns without the kernels: every method predicts the measurement."""
    out = table.copy()
    for method in validation.METHODS:
        out[f"{method}_regime"] = "continuous"
        for definition in validation.DEFINITIONS:
            out[f"{method}_{definition}_deg"] = table["phase_deg"]
            out[f"{method}_{definition}_error_deg"] = 0.0
    return out


def fake_bench(quick=False, methods=("event", "rk4", "paper"), log=print) -> xr.Dataset:
    """A dataset shaped like workprecision.run's, made in no time."""
    methods = list(methods)
    shape = (len(methods), 2, len(wp.REGIONS), len(wp.EXCITATIONS))
    settings = {m: wp.QUICK_SETTINGS[m][:2] for m in methods}
    labels = np.array([[wp.label(s) for s in settings[m]] + [""] * (2 - len(settings[m])) for m in methods])
    grid = np.arange(np.prod(shape), dtype=float).reshape(shape)
    dims = ("method", "setting", "region", "excitation")
    return xr.Dataset(
        {"error": (dims, 10.0 ** -(grid % 12)), "seconds_per_point": (dims, 1e-5 * (1 + grid)),
         "setting_label": (("method", "setting"), labels)},
        coords={"method": methods, "setting": np.arange(2), "region": list(wp.REGIONS),
                "excitation": list(wp.EXCITATIONS)},
        attrs={"settings": json.dumps(settings), "quick": int(quick)},
    )


def never(*args, **kwargs):
    raise AssertionError("computed although the command should have refused first")


def tree(folder: Path) -> dict:
    """Every file under `folder` (hidden and temporary ones included) with its content."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


# --- validate-data: bad data files ------------------------------------------------------------------

BAD_FILES = {
    # name: (bytes, the expected "FILE[:LINE]: reason" after the path)
    "binary": (bytes(range(256)) * 4, ":1: binary data"),
    "not_utf8": (GOOD.encode() + "0.1,1.5,12\n0.2,0.9,\xb0\n".encode("latin-1"), ":5: not UTF-8 text (byte 0xb0)"),
    "empty": (b"", ": empty file"),
    "blank": (b"\n  \n\r\n", ": empty file"),
    "only_comments": (b"# nothing here\n", ": no data rows"),
    "header_only": (b"force_ratio,frequency_ratio,phase_deg\n", ": no data rows"),
    "missing_column": (b"# c\nforce_ratio,frequency_ratio\n0.1,0.5\n", ":2: missing column(s) phase_deg"),
    "repeated_column": (b"force_ratio,frequency_ratio,phase_deg,phase_deg\n0.1,0.5,1,2\n", ":1: column(s) phase_deg"),
    "short_row": (GOOD.encode() + b"0.1,0.5\n", ":4: 2 fields, but the header (line 1) has 3"),
    "nan": (GOOD.encode() + b"0.1,NaN,12\n", ":4: frequency_ratio must be a finite number (got 'NaN')"),
    "inf": (GOOD.encode() + b"inf,1.5,12\n", ":4: force_ratio must be a finite number (got 'inf')"),
    "non_numeric": (GOOD.encode() + b"0.1,1.5,twelve\n", ":4: phase_deg must be a finite number (got 'twelve')"),
    "empty_cell": (GOOD.encode() + b"0.1,,12\n", ":4: frequency_ratio must be a finite number (got '')"),
    "negative_frequency": (GOOD.encode() + b"0.1,-1.5,12\n", ":4: frequency_ratio must be between 0.01 and 100 (got -1.5)"),
    "zero_frequency": (GOOD.encode() + b"0.1,0,12\n", ":4: frequency_ratio must be between 0.01 and 100 (got 0)"),
    "tiny_frequency": (GOOD.encode() + b"0.1,1e-6,12\n", ":4: frequency_ratio must be between 0.01 and 100 (got 1e-6)"),
    "negative_force": (GOOD.encode() + b"-0.1,1.5,12\n", ":4: force_ratio must be 0 or between 1e-12 and 1e+06 (got -0.1)"),
    # issue 28: numbers Python's float() reads but no CSV writer writes, and phases no rig measures
    "arabic_indic_digits": (GOOD.encode() + "0.1,\u0661.\u0664,12\n".encode(),
                            ":4: frequency_ratio must be a number in plain ASCII digits"),
    "fullwidth_digits": (GOOD.encode() + "0.1,1.5,\uff11\uff12\n".encode(), ":4: phase_deg must be a number in plain"),
    "underscore": (GOOD.encode() + b"0.1,1.5,1_4353\n", ":4: phase_deg must be a number in plain ASCII digits, such "
                   "as 1.4353 or -2.5e-3 (got '1_4353')"),
    "phase_999": (GOOD.encode() + b"0.1,1.5,999\n", ":4: phase_deg must be a phase lag in degrees within [-180, 360] "
                  "(got 999)"),
    "phase_-200": (GOOD.encode() + b"0.1,1.5,-200\n", ":4: phase_deg must be a phase lag in degrees within"),
}


@pytest.fixture
def no_kernels(monkeypatch):
    """Predictions that fail the test if reached (refusals come first), or fake ones."""
    monkeypatch.setattr(validation, "predict", never)


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_bad_data_files_are_one_line_refusals(name, tmp_path, no_kernels):
    content, reason = BAD_FILES[name]
    data = tmp_path / f"{name}.csv"
    data.write_bytes(content)
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["validate-data", "--data", str(data), "-o", str(out)])
    assert one_error_line(res, 2).startswith(f"fsweep: error: {data}{reason}")
    assert not out.exists()


def test_line_numbers_count_comment_and_blank_lines(tmp_path):
    data = tmp_path / "d.csv"
    data.write_text("# rig\n\n" + GOOD + "# between\n\n0.2,abc,3\n")
    with pytest.raises(validation.DataError, match=rf"^{data}:8: frequency_ratio must be a finite number"):
        validation.read_measurements(data)


def test_a_utf8_bom_and_crlf_line_ends_are_read(tmp_path):
    data = tmp_path / "d.csv"
    data.write_bytes(b"\xef\xbb\xbf" + GOOD.replace("\n", "\r\n").encode())
    table = validation.read_measurements(data)
    assert list(table.columns) == ["force_ratio", "frequency_ratio", "phase_deg"]
    assert table["phase_deg"].tolist() == [46.4635, 150.1044]


@pytest.mark.parametrize("kind", ["directory", "fifo", "missing"])
def test_data_that_is_not_a_regular_file_is_refused(kind, tmp_path, no_kernels):
    data = tmp_path / "data"
    if kind == "directory":
        data.mkdir()
    elif kind == "fifo":
        os.mkfifo(data)  # reading it would block forever
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["validate-data", "--data", str(data), "-o", str(out)])
    expected = {"directory": "is a directory", "fifo": "is a named pipe (FIFO)",
                "missing": "cannot read the measured data: No such file or directory"}[kind]
    assert one_error_line(res, 2) == f"fsweep: error: {data}: {expected}" + ("" if kind == "missing" else
                                                                             ", not a CSV file")
    assert not out.exists()


def test_missing_default_data_names_the_option(tmp_path, monkeypatch, no_kernels):
    monkeypatch.setattr(validation, "DEFAULT_DATA", tmp_path / "shared" / "data" / "absent.csv")
    res = CliRunner().invoke(main, ["validate-data", "-o", str(tmp_path / "out")])
    line = one_error_line(res, 2)
    assert "pass --data FILE" in line and str(tmp_path / "shared" / "data" / "absent.csv") in line
    assert not (tmp_path / "out").exists()


def test_the_shipped_data_are_the_projects_measurements():
    """An installed tool reads its own copy; it must stay the project's shared/data file, byte for byte."""
    shared = ROOT.parent / "shared" / "data" / "experiment_phase_fixed_wall.csv"
    if not shared.exists():
        pytest.skip(f"no project data at {shared} (not a checkout)")
    assert validation.DEFAULT_DATA.read_bytes() == shared.read_bytes()
    assert len(validation.read_measurements(validation.DEFAULT_DATA)) == 36


# --- validate-data and bench: matplotlib missing -------------------------------------------------------


def test_validate_data_without_matplotlib_refuses_before_computing(tmp_path, no_kernels, no_matplotlib):
    data = tmp_path / "d.csv"
    data.write_text(GOOD)
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["validate-data", "--data", str(data), "-o", str(out)])
    assert "pip install 'friction_sweep[figures]'" in one_error_line(res, 2)
    assert not out.exists()


def test_bench_without_matplotlib_refuses_before_computing(tmp_path, monkeypatch, no_matplotlib):
    monkeypatch.setattr(wp, "run", never)
    out = tmp_path / "bench" / "wp.h5"
    res = CliRunner().invoke(main, ["bench", "--quick", "-o", str(out)])
    assert "pip install 'friction_sweep[figures]'" in one_error_line(res, 2)
    assert not out.parent.exists()


# --- where outputs go ----------------------------------------------------------------------------------


def _device(path: Path) -> None:
    """A character device node like /dev/null's (1, 3), made in the test's own folder."""
    try:
        os.mknod(path, stat.S_IFCHR | 0o600, os.makedev(1, 3))
    except (PermissionError, OSError) as err:
        pytest.skip(f"cannot make a device node here: {err}")


def test_refuse_special_output(tmp_path):
    assert refuse_special_output(tmp_path / "new" / "deeper" / "x.h5") is None
    (tmp_path / "plain.h5").write_text("old")
    assert refuse_special_output(tmp_path / "plain.h5") is None
    assert refuse_special_output(tmp_path) == f"{tmp_path} is a directory, not a regular file"
    os.mkfifo(tmp_path / "fifo")
    assert refuse_special_output(tmp_path / "fifo") == f"{tmp_path / 'fifo'} is a named pipe (FIFO), not a regular file"
    # a link, even to a regular file: replacing it would replace the link, not the file
    (tmp_path / "link.h5").symlink_to(tmp_path / "plain.h5")
    reason = refuse_special_output(tmp_path / "link.h5")
    assert "never replaces links" in reason and str(tmp_path / "plain.h5") in reason
    (tmp_path / "dangling.h5").symlink_to(tmp_path / "nowhere.h5")
    assert "never replaces links" in refuse_special_output(tmp_path / "dangling.h5")
    # a parent that is a file, near or far
    assert refuse_special_output(tmp_path / "plain.h5" / "x.h5") == f"parent {tmp_path / 'plain.h5'} is a file, not a folder"
    assert refuse_special_output(tmp_path / "plain.h5" / "a" / "x.h5") == \
        f"parent {tmp_path / 'plain.h5'} is a file, not a folder"
    assert "is a named pipe (FIFO), not a folder" in refuse_special_output(tmp_path / "fifo" / "x.h5")
    # a link to a folder is a fine place to write into
    (tmp_path / "dirlink").symlink_to(tmp_path / "new", target_is_directory=True)
    (tmp_path / "new").mkdir()
    assert refuse_special_output(tmp_path / "dirlink" / "x.h5") is None


def test_refuse_special_output_device(tmp_path):
    _device(tmp_path / "null")
    assert refuse_special_output(tmp_path / "null") == f"{tmp_path / 'null'} is a character device, not a regular file"


@pytest.mark.parametrize("kind", ["directory", "fifo", "device", "symlink", "parent_file", "png_suffix"])
def test_bench_refuses_special_outputs_before_computing(kind, tmp_path, monkeypatch):
    monkeypatch.setattr(wp, "run", never)
    out = tmp_path / "wp.h5"
    if kind == "directory":
        out.mkdir()
    elif kind == "fifo":
        os.mkfifo(out)
    elif kind == "device":
        _device(out)
    elif kind == "symlink":
        (tmp_path / "real.h5").write_text("precious")
        out.symlink_to(tmp_path / "real.h5")
    elif kind == "parent_file":
        (tmp_path / "results").write_text("a file")
        out = tmp_path / "results" / "wp.h5"
    elif kind == "png_suffix":
        out = tmp_path / "wp.png"
    before = tree(tmp_path)
    res = CliRunner().invoke(main, ["bench", "--quick", "-o", str(out)])
    if kind == "directory":
        # click refuses it first (the option's dir_okay=False), as a usage error of several lines
        assert res.exit_code == 2 and "is a directory" in res.stderr and "Traceback" not in res.output
        assert tree(tmp_path) == before
        return
    line = one_error_line(res, 2)
    expected = {"directory": "is a directory", "fifo": "is a named pipe (FIFO)", "device": "is a character device",
                "symlink": "fsweep never replaces links", "parent_file": "is a file, not a folder",
                "png_suffix": "name it .nc"}[kind]
    assert expected in line
    if kind == "symlink":
        assert str(tmp_path / "real.h5") in line
    assert tree(tmp_path) == before
    assert stat.S_ISLNK(os.lstat(out).st_mode) if kind == "symlink" else True


@pytest.mark.parametrize("kind", ["file", "symlink", "fifo_inside"])
def test_validate_data_refuses_special_outputs_before_computing(kind, tmp_path, no_kernels):
    data = tmp_path / "d.csv"
    data.write_text(GOOD)
    out = tmp_path / "out"
    if kind == "file":
        out.write_text("a file")
        expected = f"parent {out} is a file, not a folder"
    elif kind == "symlink":
        out.mkdir()
        (tmp_path / "elsewhere.csv").write_text("precious")
        (out / "table.csv").symlink_to(tmp_path / "elsewhere.csv")
        expected = "fsweep never replaces links"
    else:
        out.mkdir()
        os.mkfifo(out / "table.md")
        expected = "is a named pipe (FIFO), not a regular file"
    before = tree(tmp_path)
    res = CliRunner().invoke(main, ["validate-data", "--data", str(data), "-o", str(out)])
    assert expected in one_error_line(res, 2)
    assert tree(tmp_path) == before


# --- writing: all or nothing ---------------------------------------------------------------------------


def test_bench_writes_all_its_outputs(tmp_path, monkeypatch):
    monkeypatch.setattr(wp, "run", fake_bench)
    out = tmp_path / "b" / "wp.h5"
    res = CliRunner().invoke(main, ["bench", "--quick", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert sorted(os.listdir(out.parent)) == ["wp.h5", "wp.md", "wp.png"]  # no staged or temporary files
    assert out.with_suffix(".png").read_bytes().startswith(b"\x89PNG")
    assert xr.open_dataset(out, engine="h5netcdf")["error"].shape == (3, 2, 3, 2)
    assert f"wrote {out}, {out.with_suffix('.png')}, {out.with_suffix('.md')}" in res.stdout


def test_write_all_changes_nothing_when_one_write_fails(tmp_path):
    (tmp_path / "a.txt").write_text("old a")

    def disk_full(tmp):
        Path(tmp).write_text("partial")
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space left"):
        write_all([(tmp_path / "a.txt", lambda tmp: Path(tmp).write_text("new a")),
                   (tmp_path / "sub" / "b.txt", disk_full)])
    assert tree(tmp_path) == {"a.txt": b"old a"}
    assert write_all([(tmp_path / "a.txt", lambda tmp: Path(tmp).write_text("new a"))]) == [tmp_path / "a.txt"]
    assert tree(tmp_path) == {"a.txt": b"new a"}


# A real full disk, by a file-size limit in a child process (writes past it fail with EFBIG, as
# with ENOSPC; Python ignores the SIGXFSZ signal). Which write it hits depends on the limit.
CHILD = """
import resource, sys
sys.path.insert(0, {tests!r})
import test_hostile_tools as t
from friction_sweep import validation
from friction_sweep.bench import workprecision as wp
from friction_sweep.cli import main
validation.predict, wp.run = t.fake_predict, t.fake_bench
resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit}))
main({args!r})
"""


def _run_child(args, limit):
    code = CHILD.format(tests=str(ROOT / "tests"), limit=limit, args=args)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          cwd=ROOT, timeout=300)


@pytest.mark.parametrize("limit", [1000, 20_000])
@pytest.mark.slow
def test_validate_data_on_a_full_disk_changes_nothing(tmp_path, limit):
    data = tmp_path / "d.csv"
    data.write_text(GOOD)
    out = tmp_path / "out"
    out.mkdir()
    (out / "table.csv").write_text("previous run\n")
    before = tree(out)
    proc = _run_child(["validate-data", "--data", str(data), "-o", str(out), "--overwrite"], limit)
    assert proc.returncode == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"fsweep: error: could not write into {out}: "), proc.stderr
    assert "no output was changed" in lines[0]
    assert tree(out) == before  # the old table kept; no new, staged or temporary file


@pytest.mark.parametrize("limit", [1000, 30_000])
@pytest.mark.slow
def test_bench_on_a_full_disk_changes_nothing(tmp_path, limit):
    out = tmp_path / "wp.h5"
    out.write_text("previous run\n")
    before = tree(tmp_path)
    proc = _run_child(["bench", "--quick", "-o", str(out), "--overwrite"], limit)
    assert proc.returncode == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = [line for line in proc.stderr.splitlines() if not line.startswith("estimate: ")]  # said before it runs
    assert len(lines) == 1 and lines[0].startswith(f"fsweep: error: could not write the benchmark's results ({out})")
    assert tree(tmp_path) == before


def test_dask_is_an_extra_named_where_it_is_missing(runner, tmp_path, monkeypatch):
    """Dask comes with `friction_sweep[dask]`; without it `--executor dask` is one line naming the extra, exit 2,
    and nothing is written."""
    monkeypatch.setitem(sys.modules, "distributed", None)
    spec = write_spec(tmp_path)
    for args in (["--executor", "dask"], ["--scheduler", "tcp://127.0.0.1:8786"]):
        res = runner.invoke(main, ["run", str(spec), "-o", str(tmp_path / "out.h5"), "-q", *args])
        assert res.exit_code == 2, res.output
        assert res.output.strip() == ("fsweep: error: --executor dask needs dask.distributed: "
                                      "pip install 'friction_sweep[dask]'")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]
