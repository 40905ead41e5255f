"""The one cube reader (friction_sweep.storage.cube.open_cube, behind fsweep info, check, plot and
fs.open_cube): it audits every cube it returns, and bounds what a file can make it load before xarray
reads a value (storage.bounds). Issue 28, classes 5, 11 and 18; the CLI's rows are in tests/test_hostile.py."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import hostile_cubes as hc
import numpy as np
import pytest
import xarray as xr

import friction_sweep as fs
from friction_sweep.storage import cube

SPEC = """\
scene: {excitation: base}
grid:
  frequency_ratio: {start: 0.5, stop: 2.0, num: 40}
  force_ratio: [0.1, 0.4]
method: theory
"""


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "spec.yaml").write_text(SPEC)
    return tmp_path


@pytest.mark.parametrize("setup, words", [
    (hc.value("regime", (0, 0), 9), "regime: 1 of 80 values are not valid regime codes"),
    (hc.value("transmissibility", (0, 0), -1.0), "transmissibility: 1 of 80 values lie outside the valid range"),
    (hc.value("peak_transmissibility", (1, 0), np.inf), "are infinite"),
    (hc.value("force_ratio", 1, np.nan), "force_ratio: 1 of 2 values are NaN"),
    (hc.rewritten(lambda ds: ds.assign(transmissibility=ds["transmissibility"].astype(str))), "holds strings"),
    (hc.declared(4000, 5000), "declares 20000000 values"),
    (hc.declared(2, 40), "stores 0 of their 640 bytes"),
    (hc.external("ext.bin"), "external file"),
    (hc.virtual, "virtual dataset"),
], ids=["regime 9", "T -1", "inf", "NaN coordinate", "string variable", "too large", "unwritten", "external",
        "virtual"])
def test_the_api_refuses_what_info_refuses(folder, setup, words):
    setup(folder)
    with pytest.raises(fs.FsweepError, match=words):
        fs.open_cube(folder / hc.CUBE)


def test_every_audit_problem_travels_with_the_refusal(folder):
    hc.edited(lambda f: (f["regime"].__setitem__((0, 0), 9), f["phase"].__setitem__((0, 0), -1e9)))(folder)
    with pytest.raises(cube.UnsoundCube) as err:
        cube.open_cube(folder / hc.CUBE)
    assert sorted(p.variable for p in err.value.problems) == ["phase", "regime"]
    assert "and 1 more problems" in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("path", [3, None, b"\0".decode() + "x.h5"], ids=["int", "None", "NUL"])
def test_a_path_that_names_no_file_is_a_refusal(path):
    with pytest.raises(fs.FsweepError):
        fs.open_cube(path)


def test_sound_cubes_open_compressed_and_with_time_histories(tmp_path):
    """What the bounds must let through: every cube a run writes (here one with histories, whose dims have
    no coordinates), and the same rewritten compressed by xarray."""
    from test_audit import make_cube

    ds = make_cube("event", effects={"static_friction_ratio": 1.5}, histories=True)
    ds.attrs["friction_sweep_version"] = "test"
    cube.write_atomic(ds, tmp_path / "plain.h5", overwrite=False)
    back = cube.open_cube(tmp_path / "plain.h5")
    xr.testing.assert_identical(back, ds)
    ds.to_netcdf(tmp_path / "zipped.h5", engine="h5netcdf",
                 encoding={name: {"zlib": True, "complevel": 9} for name in ds.data_vars})
    xr.testing.assert_identical(cube.open_cube(tmp_path / "zipped.h5"), ds)


def _info(path: Path, limit_bytes: int | None = None, timeout: float = 120) -> subprocess.CompletedProcess:
    """fsweep info in its own process, its address space limited to `limit_bytes`."""
    code = ("import resource, sys\n"
            "if len(sys.argv) > 2:\n"
            "    n = int(sys.argv[2]); resource.setrlimit(resource.RLIMIT_AS, (n, n))\n"
            "from friction_sweep.cli import main\n"
            "main(['info', sys.argv[1]])\n")
    args = [sys.executable, "-c", code, str(path)] + ([str(limit_bytes)] if limit_bytes else [])
    return subprocess.run(args, capture_output=True, text=True, timeout=timeout, check=False, cwd=path.parent)


@pytest.mark.slow
def test_a_file_declaring_gigabytes_is_refused_within_a_small_memory_limit(folder):
    """Issue 28: a 249 kB file declaring three 10000 x 20000 variables took 5.6 GB. With the address space
    capped at 2 GiB (the interpreter and its libraries take well under one) it is refused, not loaded."""
    hc.declared(10000, 20000)(folder)
    path = folder / hc.CUBE
    assert path.stat().st_size < 300_000
    res = _info(path, limit_bytes=2 * 2**30)
    assert res.returncode == 2, res.stderr
    assert res.stderr.count("\n") == 1 and "declares 200000000 values (10000 x 20000)" in res.stderr


def test_a_fifo_as_external_storage_does_not_hang_info(folder):
    """Reading it would wait for a writer forever: the reader refuses external storage before reading."""
    hc.external("pipe", fifo=True)(folder)
    res = _info(folder / hc.CUBE, timeout=60)
    assert res.returncode == 2 and "keeps its values in an external file ('pipe')" in res.stderr, res.stderr

