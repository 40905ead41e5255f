"""`fsweep plot`: each kind drawn from small cubes (theory planes, a tiny event cube with time
histories, and copies given physical coordinates), checked on the matplotlib Figure the drawing
returns (labels, units, curves, shaded spans against the cube's regimes), and the command's refusals."""

import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from conftest import one_error_line, small_spec

from friction_sweep import quicklook
from friction_sweep.cli import main
from friction_sweep.codes import Regime
from friction_sweep.methods import theory
from friction_sweep.quicklook import KINDS, PlotError, axis_label
from friction_sweep.storage import cube
from friction_sweep.storage.outputs import FIGURES_EXTRA

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: the physical copies: frequency = r * F_N Hz, friction force = beta * F_K N, amplitude = T * Y_M m
F_N, F_K, Y_M = 12.5, 40.0, 0.002

EVENT = """\
scene: {excitation: base}
grid: {frequency_ratio: [0.3, 0.5, 1.5, 2.0], force_ratio: [0.2, 0.6]}
method: event
outputs: [transmissibility, phase, regime, time_history]
time_history: {points: [[0.5, 0.6], [1.5, 0.2], [1.0, 0.2]], samples_per_period: 32}
"""
WIDE = """\
scene: {excitation: base}
grid: {frequency_ratio: {start: 0.2, stop: 3.0, num: 15}, force_ratio: {start: 0.05, stop: 1.0, step: 0.05}}
method: theory
"""
ONLY_TRANSMISSIBILITY = WIDE.replace("method: theory\n", "method: theory\noutputs: [transmissibility]\n")
ONE_FORCE = small_spec("base").replace("[0.0, 0.3, 0.9]", "[0.3]")
#: a rig (f_n = sqrt(k/m) / 2 pi, Y = 1 mm) whose cube holds its orbits in seconds and metres
MASS, STIFFNESS, AMPLITUDE = 2.0, 40e3, 1e-3
RIG = EVENT.replace("grid:", "system: {mass: 2 kg, stiffness: 40 kN/m, base_amplitude: 1 mm}\ngrid:")
#: a damped simulation (the issue's example: it got the undamped, rigid boundaries)
DAMPED = """\
scene: {excitation: base, effects: {viscous_damping: 0.05}}
grid: {frequency_ratio: [0.5, 1.0, 1.5], force_ratio: [0.2, 0.6, 1.2]}
method: event
"""
#: static above kinetic friction: at beta = 0.9 (beta_s = 1.35 > 1) stuck from rest, moving from a moving start
STATIC_EVENT = """\
scene: {excitation: base, effects: {static_friction_ratio: 1.5}}
grid: {frequency_ratio: [0.4, 0.6, 1.5], force_ratio: [0.3, 0.9]}
method: event
"""
#: the frictionless peak next to r = 1 (1/|1 - r^2| = 1667) beside curves with friction near 1
PEAK = """\
scene: {excitation: base}
grid: {frequency_ratio: [0.3, 0.6, 0.8, 0.9997, 1.2, 1.5, 2.0, 3.0], force_ratio: [0.0, 0.3, 0.6, 0.9]}
method: theory
"""


def physical(ds: xr.Dataset) -> xr.Dataset:
    """The cube with the physical coordinates and variable another change adds (CF units)."""
    out = ds.assign_coords(
        frequency=("frequency_ratio", ds["frequency_ratio"].values * F_N, {"long_name": "frequency", "units": "Hz"}),
        friction_force=("force_ratio", ds["force_ratio"].values * F_K, {"long_name": "friction force", "units": "N"}))
    if "transmissibility" in ds:
        out["displacement_amplitude"] = (ds["transmissibility"] * Y_M).assign_attrs(
            long_name="displacement amplitude", units="m")
    return out


@pytest.fixture(scope="session")
def cubes(tmp_path_factory):
    """name -> path of every cube the tests draw (the event cube: numba's cached kernels, a second)."""
    folder = tmp_path_factory.mktemp("plot_cubes")
    specs = {"base": small_spec("base"), "joined": small_spec("joined"), "force": small_spec("force"), "event": EVENT,
             "wide": WIDE, "no_regime": ONLY_TRANSMISSIBILITY, "one_force": ONE_FORCE, "rig": RIG, "peak": PEAK,
             "damped": DAMPED, "static": STATIC_EVENT, "force_event": EVENT.replace("excitation: base", "excitation: force")}
    paths = {}
    for name, text in specs.items():
        spec = folder / f"{name}.yaml"
        spec.write_text(text)
        paths[name] = folder / f"{name}.h5"
        res = CliRunner().invoke(main, ["run", str(spec), "-o", str(paths[name]), "--quiet"])
        assert res.exit_code == 0, res.output
    for name in ("base", "event"):  # non-dimension coordinates: written by xarray (the cube writer refuses them)
        paths[f"{name}_physical"] = folder / f"{name}_physical.h5"
        physical(cube.open_cube(paths[name])).to_netcdf(paths[f"{name}_physical"], engine="h5netcdf")
    paths["no_limit"] = folder / "no_limit.h5"
    cube.write_atomic(cube.open_cube(paths["base"]).drop_vars("continuous_limit"), paths["no_limit"], overwrite=False)
    return paths


