"""The one cube reader (friction_sweep.storage.cube.open_cube, behind fsweep info, check, plot and
fs.open_cube): it audits every cube it returns, and bounds what a file can make it load before xarray
reads a value (storage.bounds). Issue 28, classes 5, 11 and 18; the CLI's rows are in tests/test_hostile.py."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import hostile_cubes as hc
import numpy as np
import pytest
import xarray as xr

import friction_sweep as fs
from friction_sweep.storage import cube, provenance

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
    ds.attrs.update(provenance.attributes(spec_text="", spec_path="s.yaml", excitation="base", method="event",
                                          settings={"effects": {"static_friction_ratio": 1.5}}))
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



# ---- issue 28, round 2: cube readers and check ------------------------------------------------------------

DEEP = "[" * 100_000 + "]" * 100_000


@pytest.mark.parametrize("key, text, words", [
    ("method_settings", DEEP, "method_settings holds 200000 characters"),
    ("method_settings", "[" * 1000 + "]" * 1000, "method_settings nests deeper than"),
    ("method_settings", '{"a": ' * 20 + "1" + "}" * 20, "method_settings nests deeper than"),
    ("physical_system", DEEP, "physical_system holds 200000 characters"),
    ("accuracy_choice", "[" * 500 + "]" * 500, "accuracy_choice nests deeper than"),
    ("excitation", "\x1b]0;pwn\x07", "attribute excitation '\\x1b]0;pwn\\x07' is not one of"),
    ("method", "bogus", "attribute method 'bogus' is not a method of the catalogue"),
    ("method_settings", "[]", "method_settings is not a JSON object"),
    ("method_settings", "null", "method_settings is not a JSON object"),
    ("method_settings", "{", "method_settings is not JSON"),
    ("method_settings", '{"effects": {}, "x": NaN}', "method_settings is not JSON: NaN"),
    ("method_settings", '{"effects": "x"}', "effects is not a JSON object"),
    ("method_settings", '{"effects": {"viscous_damping": 0.1}}', "effect viscous_damping: method theory does not"),
    ("method_settings", '{"effects": {}, "steady_tol": 1e-10}', "steady_tol is not a setting of method theory"),
    ("method_settings", '{"effects": {"friction_heat": 1}}', "friction_heat is not an effect of the catalogue"),
    ("physical_system", "[1]", "physical_system is not a JSON object"),
], ids=["deep long", "deep list", "deep object", "deep physical", "deep accuracy", "escape excitation", "bogus method",
        "settings list", "settings null", "settings broken", "settings NaN", "effects text", "effect of another method",
        "setting of another method", "unknown effect", "physical list"])
def test_every_reader_refuses_a_bad_provenance_attribute(folder, key, text, words):
    """Issue 28 round 2, finding 1 and 2: the provenance a reader relies on is read by one bounded reader
    (storage.attributes) and audited by open_cube, so fs.open_cube, info, check and plot refuse alike (exit
    2, one line; a JSON nested 100000 deep was a RecursionError traceback from check and plot)."""
    from click.testing import CliRunner

    from friction_sweep.cli import main

    hc.with_attribute(key, text)(folder)
    path = folder / hc.CUBE
    with pytest.raises(fs.FsweepError, match=re.escape(words)):
        fs.open_cube(path)
    for command in (["info"], ["check"], ["plot", "-o", str(folder / "c.png")]):
        res = CliRunner().invoke(main, [*command, str(path)])
        assert res.exit_code == 2, (command, res.output)
        assert res.stderr.count("\n") == 1 and words in res.stderr and "Traceback" not in res.output, res.stderr
    assert not (folder / "c.png").exists()


@pytest.mark.parametrize("settings, words", [
    ({"steady_tol": -1}, "steady_tol is not a number in [1e-13, 1e-06]: -1"),
    ({"max_periods": 2.5}, "max_periods is not an integer in"),
    ({"starts": True}, "starts is not an integer"),
    ({"sweep": "sideways"}, "sweep is not one of up, down"),
    ({"effects": {"viscous_damping": -0.01}}, "effect viscous_damping is not a number in 0 or [1e-06, 1): -0.01"),
    ({"effects": {"viscous_damping": {"ratio": 0.1, "to": "ceiling"}}}, "effect viscous_damping is not {ratio, to"),
    ({"effects": {"static_friction_ratio": 0.5}}, "effect static_friction_ratio is not a number in [1, 100]"),
    ({"effects": {"contact_stiffness": "stiff"}}, "effect contact_stiffness is not a number"),
], ids=["steady_tol negative", "periods not whole", "starts bool", "sweep direction", "damping negative",
        "damping place", "static below 1", "contact text"])
def test_method_settings_outside_the_catalogue_are_refused(folder, settings, words):
    """A simulation's settings and effects as the catalogue bounds them (a negative damping passed the
    reader and failed `check` with exit 1: it is not a sound cube, exit 2)."""
    def edit(f):
        f.attrs["method"] = "event"
        f.attrs["method_settings"] = json.dumps({"effects": {}, **settings})

    hc.edited(edit)(folder)
    with pytest.raises(cube.UnsoundCube, match=re.escape(words)):
        cube.open_cube(folder / hc.CUBE)


def test_a_compressed_bomb_is_refused_before_it_expands(folder):
    """Finding 4: zlib-compressed constant variables (16 MB each in a file of under 300 kB) made info
    load hundreds of times the file's size; compressed variables expanding beyond MAX_COMPRESSION times the
    file's size are refused on its metadata."""
    from friction_sweep.storage import bounds

    hc.compressed(1000, 2000)(folder)
    path = folder / hc.CUBE
    assert path.stat().st_size < 300_000
    with pytest.raises(fs.FsweepError, match=r"compressed variables expand to 48000000 bytes, \d+ times the file's "
                       rf"\d+; fsweep reads compressed cubes up to {bounds.MAX_COMPRESSION} times their size"):
        fs.open_cube(path)


def test_an_ordinarily_compressed_cube_still_opens(tmp_path):
    """What nccopy -d9 makes of a real cube's numbers (a grid's varied floats) stays well inside the bound."""
    from test_audit import make_cube

    ds = make_cube("theory", r=np.linspace(0.2, 3.0, 100), beta=np.linspace(0.0, 1.2, 30))
    ds.attrs.update(provenance.attributes(spec_text="", spec_path="s.yaml", excitation="base", method="theory",
                                          settings={"effects": {}}))
    ds.to_netcdf(tmp_path / "zipped.h5", engine="h5netcdf",
                 encoding={name: {"zlib": True, "complevel": 9} for name in ds.data_vars})
    xr.testing.assert_identical(cube.open_cube(tmp_path / "zipped.h5"), ds)
