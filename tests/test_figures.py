"""The figure scripts: each one runs on tiny cubes built here with the library and writes a PNG;
the quick-spec writer keeps a spec valid while coarsening it; figures.mk knows every script."""

import importlib.util
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner
from conftest import ROOT

from friction_sweep.cli import main as fsweep
from friction_sweep.spec import load_spec

FIGURES = ROOT / "figures"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# Tiny cubes: name -> spec text. Grids of a few points keep the whole module to seconds.
SPECS = {
    "force_theory": """\
scene: {excitation: force}
grid: {frequency_ratio: {start: 0.2, stop: 3.0, num: 15}, force_ratio: [0.0, 0.3, 0.8]}
method: theory
""",
    "base_theory": """\
scene: {excitation: base}
grid: {frequency_ratio: {start: 0.2, stop: 3.0, num: 15}, force_ratio: [0.0, 0.2, 0.4, 0.6, 0.8]}
method: theory
""",
    "joined_theory": """\
scene: {excitation: joined}
grid: {frequency_ratio: {start: 0.2, stop: 3.0, num: 15}, force_ratio: [0.0, 0.2, 0.6, 1.0, 1.4]}
method: theory
""",
    "joined_inversion": """\
scene: {excitation: joined}
grid: {frequency_ratio: {start: 1.3, stop: 1.7, num: 9}, force_ratio: [0.2, 0.4, 0.6]}
method: theory
outputs: [transmissibility, regime]
""",
    "joined_map": """\
scene: {excitation: joined}
grid: {frequency_ratio: {start: 0.1, stop: 2.0, num: 12}, force_ratio: {start: 0.0, stop: 1.5, num: 6}}
method: theory
outputs: [regime]
""",
    "base_event": """\
scene: {excitation: base}
grid: {frequency_ratio: [0.3, 0.8, 1.5, 3.0], force_ratio: [0.2, 0.4, 0.6, 0.8]}
method: event
""",
    "joined_event": """\
scene: {excitation: joined}
grid: {frequency_ratio: [0.5, 0.95, 1.5, 3.0], force_ratio: [0.2, 0.6, 1.0, 1.4]}
method: event
""",
    "viscous_01": """\
scene: {excitation: joined, effects: {viscous_damping: 0.1}}
grid: {frequency_ratio: [0.5, 1.0, 1.5, 3.0], force_ratio: 0.0}
method: event
outputs: [transmissibility, regime]
""",
    "viscous_05": """\
scene: {excitation: joined, effects: {viscous_damping: 0.5}}
grid: {frequency_ratio: [0.5, 1.0, 1.5, 3.0], force_ratio: 0.0}
method: event
outputs: [transmissibility, regime]
""",
    "base_history": """\
scene: {excitation: base}
grid: {frequency_ratio: [0.4, 2.0], force_ratio: [0.3]}
method: event
outputs: [transmissibility, regime, time_history]
time_history: {points: [[0.4, 0.3], [2.0, 0.3]], samples_per_period: 32}
""",
    "joined_history": """\
scene: {excitation: joined}
grid: {frequency_ratio: [0.95], force_ratio: [0.8]}
method: event
outputs: [transmissibility, regime, time_history]
time_history: {points: [[0.95, 0.8]], samples_per_period: 32}
""",
    **{f"sweep_{d}": f"""\
scene: {{excitation: joined, effects: {{static_friction_ratio: 1.5}}}}
grid: {{frequency_ratio: [0.7, 0.8, 0.9, 1.5], force_ratio: [0.5]}}
method: event
sweep: {{direction: {d}}}
""" for d in ("up", "down")},
    "static_starts": """\
scene: {excitation: joined, effects: {static_friction_ratio: 1.5}}
grid: {frequency_ratio: [0.7, 0.8, 0.9, 1.5], force_ratio: [0.5]}
method: event
""",
    **{f"jenkins_{name}": f"""\
scene: {{excitation: base, effects: {{{effect}}}}}
grid: {{frequency_ratio: [0.5, 1.2, 1.5, 3.0], force_ratio: [0.3, 1.5]}}
method: event
outputs: [transmissibility, regime]
""" for name, effect in (("k10", "contact_stiffness: 10"), ("k100", "contact_stiffness: 100"), ("rigid", ""))},
    "blade_damper": """\
scene: {excitation: force}
structure:
  masses: {tip: 1.0, platform: 0.5, damper: 0.05}
  springs: [[ground, platform, 3.0], [platform, tip, 2.0], [ground, damper, 5.0]]
  dampers: [[ground, tip, 0.01]]
  contacts: [{name: damper, between: [damper, platform], friction: 1.0, stiffness: 5.0}]
  forcing: {tip: 1.0}
grid: {frequency: [0.9, 1.05, 1.12, 1.2, 1.4], friction_scale: [0.5, 3.0, 10.0]}
method: event
""",
}