@pytest.fixture(scope="session")
def ds(cubes):
    return {name: cube.open_cube(path) for name, path in cubes.items()}


def by_gid(ax, gid):
    """The lines and collections of `ax` with this gid."""
    return [a for a in (*ax.lines, *ax.collections) if a.get_gid() == gid]


def line(ax, gid):
    (found,) = [a for a in ax.lines if a.get_gid() == gid]
    return found


def spans(collection) -> list[tuple[float, float]]:
    """(left, right) of each bar of a broken_barh collection."""
    return [(p.vertices[:, 0].min(), p.vertices[:, 0].max()) for p in collection.get_paths()]


def runs(mask) -> int:
    """Number of contiguous True runs."""
    mask = np.asarray(mask, dtype=int)
    return int(np.count_nonzero(np.diff(np.r_[0, mask]) == 1))


def text(label: str) -> str:
    return label.replace("\n", " ")


def title(fig) -> str:
    """The figure's title on one line."""
    return text(fig.get_suptitle())


R_LABEL = r"frequency ratio $r = \omega/\omega_n$"
#: the y label of the curves by (excitation, variable): the scene's quantity (a force scene has no base
#: motion Y: its amplitude is X over the static deflection F0/k)
Y_LABELS = {
    ("force", "transmissibility"): r"first-harmonic amplitude $|X|/(F_0/k)$",
    ("base", "transmissibility"): r"first-harmonic transmissibility $|X|/|Y|$",
    ("joined", "transmissibility"): r"first-harmonic transmissibility $|X|/|Y|$",
    ("force", "phase"): r"first-harmonic phase lag $\varphi$ of $x$ behind the force [°]",
    ("base", "phase"): r"first-harmonic phase lag $\varphi$ of $x$ behind the base [°]",
    ("joined", "phase"): r"first-harmonic phase lag $\varphi$ of $x$ behind the base [°]",
}


# --- labels --------------------------------------------------------------------------------------------


def test_axis_label_is_long_name_and_units_unless_dimensionless(ds):
    base = ds["base"]
    assert axis_label(base["frequency_ratio"]) == "frequency ratio r"  # "r = omega / omega_n" is a definition
    assert axis_label(base["force_ratio"]) == "force ratio beta"
    assert axis_label(base["phase"]) == "first-harmonic phase lag of the response [degree]"
    assert axis_label(base["transmissibility"]) == "first-harmonic transmissibility |X| / Y"
    phys = ds["base_physical"]
    assert axis_label(phys["frequency"]) == "frequency [Hz]"
    assert axis_label(phys["friction_force"]) == "friction force [N]"
    assert axis_label(phys["displacement_amplitude"]) == "displacement amplitude [m]"
    assert axis_label(xr.DataArray([1.0], dims="x", name="bare")) == "bare"


def test_default_kind_and_output(ds):
    assert quicklook.default_kind(ds["base"]) == "map"
    assert quicklook.default_kind(ds["event"]) == "map"
    assert quicklook.default_kind(ds["one_force"]) == "curves"  # one force ratio: a line, not a plane
    assert quicklook.default_kind(ds["no_regime"]) == "curves"  # a plane without regimes has no map
    # a selection chooses curves, or an orbit by its index
    assert quicklook.default_kind(ds["event"], ["force_ratio=0.2"]) == "curves"
    assert quicklook.default_kind(ds["event"], ["history_point=1"]) == "orbit"
    assert str(quicklook.default_output("results/demo.h5")) == "results/demo.png"


# --- map -----------------------------------------------------------------------------------------------


def test_map_draws_each_regime_with_its_flag_and_the_theory_boundaries(ds):
    d = ds["joined"]
    fig = quicklook.draw(d)  # the default kind on a plane
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == (R_LABEL, r"force ratio $\beta = F_\mu/(kY)$")
    (mesh,) = by_gid(ax, "regime")
    # flag_values are 0..4, so each cell's colour index is its code
    np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(d["regime"].shape), d["regime"].values)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    counts = {c: int((d["regime"].values == c).sum()) for c in Regime}
    assert counts[Regime.STUCK] and counts[Regime.STICK_SLIP] and counts[Regime.UNBOUNDED]
    for code, n in counts.items():
        entry = f"{code.name.lower().replace('_', '-')} ({n})"
        assert (entry in legend) == (n > 0), (entry, legend)
    r = d["frequency_ratio"].values
    limit = line(ax, "continuous_limit")
    np.testing.assert_array_equal(limit.get_xdata(), r)
    np.testing.assert_array_equal(limit.get_ydata(), d["continuous_limit"].values)
    assert "computed" not in limit.get_label()
    stuck = line(ax, "stuck_limit")  # joined: no motion from rest above beta = r^2
    np.testing.assert_allclose(stuck.get_ydata(), np.asarray(stuck.get_xdata()) ** 2)
    resonance = line(ax, "resonance")
    np.testing.assert_allclose(resonance.get_xdata(), [1.0, 1.0])
    np.testing.assert_allclose(resonance.get_ydata(), [0.0, np.pi / 4])
    assert ax.get_ylim()[0] == 0.0  # cells never reach below a force ratio of 0


