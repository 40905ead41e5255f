"""Property tests of hostile specs (issue 14): specs generated from the schema, valid and mutated, and
random bytes and text as spec files.

For every generated spec, `fsweep validate` and `fsweep run --yes -q --overwrite` each exit 0 or 2,
never with a traceback; a run that exits 2 leaves nothing but the spec in its folder; a run that
exits 0 writes one cube with the spec's grid sizes and no temporary file; `validate` exits 0 exactly
when `run` does; `validate` writes nothing. Grids are kept tiny (event: at most 4 points; rk4 and
auto: 2; `paper` is never run) so that eighty examples run in about 15 s. Mutations: a key dropped,
an unknown key added, a value replaced by a wrong type, NaN, a huge integer, a nested list, a value
just past a bound, another method, or a raw YAML scalar (tags, timestamps, complex keys) in the text.
"""

from __future__ import annotations

import json
import math
import tempfile
from io import StringIO
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import in_dir
from hypothesis import HealthCheck, assume, event, example, given, note, settings
from hypothesis import strategies as st
from ruamel.yaml import YAML

from friction_sweep import catalogue
from friction_sweep.catalogue import DEFAULT_OUTPUTS, EXCITATIONS, Setting
from friction_sweep.cli import main
from friction_sweep.spec import SpecError, parse_spec_text
from friction_sweep.spec.grid import FORCE_RATIO_MAX, FREQUENCY_RATIO_RANGE, MAX_POINTS

R_LO, R_HI = FREQUENCY_RATIO_RANGE
SPEC = "spec.yaml"
#: the most grid points a generated (possibly mutated) spec may have, so that runs stay cheap
MAX_THEORY_POINTS = 60
MAX_SIMULATED_POINTS = 8

PROPERTY = settings(
    max_examples=80,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)


# ---- valid specs, built from the schema -----------------------------------------------------------


def _up(x: float) -> float:
    return math.nextafter(x, math.inf)


def _down(x: float) -> float:
    return math.nextafter(x, -math.inf)