# script -> the cubes it takes, in order
CALLS = {
    "fig01b": ["viscous_01", "viscous_05"],
    "fig04": ["force_theory"],
    "fig05": ["force_theory"],
    "fig07": ["base_theory"],
    "fig08": ["base_theory"],
    "fig10": ["joined_theory"],
    "fig11": ["joined_theory"],
    "fig13": ["joined_map"],
    "fig14": ["joined_theory", "joined_inversion"],
    "fig15": ["joined_theory"],
    "fig16": ["joined_theory"],
    "fig17": ["base_event", "base_event"],
    "fig18": ["base_event", "base_theory"],
    "fig19": ["base_history"],
    "fig20": ["joined_event"],
    "fig21": ["joined_event", "joined_theory"],
    "fig22": ["joined_history"],
    "hysteresis": ["sweep_up", "sweep_down", "static_starts"],
    "jenkins": ["jenkins_rigid", "jenkins_k100", "jenkins_k10"],  # any order: the script sorts by kappa
    "blade_damper": ["blade_damper"],
}


@pytest.fixture(scope="module")
def cubes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cubes")
    runner = CliRunner()
    paths = {}
    for name, text in SPECS.items():
        spec = folder / f"{name}.yaml"
        spec.write_text(text)
        out = folder / f"{name}.h5"
        res = runner.invoke(fsweep, ["run", str(spec), "-o", str(out), "--quiet"])
        assert res.exit_code == 0, res.output
        paths[name] = out
    return paths