def test_map_computes_the_continuous_limit_where_the_cube_lacks_it(ds):
    d = ds["no_limit"]
    assert "continuous_limit" not in d
    ax = quicklook.draw(d, "map").axes[0]
    limit = line(ax, "continuous_limit")
    r = d["frequency_ratio"].values
    np.testing.assert_allclose(limit.get_ydata(), theory.continuous_limit("base", r), rtol=1e-12)
    assert "computed" in limit.get_label()
    np.testing.assert_allclose(line(ax, "stuck_limit").get_ydata(), 1.0)  # base: beta = 1
    # the same values the run wrote
    np.testing.assert_allclose(limit.get_ydata(), ds["base"]["continuous_limit"].values, rtol=1e-12)


def test_map_on_physical_axes(ds):
    d = ds["base_physical"]
    ax = quicklook.draw(d, "map").axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("frequency $f$ [Hz]", r"friction force $F_\mu$ [N]")
    (mesh,) = by_gid(ax, "regime")
    corners = mesh.get_coordinates()
    f, force = d["frequency"].values, d["friction_force"].values
    assert corners[0, 0, 0] <= f[0] and corners[0, -1, 0] >= f[-1]
    assert corners[0, 0, 1] == 0.0 and corners[-1, 0, 1] >= force[-1]
    limit = line(ax, "continuous_limit")
    np.testing.assert_allclose(limit.get_xdata(), f)
    np.testing.assert_allclose(limit.get_ydata(), d["continuous_limit"].values * F_K)
    np.testing.assert_allclose(line(ax, "resonance").get_xdata(), [F_N, F_N])
    np.testing.assert_allclose(line(ax, "resonance").get_ydata(), [0.0, np.pi / 4 * F_K])


# --- curves and phase -------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["base", "joined", "force", "event"])
@pytest.mark.parametrize("kind", ["curves", "phase"])
def test_curves_one_per_force_ratio_with_regime_spans_per_curve(ds, name, kind):
    d = ds[name]
    var = quicklook.CURVE_VARIABLE[kind]
    fig = quicklook.draw(d, kind)
    ax, strip = fig.axes[0], fig.axes[1]
    r, beta = d["frequency_ratio"].values, d["force_ratio"].values
    curves = [ln for ln in ax.lines if str(ln.get_gid()).startswith("curve ")]
    assert len(curves) == beta.size
    assert text(ax.get_ylabel()) == Y_LABELS[d.attrs["excitation"], var]
    assert strip.get_xlabel() == R_LABEL
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [rf"$\beta$ = {b:g}" for b in beta]
    regime = d["regime"].values
    for row, ln in enumerate(curves):
        np.testing.assert_array_equal(ln.get_xdata(), r)
        np.testing.assert_array_equal(ln.get_ydata(), d[var].values[row])  # NaN where the method has none
        for code in (Regime.STICK_SLIP, Regime.STUCK):
            at = regime[row] == code
            shaded = by_gid(strip, f"{code.name.lower()} {row}")
            if not at.any():
                assert not shaded
                continue
            (bars,) = shaded
            assert len(bars.get_paths()) == runs(at)  # one span per run of the regime along r
            inside = np.zeros(r.size, bool)
            for lo, hi in spans(bars):
                inside |= (r > lo) & (r < hi)
            np.testing.assert_array_equal(inside, at)  # every point of the regime, and only those
        unbounded = by_gid(strip, f"unbounded {row}")
        at = regime[row] == Regime.UNBOUNDED
        assert len(unbounded) == int(at.any())
        if at.any():
            np.testing.assert_array_equal(unbounded[0].get_xdata(), r[at])
    assert (regime == Regime.STICK_SLIP).any()  # each cube has spans to check