def _values(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Numbers in [lo, hi]: round ones, the bounds themselves, and any float between."""
    return st.one_of(
        st.sampled_from([lo, hi]),
        st.floats(lo, hi, allow_nan=False, allow_infinity=False),
        st.integers(math.ceil(lo), math.floor(hi)),
        st.integers(math.ceil(lo * 100), math.floor(hi * 100)).map(lambda i: i / 100),
    )


@st.composite
def _axis(draw, lo: float, hi: float, max_size: int, step_form: bool) -> tuple[Any, int | None]:
    """One grid axis and its size (None where the package's step lattice decides it)."""
    values = _values(lo, hi)
    kind = draw(st.sampled_from(["number", "list", "range", "step"] if step_form else ["number", "list", "range"]))
    if kind == "number":
        return draw(values), 1
    if kind == "list":
        xs = sorted(set(float(x) for x in draw(st.lists(values, min_size=1, max_size=max_size))))
        # integers stay integers in the file: YAML `1` and `1.0` must both be accepted
        xs = [int(x) if x.is_integer() and draw(st.booleans()) else x for x in xs]
        return xs, len(xs)
    a, b = sorted((draw(values), draw(values)))
    if max_size < 2:
        b = a
    if kind == "range":
        num = 1 if a == b else draw(st.integers(2, max_size))
        return {"start": a, "stop": b, "num": num}, num
    span = b - a
    step = draw(st.floats(span / (max_size - 1), max(span, 1.0), allow_nan=False, allow_infinity=False,
                          exclude_min=False)) if span > 0 else draw(st.floats(1e-6, 10.0))
    assume(step > 0)
    return {"start": a, "stop": b, "step": step}, None


def _in_range(s: Setting, cheap_high: float | None = None) -> st.SearchStrategy:
    """A value a knob accepts, kept cheap: budgets and period counts are drawn low."""
    high = s.high if cheap_high is None else min(s.high, cheap_high)
    if s.kind == "int":
        return st.integers(int(s.low), int(high))
    return st.one_of(st.just(high), st.floats(s.low, high, allow_nan=False, allow_infinity=False))


def _outside(s: Setting) -> list:
    """Values a knob refuses: just past each bound, and of the wrong type."""
    if s.kind == "int":
        wrong = [int(s.low) - 1, int(s.high) + 1, float(s.low) + 0.5, 10**30, True, "1"]
    else:
        wrong = [_up(s.high), math.nan, math.inf, "1e-3", False]
        wrong.append(_down(s.low))
    return wrong


#: cheap upper ends for the knobs whose cost grows with them
CHEAP = {"max_periods": 3000, "max_orbit_period": 300, "work_budget": 5_000_000, "shoot_after": 200,
         "shoot_every": 200, "steps_per_period": 512}
#: the methods generated, by weight; `paper` takes minutes a point and is never run (see _cheap)
METHODS = ["theory"] * 6 + ["event"] * 3 + ["rk4", "auto"]
SIMULATED = ("event", "rk4", "auto")


@st.composite
def _settings(draw, method: str, exclude: set[str]) -> dict:
    """Knobs of the method (theory: of event, which theory has none of), mostly in range."""
    own = catalogue.METHODS[method].settings or catalogue.METHODS["event"].settings
    known = {k: v for k, v in own.items() if k not in exclude}
    out = {}
    for key in draw(st.lists(st.sampled_from(sorted(known)), max_size=3, unique=True)):
        s = known[key]
        if method != "theory" and draw(st.integers(0, 3)) > 0:
            out[key] = draw(_in_range(s, CHEAP.get(key)))
        else:  # out of range, of the wrong type, or (theory) a knob the method does not have
            out[key] = draw(st.sampled_from(_outside(s) + [draw(_in_range(s, CHEAP.get(key)))]))
    if draw(st.integers(0, 20)) == 13:
        out["no_such_knob"] = 1
    return out


def _history(draw) -> dict:
    th: dict[str, Any] = {"points": draw(st.lists(st.tuples(st.floats(0.3, 4.0), st.floats(0.0, 1.5)).map(list),
                                                  min_size=1, max_size=2))}
    if draw(st.booleans()):
        th["samples_per_period"] = draw(st.integers(8, 64))
    return th


@st.composite
def valid_specs(draw) -> tuple[dict, tuple[int | None, int | None]]:
    """A spec as a dict, and its (frequency, force) axis sizes. Mostly valid: knobs are sometimes out
    of range, and one spec in eight combines fields that exclude each other."""
    method = draw(st.sampled_from(METHODS))
    simulated = method in SIMULATED
    if simulated:  # at most 4 points (rk4, auto: 2), away from the quasi-static corner
        n = 2 if method == "event" else 1
        freq, nf = draw(_axis(0.2, 5.0, n + (method != "event"), step_form=False))
        force, nb = draw(_axis(0.0, 2.0, n, step_form=False))
    else:
        freq, nf = draw(_axis(R_LO, R_HI, 5, step_form=True))
        force, nb = draw(_axis(0.0, 10.0, 5, step_form=True))
    spec: dict[str, Any] = {
        "scene": {"excitation": draw(st.sampled_from(EXCITATIONS))},
        "grid": {"frequency_ratio": freq, "force_ratio": force},
    }
    if method != "theory" or draw(st.booleans()):
        spec["method"] = method
    if draw(st.booleans()):
        spec["outputs"] = draw(st.permutations(DEFAULT_OUTPUTS).flatmap(
            lambda p: st.integers(1, len(p)).map(lambda n: list(p[:n]))))
    record = catalogue.METHODS[method]
    sweep = record.sweep and draw(st.integers(0, 4)) == 0
    accuracy = bool(record.accuracy_knobs) and not sweep and draw(st.integers(0, 5)) == 0
    if record.effects and draw(st.booleans()):
        effects = {}
        if draw(st.booleans()):
            effects["viscous_damping"] = draw(st.one_of(st.just(0.0), st.floats(0, 0.9)))
            if draw(st.booleans()):  # with its place, one the excitation allows
                places = catalogue.EFFECTS["viscous_damping"].places[spec["scene"]["excitation"]]
                effects["viscous_damping"] = {"ratio": effects["viscous_damping"],
                                              "to": draw(st.sampled_from(list(places)))}
        if draw(st.booleans()):
            effects["static_friction_ratio"] = draw(st.one_of(st.just(1), st.floats(1, 3)))
        spec["scene"]["effects"] = effects or None
    if sweep:
        spec["sweep"] = {"direction": draw(st.sampled_from(["up", "down"]))}
    if accuracy:
        spec["accuracy"] = draw(st.sampled_from([0.5, 1e-2, 1e-4, 1e-6, 1e-9, 1e-14]))
    if record.time_history and not sweep and draw(st.integers(0, 4)) == 0:
        spec["outputs"] = [*spec.get("outputs", DEFAULT_OUTPUTS), "time_history"]
        spec["time_history"] = _history(draw)
    if draw(st.integers(0, 2)) == 0:
        exclude = ({"starts"} if sweep else set()) | (set(record.accuracy_knobs) if accuracy else set())
        spec["settings"] = draw(_settings(method, exclude))
    if draw(st.integers(0, 7)) == 5:  # fields that exclude each other, or that the method lacks
        conflict = draw(st.sampled_from(["sweep", "accuracy", "effects", "history", "history_unlisted",
                                         "history_missing", "starts"]))
        if conflict == "sweep":
            spec["sweep"] = {"direction": "up"}
        elif conflict == "accuracy":
            spec["accuracy"] = 1e-3
            spec.setdefault("settings", {})["steady_tol"] = 1e-8
        elif conflict == "effects":
            spec["scene"]["effects"] = {"viscous_damping": 0.1}
        elif conflict == "history":
            spec["outputs"] = ["regime", "time_history"]
            spec["time_history"] = _history(draw)
        elif conflict == "history_unlisted":
            spec["time_history"] = _history(draw)
        elif conflict == "history_missing":
            spec["outputs"] = ["time_history"]
        else:
            spec["sweep"] = {"direction": "down"}
            spec.setdefault("settings", {})["starts"] = 1
    spec["output"] = "out.h5"
    return spec, (nf, nb)


# ---- mutations -------------------------------------------------------------------------------------

#: keys no model has; the union tags of grid axes among them (a spec may hold any key)
UNKNOWN_KEYS = ["bogus", "Scene", "method ", "frequency-ratio", "1", "<range>", "<number>", "<list>"]

#: written into the YAML text where a mutation put the placeholder RAW
RAW = "RAWYAMLSCALAR"
RAW_YAML = [
    "2001-12-14", "2001-12-14t21:59:43.10-05:00", "!!timestamp 2001-12-14", "!!binary aGVsbG8=", "!!set {a, b}",
    "!!omap [a: 1]", "0x1F", "0o17", "1_000", ".NaN", "-.Inf", "~", "yes", "1:20", "!!float 1", '!!int "3"',
    "!!str 1", "!custom 1", "!!python/object:os.system ls", "*undefined", "{[1, 2]: 3}", "{? [1, 2] : 3}",
    "{{a: 1}: 2}", "[1, 2, ]", '!!null ""', '!!bool "true"', "!!map {}", "!!seq []", "!!float .nan",
    "!!int 1e3", "!!float 1e400", "1e400", "-0.0", "0.01e0", "&a [*a]", "'\\u0000'", '"\\0"', "!!float 0x10",
]

HOSTILE = [
    "abc", "0.3", "", " ", True, False, None, math.nan, math.inf, -math.inf, 10**400, 2**63, -1, -1e-300,
    1e300, -1e300, 0, 0.0, [[1.0]], [], {}, {"start": 1}, "1e400", "\x00", "\u202e", [None],
]


def _bounds(path: tuple) -> list:
    """Values just outside the bounds of the field at `path`."""
    last = path[-1]
    knobs = {k: v for m in catalogue.METHODS.values() for k, v in m.settings.items()}
    if "settings" in path and isinstance(last, str) and last in knobs:
        return _outside(knobs[last])
    if last == "num":
        return [0, MAX_POINTS + 1, 1.0]
    if last == "step":
        return [0.0, -1.0, 5e-324]
    if "frequency_ratio" in path:
        return [_down(R_LO), _up(R_HI), 0.0, -0.0, 1e-300]
    if "force_ratio" in path:
        return [-5e-324, _up(FORCE_RATIO_MAX), -1.0]
    if last == "viscous_damping" or (last == "ratio" and "viscous_damping" in path):
        return [1.0, _down(0.0)]
    if last == "to":  # a place no excitation has, or one another excitation has
        return ["wall", "ground", "base"]
    if last == "static_friction_ratio":
        return [_down(1.0), 0.0]
    if last == "accuracy":
        return [0.0, 1.0, 0]
    if last == "samples_per_period":
        return [7, 100_001, 8.0]
    if "points" in path and isinstance(last, int) and len(path) >= 4:  # [r, beta] of a history point
        return [_down(R_LO), _up(R_HI)] if last == 0 else [-5e-324, _up(FORCE_RATIO_MAX)]
    return [-1, 0]


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    out = []
    if isinstance(node, dict):
        for k, v in node.items():
            out.append(prefix + (k,))
            out += _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out.append(prefix + (i,))
            out += _paths(v, prefix + (i,))
    return out


def _parent(spec: dict, path: tuple) -> Any:
    node = spec
    for p in path[:-1]:
        node = node[p]
    return node


@st.composite
def mutate(draw, spec: dict) -> tuple[dict, list[str]]:
    """Apply one to three mutations; returns the mutated spec and what was done."""
    spec = json.loads(json.dumps(spec))  # a deep copy (the generated spec has no NaN or huge ints)
    done = []
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(spec)
        if not paths:
            break
        op = draw(st.sampled_from(["drop", "unknown", "replace", "replace", "outside", "outside", "method", "raw"]))
        if op == "raw":  # a YAML scalar written into the text itself (tags, timestamps, complex keys)
            if draw(st.booleans()):
                path = draw(st.sampled_from(paths))
                _parent(spec, path)[path[-1]] = RAW
                done.append(f"raw YAML value at {path}")
            else:
                where = draw(st.sampled_from([()] + [p for p in paths if isinstance(_get(spec, p), dict)]))
                _get(spec, where)[RAW] = 1
                done.append(f"raw YAML key in {where}")
            continue
        if op == "method":  # another method's fields and knobs, on the same grid
            spec["method"] = draw(st.sampled_from(["theory", "event", "rk4", "auto", "paper"]))
            done.append(f"method = {spec['method']!r}")
            continue
        if op == "unknown":
            dicts = [()] + [p for p in paths if isinstance(_get(spec, p), dict)]
            where = draw(st.sampled_from(dicts))
            key = draw(st.sampled_from(UNKNOWN_KEYS))
            _get(spec, where)[key] = draw(st.sampled_from([1, None, "x"]))
            done.append(f"unknown key {key!r} at {where}")
            continue
        path = draw(st.sampled_from(paths))
        parent = _parent(spec, path)
        if op == "drop":
            del parent[path[-1]]
            done.append(f"dropped {path}")
            continue
        value = draw(st.sampled_from(HOSTILE if op == "replace" else _bounds(path)))
        parent[path[-1]] = json.loads(json.dumps(value)) if isinstance(value, (list, dict)) else value
        done.append(f"{path} = {value!r}")
    return spec, done


def _get(spec: dict, path: tuple) -> Any:
    node = spec
    for p in path:
        node = node[p]
    return node


def _yaml(spec: dict, flow: bool) -> str:
    yaml = YAML(typ="safe", pure=True)
    yaml.default_flow_style = flow
    buf = StringIO()
    yaml.dump(spec, buf)
    return buf.getvalue()


def _serialise(spec: dict, fmt: str) -> str:
    if fmt == "json":  # JSON is YAML (NaN and Infinity are strings to YAML 1.2)
        return json.dumps(spec)
    return _yaml(spec, flow=fmt == "flow")


# ---- running the CLI -------------------------------------------------------------------------------


def _invoke(d: Path, *args: str):
    with in_dir(d):
        return CliRunner().invoke(main, list(args))


def _no_traceback(res, what: str) -> None:
    assert res.exception is None or isinstance(res.exception, SystemExit), (
        f"{what}: traceback: {res.exception!r}\n{res.output}")
    assert "Traceback" not in res.output, f"{what}: {res.output}"
    assert res.exit_code in (0, 2), f"{what}: exit {res.exit_code}: {res.output}"


def _files(d: Path) -> list[str]:
    """Everything in the folder: files, links and folders (an empty folder left behind counts)."""
    return sorted(str(p.relative_to(d)) for p in d.rglob("*"))


def _sizes(text: str) -> tuple[int, int] | None:
    """The grid sizes the package reads from `text`, or None where it refuses the spec (or fails:
    the CLI's assertions report that)."""
    try:
        s = parse_spec_text(text)
    except SpecError:
        return None
    except Exception:  # reported by the CLI assertions below, with the output
        return None
    return s.frequency_ratio.size, s.force_ratio.size


def _cheap(text: str) -> bool:
    """Whether a spec costs little to run: refused ones do; accepted ones have a few points (and are
    not `paper`, which simulates from rest with ode45 for minutes a point)."""
    try:
        s = parse_spec_text(text)
    except Exception:  # refused (or failing: the CLI's assertions report that)
        return True
    points = s.frequency_ratio.size * s.force_ratio.size
    return s.method != "paper" and points <= (MAX_THEORY_POINTS if s.method == "theory" else MAX_SIMULATED_POINTS)


@st.composite
def spec_texts(draw) -> tuple[str, dict, tuple, list[str]]:
    spec, sizes = draw(valid_specs())
    done: list[str] = []
    if draw(st.integers(0, 2)) > 0:  # two thirds mutated
        spec, done = draw(mutate(spec))
    raw = any(m.startswith("raw") for m in done)
    fmt = draw(st.sampled_from(["block", "flow"] if raw else ["block", "flow", "json"]))
    text = _serialise(spec, fmt)
    if raw:
        scalar = draw(st.sampled_from(RAW_YAML))
        done.append(f"raw = {scalar}")
        text = text.replace(RAW, scalar)
    return text, spec, sizes, done


#: found by this property: an unknown top-level key named like an axis tag crashed the error report
TAG_KEY = ("'<range>': 1\ngrid:\n  force_ratio: 0.0\n  frequency_ratio: 0.01\noutput: out.h5\nscene:\n"
           "  excitation: force\n")


@PROPERTY
@given(case=spec_texts())
@example(case=(TAG_KEY, {"scene": {"excitation": "force"}}, (1, 1), ["unknown key '<range>' at ()"]))
@pytest.mark.slow
def test_validate_and_run_agree_exit_0_or_2_and_leave_nothing_on_refusal(case, compiled) -> None:
    text, spec, sizes, mutations = case
    note(f"mutations: {mutations}")
    note(f"spec text:\n{text}")
    assume(_cheap(text))
    with tempfile.TemporaryDirectory(prefix="fsweep-prop-") as tmp:
        d = Path(tmp)
        (d / SPEC).write_text(text)

        val = _invoke(d, "validate", SPEC)
        note(f"validate: exit {val.exit_code}\n{val.output}")
        _no_traceback(val, "validate")
        assert _files(d) == [SPEC], f"validate wrote {_files(d)}"

        res = _invoke(d, "run", SPEC, "--yes", "-q", "--overwrite")
        note(f"run: exit {res.exit_code}\n{res.output}")
        _no_traceback(res, "run")
        event(f"method {str(spec.get('method', 'theory'))[:8]}, mutated {bool(mutations)}, exit {res.exit_code}")
        assert val.exit_code == res.exit_code, (
            f"validate exit {val.exit_code} but run exit {res.exit_code}\nvalidate: {val.output}\nrun: {res.output}")

        files = _files(d)
        hidden = [p for p in d.rglob("*") if p.name.startswith(".") or p.name.endswith((".tmp", ".probe", ".staged"))]
        assert not hidden, f"left over: {hidden}"
        if res.exit_code == 2:
            assert files == [SPEC], f"run exited 2 but left {files}: {res.output}"
            return

        cubes = [f for f in files if f != SPEC and (d / f).is_file()]
        assert len(cubes) == 1, f"run exited 0 with files {files}"
        folders = {str(p) for p in Path(cubes[0]).parents if str(p) != "."}
        assert set(files) == {SPEC, cubes[0], *folders}, f"run exited 0 with files {files}"
        expected = _sizes(text)
        assert expected is not None, "run exited 0 on a spec the package refuses"
        if not mutations:  # the generator's own sizes, where it knows them
            for want, got in zip(sizes, expected, strict=True):
                assert want is None or want == got, (sizes, expected)
        with xr.open_dataset(d / cubes[0], engine="h5netcdf") as ds:
            assert ds.sizes["frequency_ratio"] == expected[0], dict(ds.sizes)
            assert ds.sizes["force_ratio"] == expected[1], dict(ds.sizes)
            if not mutations:
                for name in ("frequency_ratio", "force_ratio"):
                    axis = spec["grid"][name]
                    if not isinstance(axis, dict):  # a number or a list: stored exactly
                        np.testing.assert_array_equal(ds[name].values, np.atleast_1d(np.asarray(axis, float)))


def test_the_generator_makes_mostly_valid_specs() -> None:
    """A guard on the property above: unmutated specs are mostly accepted (else it tests little)."""
    verdicts: list[bool] = []

    @settings(max_examples=60, deadline=None, database=None)
    @given(valid_specs())
    def collect(case):
        try:
            parse_spec_text(json.dumps(case[0]))
            verdicts.append(True)
        except SpecError:
            verdicts.append(False)

    collect()
    assert sum(verdicts) >= len(verdicts) // 2, f"{sum(verdicts)} of {len(verdicts)} accepted"


# ---- random bytes and text as the spec file ---------------------------------------------------------

YAMLISH = st.text(
    alphabet=st.one_of(st.sampled_from(list("{}[]:,-?&*!|>'\"#%@` \n\t.eE0123456789abxyz_<=~\\")),
                       st.characters(exclude_categories=["Cs"])),
    max_size=300,
)


@PROPERTY
@given(data=st.one_of(st.binary(max_size=300), st.text(max_size=300), YAMLISH,
                      YAMLISH.map(lambda t: "scene: {excitation: base}\ngrid: " + t)))
def test_random_bytes_or_text_validate_exit_0_or_2(data) -> None:
    with tempfile.TemporaryDirectory(prefix="fsweep-prop-") as tmp:
        d = Path(tmp)
        (d / SPEC).write_bytes(data if isinstance(data, bytes) else data.encode())
        res = _invoke(d, "validate", SPEC)
        note(f"validate: exit {res.exit_code}\n{res.output}")
        _no_traceback(res, "validate")
        assert _files(d) == [SPEC], _files(d)


# ---- the Python API with hostile arguments (issue 28) -----------------------------------------------

#: numpy values that once escaped as TypeError, ValueError or RecursionError (longdouble's tolist is itself)
NUMPY_VALUES = [np.longdouble("1e4000"), np.longdouble(0.5), np.float32(0.5), np.float64(math.nan), np.int64(3),
                np.uint8(2), np.bool_(True), np.str_("base"), np.array(2), np.array(0.5), np.array([[0.5, 1.0]]),
                np.array([]), np.array([0.5, 1.0]), np.array([1.0, 0.5]), np.array([0.5, 1.0], dtype=np.longdouble),
                np.array(["a"]), np.array([1 + 1j]), np.array([0.5], dtype=object)]
ODD_VALUES = [None, True, 10**400, -(2**63), math.nan, math.inf, 2.5, "", "a\x00b", b"a\x00b", b"\xff.yaml",
              Path("nowhere.yaml"), Path("."), [], {}, [1], {"scene": 1}, object(), "\ud800", "threads", "serial"]
HOSTILE_ARGUMENTS = st.one_of(st.sampled_from(NUMPY_VALUES + ODD_VALUES), st.integers(), st.floats(),
                              st.text(max_size=12), st.binary(max_size=12))
#: where a hostile value replaces part of a small valid dict spec
DICT_PLACES = [("scene", "excitation"), ("grid", "frequency_ratio"), ("grid", "force_ratio"), ("method",),
               ("outputs",), ("settings",), ("grid",), ("x",)]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(call=st.sampled_from(["sweep", "sweep_dict", "sweep_yaml", "open_cube"]), value=HOSTILE_ARGUMENTS,
       place=st.sampled_from(DICT_PLACES),
       jobs=st.one_of(st.just(1), HOSTILE_ARGUMENTS), executor=st.one_of(st.just("serial"), HOSTILE_ARGUMENTS))
@example(call="sweep", value=12, place=("x",), jobs=1, executor="serial")
@example(call="sweep_dict", value=np.longdouble(0.5), place=("grid", "force_ratio"), jobs=1, executor="serial")
def test_any_api_argument_gives_a_result_or_a_fsweep_error(call, value, place, jobs, executor) -> None:
    """fs.sweep (path or dict), fs.sweep_yaml and fs.open_cube, with any argument of any type in any place
    (jobs, executor, the spec, a value inside a dict spec): a Dataset, or a FsweepError; never another
    exception (TypeError, ValueError, UnicodeEncodeError, RecursionError, YAMLStreamError before)."""
    import friction_sweep as fs

    spec = {"scene": {"excitation": "base"}, "grid": {"frequency_ratio": [1.0], "force_ratio": [0.1]},
            "method": "theory"}
    node = spec
    for key in place[:-1]:
        node = node[key]
    node[place[-1]] = value
    runs = {"sweep": lambda: fs.sweep(value, jobs=jobs, executor=executor),
            "sweep_dict": lambda: fs.sweep(spec, jobs=jobs, executor=executor),
            "sweep_yaml": lambda: fs.sweep_yaml(value, jobs=jobs, executor=executor),
            "open_cube": lambda: fs.open_cube(value)}
    with tempfile.TemporaryDirectory(prefix="fsweep-api-") as tmp, in_dir(Path(tmp)):
        try:
            result = runs[call]()
        except fs.FsweepError as err:
            assert str(err), "a refusal says why"
            return
    assert isinstance(result, xr.Dataset)