def load_script(name):
    """A figure script as a module; its folder on sys.path, as when it runs as `python figures/X.py`."""
    if str(FIGURES) not in sys.path:
        sys.path.insert(0, str(FIGURES))
    spec = importlib.util.spec_from_file_location(f"figure_script_{name}", FIGURES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_script_is_covered_here():
    scripts = sorted(p.stem for p in FIGURES.glob("*.py") if p.stem not in ("common", "quick_spec"))
    assert scripts == sorted(CALLS)


@pytest.mark.parametrize("name", sorted(CALLS))
@pytest.mark.slow
def test_script_writes_a_png(cubes, tmp_path, name, monkeypatch):
    out = tmp_path / "out" / f"{name}.png"
    script = load_script(name)
    drawn = []
    write = script.C.save_figure
    monkeypatch.setattr(script.C, "save_figure", lambda fig, path: (drawn.append(fig), write(fig, path))[1])
    script.main([str(cubes[c]) for c in CALLS[name]] + [str(out)])
    data = out.read_bytes()
    assert data.startswith(PNG_SIGNATURE) and len(data) > 10_000
    assert not [p for p in out.parent.iterdir() if p.name != out.name]  # no temporary file left behind
    (fig,) = drawn
    assert_texts_inside(fig)


def assert_texts_inside(fig):
    """Every title, axis label and legend entry of `fig` lies inside it as saved (none clipped)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    renderer, frame = fig.canvas.get_renderer(), fig.bbox
    texts = [fig._suptitle] if fig._suptitle is not None else []
    for ax in fig.axes:
        texts += [ax.title, ax.xaxis.label, ax.yaxis.label, *(ax.get_legend().get_texts() if ax.get_legend() else [])]
    for t in (t for t in texts if t.get_visible() and t.get_text().strip()):
        box = t.get_window_extent(renderer)
        assert (box.x0 >= frame.x0 - 0.5 and box.x1 <= frame.x1 + 0.5 and box.y0 >= frame.y0 - 0.5
                and box.y1 <= frame.y1 + 0.5), f"{t.get_text()!r} leaves the figure"


@pytest.mark.slow
def test_script_runs_from_the_command_line(cubes, tmp_path):
    out = tmp_path / "fig07.png"
    res = subprocess.run([sys.executable, str(FIGURES / "fig07.py"), str(cubes["base_theory"]), str(out)],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert out.read_bytes().startswith(PNG_SIGNATURE)


@pytest.mark.slow
def test_wrong_call_exits_with_usage(cubes, tmp_path):
    with pytest.raises(SystemExit, match="usage"):
        load_script("fig14").main([str(cubes["joined_theory"]), str(tmp_path / "x.png")])  # needs two cubes
    with pytest.raises(SystemExit, match="usage"):
        load_script("fig07").main([str(cubes["base_theory"]), str(tmp_path / "x.pdf")])


@pytest.mark.slow
def test_missing_variable_is_reported(cubes, tmp_path):
    with pytest.raises(SystemExit, match="peak_phase"):  # the map cube has no phases
        load_script("fig05").main([str(cubes["joined_map"]), str(tmp_path / "x.png")])


def test_transient_from_rest_starts_at_rest_and_beats():
    common = load_script("common")
    t, x, y, q, v = common.transient_from_rest("base", 0.95, 0.05, periods=40, samples_per_period=64)
    assert t.shape == x.shape == (40 * 64,)
    assert x[0] == 0.0 and v[0] == 0.0 and y[0] == 1.0
    # beating: the envelope (max |x| per period) rises to ~19 near period 10, falls back near
    # period 19 and rises again (the undamped beat lasts 1/(1 - r) = 20 forcing periods)
    envelope = np.abs(x).reshape(40, 64).max(axis=1)
    peak, trough, second = envelope[5:15].max(), envelope[15:23].min(), envelope[23:35].max()
    assert peak > 15.0 and trough < 0.25 * peak and second > 3.0 * trough


def test_regime_runs_split_at_midpoints():
    common = load_script("common")
    runs = common.regime_runs([0.0, 1.0, 2.0, 3.0], [0, 0, 1, 2])
    assert runs == [(0, 0.0, 1.5), (1, 1.5, 2.5), (2, 2.5, 3.0)]


def test_quick_spec_is_a_valid_coarse_copy(tmp_path):
    quick = load_script("quick_spec")
    src = ROOT / "configs" / "fig13_joined_regime_map.yaml"
    dst = tmp_path / "quick" / "fig13.yaml"
    assert quick.main([str(src), str(dst), "--num", "40", "--max-force-ratios", "7"]) == 0
    original, coarse = load_spec(src), load_spec(dst)
    assert coarse.frequency_ratio.size == 40 and coarse.force_ratio.size == 7
    assert coarse.frequency_ratio[0] == original.frequency_ratio[0]
    assert coarse.frequency_ratio[-1] == original.frequency_ratio[-1]
    assert (coarse.scene, coarse.method, coarse.outputs) == (original.scene, original.method, original.outputs)
    assert str(coarse.output) == str(dst.with_suffix(".nc"))


def test_quick_spec_keeps_small_axes_and_time_histories(tmp_path):
    quick = load_script("quick_spec")
    src = ROOT / "configs" / "numerical" / "fig19_base_time_histories.yaml"
    dst = tmp_path / "fig19.yaml"
    assert quick.main([str(src), str(dst)]) == 0
    original, coarse = load_spec(src), load_spec(dst)
    np.testing.assert_array_equal(coarse.frequency_ratio, original.frequency_ratio)
    np.testing.assert_array_equal(coarse.force_ratio, original.force_ratio)
    assert coarse.time_history == original.time_history


def test_quick_spec_coarsens_a_structure_spec_on_its_own_axes(tmp_path):
    quick = load_script("quick_spec")
    src = ROOT / "configs" / "blade_damper.yaml"
    dst = tmp_path / "blade_damper.yaml"
    assert quick.main([str(src), str(dst), "--num", "40", "--max-force-ratios", "11"]) == 0
    original, coarse = load_spec(src), load_spec(dst)
    assert coarse.frequency.size == 40 and coarse.friction_scale.size == 11
    assert coarse.frequency[[0, -1]].tolist() == original.frequency[[0, -1]].tolist()
    assert coarse.friction_scale[[0, -1]].tolist() == original.friction_scale[[0, -1]].tolist()
    assert coarse.structure == original.structure and coarse.outputs == original.outputs


@pytest.mark.parametrize("config", sorted((ROOT / "configs" / "numerical").glob("*.yaml")), ids=lambda p: p.stem)
def test_simulation_specs_are_valid(config):
    spec = load_spec(config)
    assert spec.method == "event"
    assert str(spec.output) == f"results/numerical/{config.stem}.nc"
    assert spec.frequency_ratio.size * spec.force_ratio.size <= 10_000  # well under a minute on 2 cores


def test_figures_mk_builds_every_script():
    text = (ROOT / "figures.mk").read_text()
    names = re.search(r"^FIGURE_NAMES\s*:=\s*((?:.*\\\n)*.*)$", text, re.M).group(1)
    assert sorted(names.replace("\\", " ").split()) == sorted(CALLS)
    for name in CALLS:
        assert re.search(rf"^CUBES_{name}\s*:=", text, re.M), name


@pytest.mark.skipif(shutil.which("make") is None, reason="make not installed")
def test_figures_mk_parses_and_plans_every_figure():
    # -n: print the plan only; -o: never (re)install the environment for this
    res = subprocess.run(["make", "-n", "-f", "Makefile", "-f", "figures.mk", "-o", ".venv/.installed-stamp",
                          "-W", "figures/common.py", "figures", "figures-quick", "validate"],
                         cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    for name in CALLS:
        assert f"figures/{name}.py" in res.stdout
        assert f"figures/out/quick/{name}.png" in res.stdout
    assert "friction_sweep.validation" in res.stdout