def test_curves_on_physical_axes(ds):
    d = ds["base_physical"]
    fig = quicklook.draw(d, "curves")
    ax, strip = fig.axes[0], fig.axes[1]
    assert strip.get_xlabel() == "frequency $f$ [Hz]"
    assert strip.get_ylabel() == r"$F_\mu$ [N]"  # the strip's rows are friction forces: in newtons
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [rf"$F_\mu$ = {b * F_K:g} N"
                                                                   for b in d["force_ratio"].values]
    for ln in (ln for ln in ax.lines if str(ln.get_gid()).startswith("curve ")):
        np.testing.assert_allclose(ln.get_xdata(), d["frequency"].values)
    (bars,) = by_gid(strip, "stick_slip 2")  # beta = 0.9 sticks everywhere: one span over the whole axis
    ((lo, hi),) = spans(bars)
    assert lo <= d["frequency"].values[0] and hi >= d["frequency"].values[-1]


def test_curves_are_limited_to_a_readable_number_or_chosen_by_nearest_value(ds):
    d = ds["wide"]
    beta = d["force_ratio"].values
    assert beta.size == 20

    def drawn(fig):
        return [ln.get_label() for ln in fig.axes[0].lines if str(ln.get_gid()).startswith("curve ")]

    fig = quicklook.draw(d, "curves")
    labels = drawn(fig)
    assert len(labels) == quicklook.MAX_CURVES
    assert labels[0] == r"$\beta$ = 0.05" and labels[-1] == r"$\beta$ = 1"
    assert f"{quicklook.MAX_CURVES} of 20 force ratios" in title(fig)
    chosen = quicklook.draw(d, "curves", ["force_ratio=0.31", "force_ratio=0.87", "force_ratio=0.3"])
    assert drawn(chosen) == [r"$\beta$ = 0.3", r"$\beta$ = 0.85"]  # nearest, each once
    assert "of 20" in title(chosen)
    phys = quicklook.draw(ds["base_physical"], "phase", ["friction_force=13"])  # 0.3 * 40 = 12 N is nearest
    assert drawn(phys) == [r"$F_\mu$ = 12 N"]


def test_curves_without_regimes_draw_no_strip(ds):
    fig = quicklook.draw(ds["no_regime"])
    assert len(fig.axes) == 1 and fig.axes[0].get_xlabel() == R_LABEL


# --- orbit ---------------------------------------------------------------------------------------------


def test_orbit_draws_the_chosen_history(ds):
    d = ds["event"]
    for sel, k in ((["history_point=1"], 1), ([], 0), (["frequency_ratio=0.45"], 0), (["force_ratio=0.25"], 1),
                   (["frequency_ratio=1.4", "force_ratio=0.3"], 1)):
        fig = quicklook.draw(d, "orbit", sel)
        ax, plane = fig.axes
        t = d["history_time"].values[k]
        ok = np.isfinite(t)
        x = line(ax, "history_displacement")
        np.testing.assert_array_equal(x.get_xdata(), t[ok])
        np.testing.assert_array_equal(x.get_ydata(), d["history_displacement"].values[k][ok])
        np.testing.assert_array_equal(line(ax, "history_excitation").get_ydata(), d["history_excitation"].values[k][ok])
        q = line(plane, "phase_plane").get_xdata()
        np.testing.assert_array_equal(q[:-1], d["history_relative_displacement"].values[k][ok])
        assert q[-1] == q[0]  # closed: the orbit repeats
        assert ax.get_xlabel() == "time $t/T$ [forcing periods]"
        assert ax.get_ylabel() == "displacement $x/Y$"
        r, b = d["history_frequency_ratio"].values[k], d["history_force_ratio"].values[k]
        assert rf"orbit {k} of 3 at $r$ = {r:g}, $\beta$ = {b:g}" in title(fig)
    # physical coordinates pick by their own units: 18 Hz is r = 1.44, nearest to the history at 1.5
    fig = quicklook.draw(ds["event_physical"], "orbit", ["frequency=18"])
    assert "orbit 1 of 3 at $r$ = 1.5" in title(fig)


# --- what an engineer reads (issue 29): titles, labels, boundaries per scene and effects, scales ----------

BOUNDARY_GIDS = {"continuous_limit", "stuck_limit", "slider_stuck_limit", "resonance"}
DASHPOT = {"ratio": 0.05, "to": "ground"}
#: effects as a simulation records them (method_settings), and the boundaries whose theory holds with them
#: (docs/equations.md): Den Hartog's beta*(r) for the plain model only; no motion from rest while the force
#: amplitude stays inside the static band, for a rigid contact (on a contact spring the mass moves while the
#: slider holds); the Jenkins slider held while the forced motion on it loads the contact spring less than the
#: friction (§7: undamped, static = kinetic friction); the resonance at r = 1 without damping (rigid or
#: Jenkins contact, §7)
EFFECT_CASES = {
    "plain": ({}, {"continuous_limit", "stuck_limit", "resonance"}),
    "damped": ({"viscous_damping": DASHPOT}, {"stuck_limit"}),
    "static": ({"static_friction_ratio": 1.5}, {"stuck_limit", "resonance"}),
    "jenkins": ({"contact_stiffness": 10.0}, {"slider_stuck_limit", "resonance"}),
    "jenkins_static": ({"contact_stiffness": 10.0, "static_friction_ratio": 1.5}, {"resonance"}),
    "all": ({"viscous_damping": DASHPOT, "static_friction_ratio": 1.5, "contact_stiffness": 10.0}, set()),
}


def with_effects(d: xr.Dataset, effects: dict) -> xr.Dataset:
    """The cube as a simulation with these effects records its scene (what the boundaries and title read)."""
    out = d.copy()
    out.attrs = {**d.attrs, "method": "event", "method_settings": json.dumps({"effects": effects})}
    return out


def words(fig) -> list:
    """The figure's texts a reader reads: its title, the axes' titles and labels, the legends' entries."""
    texts = [fig._suptitle] if fig._suptitle is not None else []
    for ax in fig.axes:
        texts += [ax.title, ax.xaxis.label, ax.yaxis.label]
        if ax.get_legend() is not None:
            texts += ax.get_legend().get_texts()
    return [t for t in texts if t.get_visible() and t.get_text().strip()]


DRAWN = [(name, kind) for name in ("base", "joined", "force", "event", "rig", "force_event", "wide", "base_physical",
                                   "static")
         for kind in KINDS if kind != "orbit" or name in ("event", "rig", "force_event")]


@pytest.mark.parametrize("effects", ["plain", "all"])
@pytest.mark.parametrize(("name", "kind"), DRAWN)
def test_every_title_and_label_fits_inside_the_figure(ds, name, kind, effects):
    d = with_effects(ds[name], EFFECT_CASES[effects][0]) if effects != "plain" else ds[name]
    fig = quicklook.draw(d, kind)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = fig.bbox
    assert fig.get_suptitle(), "the figure has a title"
    for t in words(fig):
        box = t.get_window_extent(renderer)
        assert (box.x0 >= frame.x0 - 0.5 and box.x1 <= frame.x1 + 0.5 and box.y0 >= frame.y0 - 0.5
                and box.y1 <= frame.y1 + 0.5), f"{t.get_text()!r} leaves the figure: {box} outside {frame}"


@pytest.mark.parametrize(("name", "kind"), DRAWN)
def test_symbols_are_mathtext_everywhere(ds, name, kind):
    d = with_effects(ds[name], EFFECT_CASES["all"][0])
    for t in words(quicklook.draw(d, kind)):
        content = t.get_text()
        assert content.count("$") % 2 == 0, content
        prose = "".join(content.split("$")[::2])  # outside $...$
        for plain in ("beta", "F_mu", "omega", "zeta", "kappa", "mu_s", "F0", "_n", "|Y(r)|"):
            assert plain not in prose, (plain, content)


@pytest.mark.parametrize("case", EFFECT_CASES)
def test_the_title_says_which_effects_the_cube_has(ds, case):
    effects, _ = EFFECT_CASES[case]
    for kind in ("map", "curves"):
        said = title(quicklook.draw(with_effects(ds["base"], effects), kind))
        assert "base excitation, method event" in said
        assert (r"viscous damping $\zeta$ = 0.05 (dashpot to ground)" in said) == ("viscous_damping" in effects)
        assert (r"static friction $\mu_s/\mu_k$ = 1.5" in said) == ("static_friction_ratio" in effects)
        assert (r"contact stiffness $\kappa = k_t/k$ = 10" in said) == ("contact_stiffness" in effects)
        assert ("no effects" in said) == (not effects)


@pytest.mark.parametrize("excitation", ["force", "base", "joined"])
@pytest.mark.parametrize("case", EFFECT_CASES)
def test_map_draws_only_the_boundaries_whose_theory_holds(ds, excitation, case):
    effects, expected = EFFECT_CASES[case]
    ax = quicklook.draw(with_effects(ds[excitation], effects), "map").axes[0]
    assert {ln.get_gid() for ln in ax.lines} & BOUNDARY_GIDS == expected
    static = effects.get("static_friction_ratio", 1.0)
    if "stuck_limit" in expected:  # no motion from rest while the force amplitude (1; r^2 joined) <= beta_s
        r, beta = line(ax, "stuck_limit").get_data()
        np.testing.assert_allclose(beta, (np.asarray(r) ** 2 if excitation == "joined" else 1.0) / static)
    if "slider_stuck_limit" in expected:  # kappa |F|, F the forced amplitude of the held oscillator 1 + kappa
        r, beta = line(ax, "slider_stuck_limit").get_data()
        r = np.asarray(r)
        force = r**2 if excitation == "joined" else 1.0
        np.testing.assert_allclose(beta, 10.0 * force / np.abs(11.0 - r**2), rtol=1e-12)
    if "resonance" in expected:  # unbounded for b <= pi/4, among the force ratios that move from rest
        np.testing.assert_allclose(line(ax, "resonance").get_ydata(), [0.0, min(np.pi / 4, 1.0 / static)])
    legend = [text(t.get_text()) for t in ax.get_legend().get_texts()]
    assert any("no closed-form boundary" in t for t in legend) == (not expected)


def test_a_damped_simulation_gets_no_undamped_boundaries(ds):
    d = ds["damped"]
    ax = quicklook.draw(d, "map").axes[0]
    assert {ln.get_gid() for ln in ax.lines} & BOUNDARY_GIDS == {"stuck_limit"}
    assert r"viscous damping $\zeta$ = 0.05" in title(ax.figure)
    # the simulation agrees: bounded at r = 1 (the undamped line said unbounded), and stuck above beta = 1
    assert not (d["regime"].values == Regime.UNBOUNDED).any()
    np.testing.assert_array_equal(d["regime"].sel(force_ratio=1.2).values, Regime.STUCK)


@pytest.mark.slow
def test_the_jenkins_slider_limit_parts_the_simulated_stuck_points(tmp_path):
    """An event run of the Jenkins contact (kappa = 10) is stuck exactly above the drawn limit."""
    spec = tmp_path / "jenkins.yaml"
    spec.write_text("""\
scene: {excitation: base, effects: {contact_stiffness: 10}}
grid: {frequency_ratio: [0.5, 1.5, 2.0, 2.5, 3.0], force_ratio: [1.2, 2.0]}
method: event
outputs: [transmissibility, regime]
""")
    out = tmp_path / "jenkins.h5"
    res = CliRunner().invoke(main, ["run", str(spec), "-o", str(out), "-q"])
    assert res.exit_code == 0, res.output
    d = cube.open_cube(out)
    fine_r, limit = line(quicklook.draw(d, "map").axes[0], "slider_stuck_limit").get_data()
    r, beta = d["frequency_ratio"].values, d["force_ratio"].values
    above = beta[:, None] > np.interp(r, fine_r, limit)[None, :]
    np.testing.assert_array_equal(d["regime"].values == Regime.STUCK, above)
    assert above.any() and not above.all()


def test_a_dashpot_to_the_base_raises_the_no_motion_limit(ds):
    zeta = 0.2
    ax = quicklook.draw(with_effects(ds["base"], {"viscous_damping": {"ratio": zeta, "to": "base"}}), "map").axes[0]
    r, beta = line(ax, "stuck_limit").get_data()
    # x'' + 2 zeta x' + x + beta sgn(x') = cos(r t) - 2 zeta r sin(r t): the force's amplitude |1 + 2i zeta r|
    np.testing.assert_allclose(beta, np.abs(1.0 + 2j * zeta * np.asarray(r)), rtol=1e-12)


def test_curves_choose_a_log_axis_where_the_range_is_wide(ds):
    peak = ds["peak"]
    assert np.nanmax(peak["transmissibility"].values) > 1000  # the frictionless peak next to r = 1
    assert quicklook.draw(peak, "curves").axes[0].get_yscale() == "log"
    assert quicklook.draw(ds["base"], "curves").axes[0].get_yscale() == "linear"  # peaks of 3 beside 1: readable
    assert quicklook.draw(peak, "curves", yscale="linear").axes[0].get_yscale() == "linear"
    assert quicklook.draw(ds["base"], "curves", yscale="log").axes[0].get_yscale() == "log"
    assert quicklook.draw(peak, "phase").axes[0].get_yscale() == "linear"  # lags change sign
    for kind in ("phase", "map"):
        with pytest.raises(PlotError, match=f"--yscale log applies to --kind curves .*--kind {kind} draws"):
            quicklook.draw(peak, kind, yscale="log")


@pytest.mark.parametrize("kind", ["curves", "phase"])
def test_curves_show_the_second_state_where_the_cube_has_two(ds, kind):
    d = ds["static"]
    var = quicklook.CURVE_VARIABLE[kind]
    two = d["steady_states"].values == 2
    assert two[1, :2].all() and not two[0].any()  # beta = 0.9 below resonance: stuck from rest, or moving
    ax = quicklook.draw(d, kind).axes[0]
    assert not by_gid(ax, "moving 0")  # beta = 0.3: one state, nothing dashed
    (dashed,) = by_gid(ax, "moving 1")
    np.testing.assert_array_equal(dashed.get_ydata(), np.where(two[1], d[var + "_moving"].values[1], np.nan))
    assert d["regime"].values[1, 0] == Regime.STUCK and d["regime_moving"].values[1, 0] != Regime.STUCK
    assert any("second state" in t.get_text() for t in ax.get_legend().get_texts())
    assert "second state" not in " ".join(t.get_text() for t in quicklook.draw(ds["event"], kind).axes[0]
                                          .get_legend().get_texts())


def test_curves_of_a_rig_say_what_their_ratio_is_of(ds):
    ax = quicklook.draw(ds["rig"], "curves").axes[0]
    assert text(ax.get_ylabel()) == Y_LABELS["base", "transmissibility"] + f" ($Y$ = {AMPLITUDE * 1e3:g} mm)"
    assert text(quicklook.draw(ds["rig"], "phase").axes[0].get_ylabel()) == Y_LABELS["base", "phase"]


def test_orbit_in_seconds_and_metres_where_the_cube_holds_them(ds):
    d = ds["rig"]
    natural = math.sqrt(STIFFNESS / MASS) / (2.0 * math.pi)  # f_n [Hz]
    for k in (0, 1):
        fig = quicklook.draw(d, "orbit", [f"history_point={k}"])
        ax, plane = fig.axes
        t = d["history_time"].values[k]
        ok = np.isfinite(t)
        r = float(d["history_frequency_ratio"].values[k])
        x = line(ax, "history_displacement")
        np.testing.assert_allclose(x.get_xdata(), t[ok] / (r * natural), rtol=1e-9)  # forcing periods / f
        np.testing.assert_allclose(x.get_ydata(), d["history_displacement"].values[k][ok] * AMPLITUDE, rtol=1e-12)
        np.testing.assert_allclose(line(ax, "history_excitation").get_ydata(),
                                   d["history_excitation"].values[k][ok] * AMPLITUDE, rtol=1e-12)  # the base, y
        q, v = line(plane, "phase_plane").get_data()
        np.testing.assert_allclose(q[:-1], d["history_relative_displacement"].values[k][ok] * AMPLITUDE, rtol=1e-12)
        omega_n = 2.0 * math.pi * natural  # velocities in Y per 1/omega_n
        np.testing.assert_allclose(v[:-1], d["history_relative_velocity"].values[k][ok] * AMPLITUDE * omega_n,
                                   rtol=1e-9)
        np.testing.assert_allclose(line(plane, "section").get_data(), [[q[0]], [v[0]]])
        assert (ax.get_xlabel(), ax.get_ylabel()) == ("time $t$ [s]", "displacement $x$ [m]")
        assert (plane.get_xlabel(), plane.get_ylabel()) == ("displacement $x$ [m]", r"velocity $\dot{x}$ [m/s]")
        assert f"$f$ = {r * natural:.3g} Hz" in title(fig)


def test_orbit_of_a_force_draws_the_force_on_its_own_axis(ds):
    d = ds["force_event"]
    fig = quicklook.draw(d, "orbit", ["history_point=0"])
    ax, plane, twin = fig.axes
    assert ax.get_ylabel() == "displacement $x/(F_0/k)$" and twin.get_ylabel() == "force $F/F_0$"
    np.testing.assert_array_equal(line(twin, "history_excitation").get_ydata(),
                                  d["history_excitation"].values[0][np.isfinite(d["history_time"].values[0])])
    assert not by_gid(ax, "history_excitation")
    assert (plane.get_xlabel(), plane.get_ylabel()) == ("displacement $x/(F_0/k)$", r"velocity $\dot{x}/(\omega_n F_0/k)$")


# --- refusals (library) --------------------------------------------------------------------------------


@pytest.mark.parametrize(("kind", "sel", "words"), [
    ("curves", ["foo=1"], "the cube has no dimension or coordinate 'foo'"),
    ("curves", ["force_ratio=abc"], "'abc' is not a number"),
    ("curves", ["force_ratio"], "expected NAME=VALUE"),
    ("curves", ["=0.3"], "expected NAME=VALUE"),
    ("curves", ["force_ratio=nan"], "must be finite"),
    ("curves", ["frequency_ratio=1"], "does not apply to --kind curves (it applies to force_ratio)"),
    ("map", ["force_ratio=0.2"], "does not apply to --kind map (it draws the whole cube)"),
    ("orbit", ["history_point=1.5"], "is not a whole number"),
    ("orbit", ["history_point=3"], "the cube holds histories 0..2"),
    ("orbit", ["history_point=2"], "history 2 (r = 1, beta = 0.2, unbounded) holds no steady orbit"),
    ("orbit", ["history_point=0", "force_ratio=0.2"], "picks the orbit by itself"),
    ("orbit", ["force_ratio=0.2", "force_ratio=0.6"], "draws one orbit"),
])
def test_bad_selections_are_refused(ds, kind, sel, words):
    with pytest.raises(PlotError) as err:
        quicklook.draw(ds["event"], kind, sel)
    assert words in str(err.value)


def test_missing_variables_are_refused(ds):
    with pytest.raises(PlotError, match="the cube holds no time history"):
        quicklook.draw(ds["base"], "orbit")
    with pytest.raises(PlotError, match="--kind map needs the variable regime"):
        quicklook.draw(ds["no_regime"], "map")
    with pytest.raises(PlotError, match="--kind phase needs the variable phase"):
        quicklook.draw(ds["no_regime"], "phase")


# --- the command ---------------------------------------------------------------------------------------


def test_plot_writes_a_png_beside_the_cube_by_default(runner, cubes, tmp_path):
    result = tmp_path / "demo.h5"
    shutil.copy(cubes["base"], result)
    res = runner.invoke(main, ["plot", str(result)])
    assert res.exit_code == 0, res.output
    out = tmp_path / "demo.png"
    assert res.stdout.strip() == f"wrote {out}"
    assert out.read_bytes().startswith(PNG_SIGNATURE) and out.stat().st_size > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.h5", "demo.png"]  # no temporary left


@pytest.mark.parametrize("kind", KINDS)
def test_plot_every_kind(runner, cubes, tmp_path, kind):
    out = tmp_path / "sub" / f"{kind}.png"
    res = runner.invoke(main, ["plot", str(cubes["event_physical"]), "--kind", kind, "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes().startswith(PNG_SIGNATURE) and out.stat().st_size > 10_000


@pytest.mark.parametrize("yscale", ["log", "linear", "auto"])
def test_plot_takes_the_curves_y_scale(runner, cubes, tmp_path, yscale):
    out = tmp_path / "curves.png"
    res = runner.invoke(main, ["plot", str(cubes["peak"]), "--kind", "curves", "--yscale", yscale, "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes().startswith(PNG_SIGNATURE)


def test_plot_without_matplotlib_refuses_before_reading(runner, tmp_path, no_matplotlib):
    # the cube does not even exist: the extra is checked first
    res = runner.invoke(main, ["plot", str(tmp_path / "absent.h5")])
    assert FIGURES_EXTRA in one_error_line(res, 2)
    assert list(tmp_path.iterdir()) == []


def _refused(runner, args, folder, words):
    before = sorted(os.listdir(folder))
    res = runner.invoke(main, ["plot", *args])
    assert words in one_error_line(res, 2)
    assert sorted(os.listdir(folder)) == before  # nothing written
    return res


def test_plot_refusals(runner, cubes, tmp_path):
    good = tmp_path / "c.h5"
    shutil.copy(cubes["event"], good)
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"not hdf5 at all")
    _refused(runner, [str(garbage)], tmp_path, "is not a readable result cube")
    _refused(runner, [str(tmp_path / "absent.h5")], tmp_path, "No such file or directory")
    _refused(runner, [str(good), "--sel", "beta=0.3"], tmp_path, "no dimension or coordinate 'beta'")
    _refused(runner, [str(good), "--kind", "curves", "--sel", "force_ratio=x"], tmp_path, "'x' is not a number")
    _refused(runner, [str(good), "--kind", "phase", "--yscale", "log"], tmp_path, "--yscale log applies to --kind curves")
    theory_cube = tmp_path / "t.h5"
    shutil.copy(cubes["base"], theory_cube)
    _refused(runner, [str(theory_cube), "--kind", "orbit"], tmp_path, "holds no time history")
    # outputs: a folder, a link, not a PNG, the cube itself
    (tmp_path / "folder.png").mkdir()
    _refused(runner, [str(good), "-o", str(tmp_path / "folder.png")], tmp_path, "is a directory")
    (tmp_path / "link.png").symlink_to(tmp_path / "elsewhere.png")
    _refused(runner, [str(good), "-o", str(tmp_path / "link.png")], tmp_path, "never replaces links")
    _refused(runner, [str(good), "-o", str(theory_cube)], tmp_path, "does not end in .png")
    named_png = tmp_path / "cube.png"
    shutil.copy(cubes["event"], named_png)
    _refused(runner, [str(named_png)], tmp_path, "an input of this command")
    res = runner.invoke(main, ["plot", str(good), "--kind", "bars"])
    assert "Invalid value for '--kind'" in one_error_line(res, 2)


def test_plot_write_failure_leaves_nothing(runner, cubes, tmp_path, monkeypatch):
    import errno

    out = tmp_path / "x.png"

    def full(fh, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr("matplotlib.figure.Figure.savefig", lambda self, fh, **k: full(fh))
    res = runner.invoke(main, ["plot", str(cubes["base"]), "-o", str(out)])
    assert "No space left on device; nothing was written" in one_error_line(res, 1)
    assert list(tmp_path.iterdir()) == []


def test_the_command_line_imports_no_matplotlib():
    code = "import sys, friction_sweep.cli\nassert 'matplotlib' not in sys.modules, 'matplotlib was imported'\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_the_readme_states_the_wide_range_the_code_uses():
    from conftest import ROOT

    readme = " ".join((ROOT / "README.md").read_text().split())
    assert f"more than {quicklook.WIDE_RANGE:g} times their median" in readme
    assert "[--yscale auto|linear|log]" in readme
