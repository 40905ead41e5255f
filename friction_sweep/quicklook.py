"""Quick looks at a result cube (`fsweep plot`): the regime map, transmissibility or phase curves, and a
stored orbit, each drawn from the cube alone into a matplotlib Figure.

    map      `regime` over (r, beta), coloured by its CF flags, with the theory's boundaries over it, each
             only where its theory holds for the cube's scene and effects (boundaries):
             Den Hartog's continuous-motion limit (plain model only), the no-motion limit A(r) = beta_s
             (stuck above; rigid contact) or the Jenkins slider's, and the undamped resonance r = 1
             (unbounded for b <= pi/4)
    curves   `transmissibility` against r, one curve per force ratio (at most MAX_CURVES unless chosen),
             and under it a strip per curve: its stick-slip and stuck spans shaded, its unbounded and
             unsettled points marked; the y axis logarithmic where asked, or (auto) where the values span
             more than WIDE_RANGE (a frictionless peak beside damped curves)
    phase    the same for `phase`
    orbit    one stored steady orbit (`history_*`): response and excitation over time, and the phase plane,
             in seconds and metres where the cube holds them (`system:`)

Every figure's title says what is drawn, the scene (excitation, method) and its effects, wrapped to fit
the figure's width (fit_title). Axes follow the cube: where it holds a non-dimension coordinate with
physical units along a grid dimension (`frequency` in Hz on frequency_ratio, `friction_force` in N on
force_ratio), the plot is drawn against it. Labels are mathtext with the scene's quantity (LABELS: a
force scene's amplitude is X/(F0/k), a base scene's X/Y); a variable or coordinate the table does not know
is labelled by its long_name (up to a definition after " = " or a remark in parentheses) or name, plus its
CF units where they are not "1" (axis_label).

matplotlib (the `figures` extra) is imported only inside the drawing functions, so that importing this
module, and the command line that does, costs nothing: the caller checks for it first
(storage.outputs.missing_figures_extra). Figures are plain matplotlib Figures on the Agg canvas (no
pyplot state, no display); `save` writes one as PNG atomically.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from friction_sweep import ties
from friction_sweep.codes import Regime
from friction_sweep.storage.schema import HISTORY_DIM

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

KINDS = ("map", "curves", "phase", "orbit")
#: curves drawn when none are chosen with --sel (evenly spread over the force ratios)
MAX_CURVES = 8
DPI = 150
GRID = ("force_ratio", "frequency_ratio")
#: a cube at constant base acceleration: the physical dims (storage.schema.ACCELERATION_DIMS), beta a 2-D
#: coordinate on them
PHYSICAL_GRID = ("friction_force", "frequency")
#: the variable each kind draws (orbit: the time history's)
NEEDS = {"map": ("regime",), "curves": ("transmissibility",), "phase": ("phase",),
         "orbit": ("history_time", "history_displacement")}
CURVE_VARIABLE = {"curves": "transmissibility", "phase": "phase"}
#: face colour of each regime, by its flag meaning (the paper's greys; continuous white)
REGIME_COLORS = {"stuck": "0.6", "stick_slip": "#f6b26b", "continuous": "#cfe2f3", "unbounded": "tab:red",
                 "unsettled": "black"}
#: markers of the point regimes in the curves' strip
POINT_MARKERS = {Regime.UNBOUNDED: ("x", "tab:red"), Regime.UNSETTLED: ("o", "black")}


class PlotError(ValueError):
    """Why the cube cannot be drawn as asked (a one-line reason for the command to report)."""


class Axis(NamedTuple):
    """What one grid dimension is drawn against: the dimension's ratio or a physical coordinate on it."""

    dim: str
    name: str  # the coordinate drawn along
    values: np.ndarray
    ratio: np.ndarray  # the ratio along the dimension, point by point
    label: str

    def from_ratio(self, ratio) -> np.ndarray:
        """Ratio values in this axis's units (identity on the ratio itself; a physical coordinate is
        interpolated linearly between grid points and extrapolated along the end segments)."""
        ratio = np.asarray(ratio, dtype=float)
        return ratio if self.values is self.ratio else _interp(ratio, self.ratio, self.values)


def axis_label(da) -> str:
    """A variable's or coordinate's axis label: its long_name (else its name), up to a definition after
    " = " or a remark in parentheses, plus its CF units in brackets unless they are "1"."""
    text = str(da.attrs.get("long_name") or da.name)
    text = text.split(" = ")[0].split(" (")[0].strip() or str(da.name)
    units = str(da.attrs.get("units", "1")).strip()
    return text if units in ("", "1") else f"{text} [{units}]"


#: the scene's length unit L in mathtext, as a divisor: the static deflection F0/k under a force, the base
#: amplitude Y otherwise
LENGTH = {"force": "(F_0/k)", "base": "Y", "joined": "Y"}
#: what drives the system, in words
DRIVE = {"force": "the force", "base": "the base", "joined": "the base"}
#: mathtext axis labels of what the quick looks draw ({L}: the scene's LENGTH, {drive}: DRIVE's words); a
#: name not here is labelled by axis_label
LABELS: dict[str, str | dict[str, str]] = {
    "frequency_ratio": r"frequency ratio $r = \omega/\omega_n$",
    "force_ratio": {"force": r"force ratio $\beta = F_\mu/F_0$", "base": r"force ratio $\beta = F_\mu/(kY)$",
                    "joined": r"force ratio $\beta = F_\mu/(kY)$"},
    "frequency": r"frequency $f$ [Hz]",
    "friction_force": r"friction force $F_\mu$ [N]",
    "transmissibility": {"force": r"first-harmonic amplitude $|X|/(F_0/k)$",
                         "base": r"first-harmonic transmissibility $|X|/|Y|$",
                         "joined": r"first-harmonic transmissibility $|X|/|Y|$"},
    "phase": r"first-harmonic phase lag $\varphi$ of $x$ behind {drive} [°]",
    "history_time": r"time $t/T$ [forcing periods]",
    "history_physical_time": r"time $t$ [s]",
    "history_displacement": r"displacement $x/{L}$",
    "history_physical_displacement": r"displacement $x$ [m]",
    "history_relative_displacement": {"force": r"displacement $x/(F_0/k)$", "base": r"displacement $x/Y$",
                                      "joined": r"relative displacement $z/Y$, $z = x - y$"},
    "history_relative_velocity": {"force": r"velocity $\dot{{x}}/(\omega_n F_0/k)$",
                                  "base": r"velocity $\dot{{x}}/(\omega_n Y)$",
                                  "joined": r"relative velocity $\dot{{z}}/(\omega_n Y)$"},
}
#: the short symbol of a force axis, for the curves' legend and the strip (units added where physical)
SYMBOLS = {"force_ratio": r"$\beta$", "friction_force": r"$F_\mu$", "frequency_ratio": "$r$", "frequency": "$f$"}


def label(ds: xr.Dataset, name: str) -> str:
    """The axis label of variable or coordinate `name` in the cube's scene: LABELS, else axis_label."""
    excitation = str(ds.attrs.get("excitation", "base"))
    given = LABELS.get(name)
    entry = given.get(excitation) if isinstance(given, dict) else given
    if entry is None:
        return axis_label(ds[name])
    return entry.format(L=LENGTH.get(excitation, "Y"), drive=DRIVE.get(excitation, DRIVE["base"]))


def symbol(ds: xr.Dataset, name: str) -> tuple[str, str]:
    """(symbol, units) of a grid axis: ("$F_\\mu$", "N"), ("$\\beta$", ""); a name without a symbol: its
    label, and no units (the label has them)."""
    if name not in SYMBOLS:
        return label(ds, name), ""
    units = str(ds[name].attrs.get("units", "1")).strip()
    return SYMBOLS[name], "" if units == "1" else units


def grid_dims(ds: xr.Dataset) -> tuple[str, str]:
    """The cube's (force, frequency) dims: the ratios, or the physical ones of a constant-acceleration cube."""
    for dims in (GRID, PHYSICAL_GRID):
        if all(d in ds.dims for d in dims):
            return dims
    raise PlotError(f"not a friction_sweep cube: no dimension {', '.join(n for n in GRID if n not in ds.dims)}")


def grid_axis(ds: xr.Dataset, dim: str) -> Axis:
    """The axis of grid dimension `dim`: the first non-dimension coordinate along it that has physical
    units (not "1") and finite, strictly monotonic values, else the dimension's own coordinate. A physical
    dimension (constant acceleration) is its own axis, its ratio the 1-D ratio coordinate on it, if any."""
    if dim in PHYSICAL_GRID:
        values = ds[dim].values.astype(float)
        ratios = [c for n, c in ds.coords.items() if n in GRID and c.dims == (dim,)]
        return Axis(dim, dim, values, ratios[0].values.astype(float) if ratios else values, label(ds, dim))
    ratio = ds[dim].values.astype(float)
    for name, coord in ds.coords.items():
        if name == dim or coord.dims != (dim,) or str(coord.attrs.get("units", "1")).strip() in ("", "1"):
            continue
        try:
            values = coord.values.astype(float)
        except (TypeError, ValueError):
            continue
        steps = np.diff(values)
        if np.isfinite(values).all() and (np.all(steps > 0) or np.all(steps < 0)):
            return Axis(dim, str(name), values, ratio, label(ds, str(name)))
    return Axis(dim, dim, ratio, ratio, label(ds, dim))


def _interp(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """Piecewise-linear y(x) through (xp, fp), extended along the end segments (xp monotonic)."""
    if xp.size == 0:
        return np.full_like(x, np.nan, dtype=float)
    if xp.size == 1:
        return x * (fp[0] / xp[0]) if xp[0] != 0 else np.full_like(x, np.nan, dtype=float)
    if xp[0] > xp[-1]:
        xp, fp = xp[::-1], fp[::-1]
    y = np.interp(x, xp, fp)
    lo, hi = x < xp[0], x > xp[-1]
    y[lo] = fp[0] + (x[lo] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
    y[hi] = fp[-1] + (x[hi] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return y


# --- what to draw: the kind, the selection ---------------------------------------------------------------


def default_kind(ds: xr.Dataset, sel: Sequence[str] = ()) -> str:
    """What to draw when no kind is given: with --sel, `orbit` for a history's index, else `curves`
    (a selection chooses curves or an orbit, never part of a map); without, `map` for a plane (more
    than one force and frequency ratio) that has regimes, else `curves`."""
    names = {name for name, _ in parse_selection(sel)}
    if names:
        return "orbit" if HISTORY_DIM in names else "curves"
    plane = any(all(ds.sizes.get(dim, 0) > 1 for dim in dims) for dims in (GRID, PHYSICAL_GRID))
    return "map" if plane and "regime" in ds else "curves"


def default_output(result: str | os.PathLike[str]) -> Path:
    """RESULT with the suffix .png, beside it (results/demo.h5 -> results/demo.png)."""
    return Path(result).with_suffix(".png")


def parse_selection(items: Sequence[str]) -> list[tuple[str, str]]:
    """`NAME=VALUE` items as (name, value text); PlotError for an item without a name and a value."""
    pairs = []
    for item in items:
        name, eq, value = item.partition("=")
        if not eq or not name.strip() or not value.strip():
            raise PlotError(f"--sel {item!r}: expected NAME=VALUE (e.g. force_ratio=0.3)")
        pairs.append((name.strip(), value.strip()))
    return pairs


def selection_names(ds: xr.Dataset, kind: str) -> tuple[str, ...]:
    """The --sel names that apply to `kind` for this cube (the dims and coordinates that choose what is drawn)."""
    force, frequency = grid_dims(ds)
    if kind in CURVE_VARIABLE:
        dims: tuple[str, ...] = (force,)
    elif kind == "orbit":
        dims = (HISTORY_DIM, frequency, force)
    else:
        return ()
    names = [d for d in dims if d in ds.dims]
    names += [str(n) for n, c in ds.coords.items() if len(c.dims) == 1 and c.dims[0] in dims and n not in names]
    return tuple(names)


def _selection(ds: xr.Dataset, kind: str, items: Sequence[str]) -> dict[str, list[float]]:
    """The --sel values by name, checked against the cube and the kind (PlotError naming what is wrong)."""
    known = sorted({*map(str, ds.dims), *map(str, ds.coords)})
    applies = selection_names(ds, kind)
    chosen: dict[str, list[float]] = {}
    for name, text in parse_selection(items):
        if name not in known:
            raise PlotError(f"--sel {name}={text}: the cube has no dimension or coordinate {name!r} "
                            f"(it has {', '.join(known)})")
        if name not in applies:
            what = f"it applies to {', '.join(applies)}" if applies else "it draws the whole cube"
            raise PlotError(f"--sel {name}={text} does not apply to --kind {kind} ({what})")
        try:
            value = int(text) if name == HISTORY_DIM else float(text)
        except ValueError:
            need = "a whole number (a history's index)" if name == HISTORY_DIM else "a number"
            raise PlotError(f"--sel {name}={text}: {text!r} is not {need}") from None
        if not math.isfinite(value):
            raise PlotError(f"--sel {name}={text}: the value must be finite")
        chosen.setdefault(name, []).append(value)
    return chosen


def _nearest(values: np.ndarray, target: float) -> int:
    """Index of the value nearest to `target` (the first of a tie), as xarray's sel(method="nearest")."""
    return int(np.nanargmin(np.abs(values - target)))


# --- drawing -------------------------------------------------------------------------------------------


def draw(ds: xr.Dataset, kind: str | None = None, sel: Sequence[str] = (), yscale: str = "auto") -> Figure:
    """The quick look of `kind` (default: default_kind) with the --sel items `sel` and the curves' y scale
    `yscale` (YSCALES); PlotError where the cube cannot be drawn so."""
    kind = kind or default_kind(ds, sel)
    if kind not in KINDS:
        raise PlotError(f"unknown kind {kind!r} (kinds: {', '.join(KINDS)})")
    grid_dims(ds)  # PlotError where the cube has no grid
    if kind == "orbit" and (HISTORY_DIM not in ds.dims or any(n not in ds for n in NEEDS["orbit"])):
        raise PlotError("--kind orbit: the cube holds no time history (history_* variables); add "
                        "time_history to the spec's outputs (time_history: {points: [[r, beta]]})")
    lacking = [n for n in NEEDS[kind] if n not in ds]
    if lacking:
        raise PlotError(f"--kind {kind} needs the variable {', '.join(lacking)}, which the cube lacks "
                        f"(it has {', '.join(map(str, ds.data_vars))}); add it to the spec's outputs")
    if yscale not in YSCALES:
        raise PlotError(f"unknown y scale {yscale!r} (scales: {', '.join(YSCALES)})")
    if yscale == "log" and kind != "curves":
        raise PlotError(f"--yscale log applies to --kind curves (amplitudes); --kind {kind} draws "
                        + {"map": "force ratios from 0", "phase": "phase lags, which change sign",
                           "orbit": "displacements, which change sign"}[kind])
    chosen = _selection(ds, kind, sel)
    if kind == "map":
        return draw_map(ds)
    if kind == "orbit":
        return draw_orbit(ds, history_index(ds, chosen))
    return draw_curves(ds, CURVE_VARIABLE[kind], curve_indices(ds, chosen), yscale)


def save(fig: Figure, path: str | os.PathLike[str]) -> Path:
    """Write `fig` as PNG to `path` atomically (storage.atomic): the whole picture or nothing."""
    from friction_sweep.storage import atomic

    return atomic.write(path, lambda fh: fig.savefig(fh, format="png", dpi=DPI))


def _figure(nrows: int = 1, ncols: int = 1, size=(7.0, 4.6), **gridspec) -> tuple[Figure, Any]:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)  # the Agg backend, whatever pyplot's is: no display needed
    axes = fig.subplots(nrows, ncols, squeeze=False, gridspec_kw=gridspec or None)
    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
    return fig, axes


class Scene(NamedTuple):
    """The cube's scene as the drawings need it: its excitation and effects (their plain values where off)."""

    excitation: str
    damping: float  # zeta
    damper: str | None  # where the dashpot sits (catalogue.EFFECTS places), None without one
    static_ratio: float  # mu_s / mu_k
    contact_stiffness: float  # kappa = k_t / k; 0: a rigid contact

    @property
    def plain(self) -> bool:
        """Den Hartog's model: no dashpot, static = kinetic friction, a rigid contact."""
        return self.damping == 0.0 and self.static_ratio == 1.0 and self.contact_stiffness == 0.0


def scene(ds: xr.Dataset) -> Scene:
    """The cube's excitation and the effects its method_settings record (read by the one bounded reader,
    storage.attributes; the plain model where unreadable: open_cube refuses such a cube, a Dataset from
    elsewhere is drawn without them)."""
    from friction_sweep.catalogue import EFFECTS, effect_place, effect_value
    from friction_sweep.storage import attributes

    excitation = str(ds.attrs.get("excitation", "base"))
    try:
        given = attributes.method_settings(ds.attrs)["effects"]
        values = {name: effect_value(given, name) for name in EFFECTS}
        damper = effect_place(excitation, given, "viscous_damping") if values["viscous_damping"] > 0 else None
    except (attributes.BadAttribute, TypeError, ValueError, KeyError, StopIteration):
        values, damper = {name: effect.off for name, effect in EFFECTS.items()}, None
    return Scene(excitation, values["viscous_damping"], damper, values["static_friction_ratio"],
                 values["contact_stiffness"])


def effect_phrases(sc: Scene) -> list[str]:
    """What the title says of the scene's effects: each effect the cube has, or that it has none."""
    phrases = []
    if sc.damping > 0.0:
        phrases.append(rf"viscous damping $\zeta$ = {sc.damping:g} (dashpot to {sc.damper})")
    if sc.static_ratio != 1.0:
        phrases.append(rf"static friction $\mu_s/\mu_k$ = {sc.static_ratio:g}")
    if sc.contact_stiffness > 0.0:
        phrases.append(rf"contact stiffness $\kappa = k_t/k$ = {sc.contact_stiffness:g}")
    return phrases or ["no effects (undamped, rigid contact, static = kinetic friction)"]


def title_phrases(ds: xr.Dataset, what: str) -> list[str]:
    """The title's phrases: what is drawn, the scene and method, then the effects."""
    sc = scene(ds)
    effects = effect_phrases(sc)
    return [f"{what};", f"{sc.excitation} excitation, method {ds.attrs.get('method', '?')};",
            *[f"{p}," for p in effects[:-1]], effects[-1]]


#: the title's width at most, as a share of the figure's (room for the layout's margins)
TITLE_WIDTH = 0.96


def fit_title(fig: Figure, phrases: Sequence[str], fontsize: float = 10.0):
    """The figure's title (suptitle) from `phrases`, joined by spaces and broken between phrases so that
    every line fits inside TITLE_WIDTH of the figure's width (a phrase wider than that alone gets a line
    of its own). Returns the Text."""
    title = fig.suptitle("", fontsize=fontsize)
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]  # the Agg canvas (_figure)
    room = TITLE_WIDTH * fig.bbox.width

    def width(text: str) -> float:
        title.set_text(text)
        return float(title.get_window_extent(renderer).width)

    lines: list[str] = []
    for phrase in phrases:
        if lines and width(f"{lines[-1]} {phrase}") <= room:
            lines[-1] = f"{lines[-1]} {phrase}"
        else:
            lines.append(phrase)
    title.set_text("\n".join(lines))
    return title


def _wrapped(label: str, width: int = 42) -> str:
    """A long axis label on two or more lines, broken at spaces outside mathtext ($...$)."""
    words: list[str] = []
    for i, part in enumerate(label.split("$")):
        if i % 2:  # inside $...$: one unbreakable word, glued to its neighbours
            words[-1:] = [(words[-1] if words else "") + f"${part}$"]
        else:
            pieces = part.split(" ")
            if words:
                words[-1] += pieces[0]
                pieces = pieces[1:]
            words += pieces
    lines: list[str] = []
    for word in (w for w in words if w):
        length = len(lines[-1].replace("$", "")) if lines else 0
        if lines and length + 1 + len(word.replace("$", "")) <= width:
            lines[-1] += " " + word
        else:
            lines.append(word)
    return "\n".join(lines) or label


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges halfway between centres (half a step beyond the ends; +-5 % around a single one),
    never below 0 where the centres are not (ratios, frequencies and forces are not negative)."""
    c = np.asarray(centres, dtype=float)
    if c.size == 1:
        half = 0.05 * abs(c[0]) or 0.5
        edges = np.array([c[0] - half, c[0] + half])
    else:
        mids = 0.5 * (c[1:] + c[:-1])
        edges = np.concatenate([[c[0] - (mids[0] - c[0])], mids, [c[-1] + (c[-1] - mids[-1])]])
    if c.min() >= 0.0:
        edges = np.maximum(edges, 0.0)
    return edges


# --- map -----------------------------------------------------------------------------------------------


def draw_map(ds: xr.Dataset) -> Figure:
    """`regime` over (r, beta) with a legend from its flag_meanings, and the theory's boundaries."""
    force, frequency = grid_dims(ds)
    x, y = grid_axis(ds, frequency), grid_axis(ds, force)
    fig, axes = _figure(size=(7.6, 4.8))
    ax = axes[0, 0]
    patches = regime_mesh(ax, x.values, y.values, ds["regime"].transpose(force, frequency), "regime")
    _draw_boundaries(ax, ds, x, _force_axis_of(ds, x, y))
    lines, _ = ax.get_legend_handles_labels()
    if not lines:  # say so, rather than leave the reader looking for them
        from matplotlib.lines import Line2D

        lines = [Line2D([], [], ls="none", label="no closed-form boundary\nholds for these effects")]
    ax.legend(handles=lines + patches, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, framealpha=0.95)
    ax.set(xlabel=_wrapped(x.label, 60), ylabel=_wrapped(y.label))
    fit_title(fig, title_phrases(ds, "regime map"))
    return fig


def regime_mesh(ax: Axes, x: np.ndarray, y: np.ndarray, regime: xr.DataArray, gid: str) -> list:
    """`regime` (2-D, rows along y, columns along x) as cells coloured by its flag meanings (REGIME_COLORS),
    the axes' limits set to the cells' edges; returns a legend patch per code present, with its count."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    values = np.asarray(regime.attrs.get("flag_values", [int(c) for c in Regime])).astype(int).ravel()
    meanings = str(regime.attrs.get("flag_meanings", " ".join(c.name.lower() for c in Regime))).split()
    if len(meanings) != len(values):
        meanings = [f"code {v}" for v in values]
    codes = regime.values.astype(int)
    # colour by position in flag_values: any codes the cube declares; none else (left blank)
    position = np.full(codes.shape, np.nan)
    for i, v in enumerate(values):
        position[codes == v] = i
    colours = [REGIME_COLORS.get(m, f"C{i}") for i, m in enumerate(meanings)]
    ax.pcolormesh(_edges(x), _edges(y), np.ma.masked_invalid(position),
                  cmap=ListedColormap(colours), norm=BoundaryNorm(np.arange(len(values) + 1) - 0.5, len(values)),
                  shading="flat", rasterized=True, gid=gid)
    xe, ye = _edges(x), _edges(y)
    ax.set_xlim(float(xe[0]), float(xe[-1]))
    ax.set_ylim(float(ye[0]), float(ye[-1]))  # first: a boundary outside these is left out of the legend
    return [Patch(facecolor=colours[i], edgecolor="0.5", label=f"{m.replace('_', '-')} ({int((codes == v).sum())})")
            for i, (v, m) in enumerate(zip(values, meanings, strict=True)) if (codes == v).any()]


def _force_axis_of(ds: xr.Dataset, x: Axis, y: Axis):
    """(r, beta) -> the force axis's value: beta itself or its coordinate's units; at constant
    acceleration F = beta F_k(r), F_k falling as 1/r^2 (read from the cube's own friction_force / beta)."""
    if y.dim not in PHYSICAL_GRID:
        return lambda r, beta: y.from_ratio(beta)
    beta = ds["force_ratio"].transpose(*grid_dims(ds)).values.astype(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        fk_r2 = y.values[:, None] / beta * x.ratio[None, :] ** 2  # F_k r^2, a constant
    c = float(np.nanmedian(fk_r2[np.isfinite(fk_r2) & (beta > 0)])) if (beta > 0).any() else math.nan
    return lambda r, b: np.asarray(b, dtype=float) * c / np.asarray(r, dtype=float) ** 2


def boundaries(sc: Scene) -> tuple[str, ...]:
    """The theory's boundaries that hold for the scene (docs/equations.md §2, §6, §7), by gid:

        continuous_limit  Den Hartog's beta*(r) (r^2 beta* joined): the plain model only; a dashpot, static
                          above kinetic friction (a reversal may stick) or a contact spring each move it
        stuck_limit       no motion from rest while A(r) <= beta_s (A the forcing amplitude: 1, r^2 joined,
                          sqrt(1 + (2 zeta r)^2) for the base scene's dashpot to the base): a rigid contact
                          only (on a contact spring the mass moves while the slider holds)
        slider_stuck_limit  the Jenkins contact's slider never slips where the forced motion on the held
                          slider, an oscillator of stiffness 1 + kappa, loads the contact spring less than
                          the friction: beta >= kappa A / |1 + kappa - r^2| (§7, "a slider that never slips":
                          undamped, static = kinetic friction, where the state does not depend on the start)
        resonance         r = 1 unbounded for b <= pi/4 (and beta_s < A(1) = 1: else it never moves): without
                          damping only, rigid or Jenkins contact (§7: only r = 1 grows without bound)
    """
    jenkins = sc.contact_stiffness > 0.0
    holds = {"continuous_limit": sc.plain, "stuck_limit": not jenkins,
             "slider_stuck_limit": jenkins and sc.damping == 0.0 and sc.static_ratio == 1.0,
             "resonance": sc.damping == 0.0}
    return tuple(name for name, ok in holds.items() if ok)


def _draw_boundaries(ax: Axes, ds: xr.Dataset, x: Axis, to_y) -> None:
    """The theory's boundaries that hold for the cube's scene (boundaries), in the scene's force-ratio
    convention, drawn in the axes' units (`to_y`: (r, beta) -> the force axis)."""
    from friction_sweep.theory import scenes

    sc = scene(ds)
    drawn = boundaries(sc)
    r = x.ratio
    if "continuous_limit" in drawn:
        if "continuous_limit" in ds:
            limit = ds["continuous_limit"].values.astype(float)
            source = ""
        else:  # a cube without it: the same closed form, for the cube's excitation
            from friction_sweep.methods.theory import continuous_limit

            limit = continuous_limit(sc.excitation, r)
            source = ", computed"
        symbol = r"r^2\beta^*(r)" if sc.excitation == "joined" else r"\beta^*(r)"
        ax.plot(x.values, to_y(r, limit), "--", color="k", lw=1.4, gid="continuous_limit",
                label=rf"continuous below: ${symbol}$ (Den Hartog{source})")
    if "stuck_limit" in drawn:  # no motion from rest where the force's swing A stays inside the static band
        fine = np.linspace(r.min(), r.max(), 400) if r.size > 1 else r
        amplitude, _ = scenes.kernel_forcing(sc.excitation, fine, sc.damping, sc.damper)
        stuck = amplitude / sc.static_ratio
        if scenes.spring_parallel(sc.excitation, sc.damper):
            where = r"\sqrt{1 + (2\zeta r)^2}"
        else:
            where = "r^2" if sc.excitation == "joined" else "1"
        if sc.static_ratio != 1.0:
            where += rf"\,/\,{sc.static_ratio:g}"
        if np.nanmin(to_y(fine, stuck)) <= ax.get_ylim()[1]:  # else above the plot: not in its legend
            ax.plot(x.from_ratio(fine), to_y(fine, stuck), "-", color="k", lw=1.4, gid="stuck_limit",
                    label=rf"stuck above: $\beta = {where}$ (no motion from rest)")
    if "slider_stuck_limit" in drawn:
        fine = np.linspace(r.min(), r.max(), 400) if r.size > 1 else r
        kappa = sc.contact_stiffness
        with np.errstate(divide="ignore"):  # r = sqrt(1 + kappa): the held oscillator's resonance, never held
            held = kappa * scenes.forcing_amplitude(sc.excitation, fine) / np.abs(1.0 + kappa - fine**2)
        held[~np.isfinite(held)] = np.nan
        force = r"\kappa r^2" if sc.excitation == "joined" else r"\kappa"
        ax.plot(x.from_ratio(fine), to_y(fine, held), "-.", color="k", lw=1.4, gid="slider_stuck_limit",
                label=rf"slider stuck above: $\beta = {force}/|1 + \kappa - r^2|$")
    # the undamped resonance: unbounded at r = 1 for friction ratios b <= pi/4 (b = beta/A, A(1) = 1) that
    # move from rest (beta_s < 1)
    top = min(ties.RESONANCE_FRICTION_LIMIT, 1.0 / sc.static_ratio)
    if "resonance" in drawn and r.min() <= 1.0 <= r.max() and to_y(np.ones(1), np.full(1, top))[0] >= ax.get_ylim()[0]:
        bound = r"\pi/4" if top == ties.RESONANCE_FRICTION_LIMIT else f"{top:.3g}"
        x1 = float(x.from_ratio(np.array([1.0]))[0])
        ax.plot([x1, x1], to_y(np.array([1.0, 1.0]), np.array([0.0, top])), "-", color="tab:red", lw=2.0,
                gid="resonance", label=rf"unbounded: $r = 1$, $\beta \leq {bound}$")


# --- curves --------------------------------------------------------------------------------------------


def curve_indices(ds: xr.Dataset, chosen: dict[str, list[float]]) -> list[int]:
    """Force-ratio indices to draw: the nearest to each chosen value (force_ratio or a coordinate on
    it), else at most MAX_CURVES spread evenly from the first to the last."""
    n = ds.sizes[grid_dims(ds)[0]]
    picked: set[int] = set()
    for name, targets in chosen.items():
        values = ds[name].values.astype(float)
        picked.update(_nearest(values, t) for t in targets)
    if picked:
        return sorted(picked)
    if n <= MAX_CURVES:
        return list(range(n))
    return sorted({int(i) for i in np.rint(np.linspace(0, n - 1, MAX_CURVES))})


def regime_runs(codes: np.ndarray) -> list[tuple[int, int, int]]:
    """Contiguous runs (code, first index, last index + 1) of equal codes along a line."""
    codes = np.asarray(codes).astype(int)
    runs = []
    start = 0
    for i in range(1, codes.size + 1):
        if i == codes.size or codes[i] != codes[start]:
            runs.append((int(codes[start]), start, i))
            start = i
    return runs


def draw_curves(ds: xr.Dataset, var: str, indices: Sequence[int], yscale: str = "auto") -> Figure:
    """`var` against r, one curve per force-ratio index, on a y axis `yscale` (choose_yscale); under it,
    where the cube has regimes, a strip with a row per curve (_regime_strip)."""
    force, frequency = grid_dims(ds)
    x, f = grid_axis(ds, frequency), grid_axis(ds, force)
    data = ds[var].transpose(force, frequency)
    n = len(indices)
    if "regime" in ds:
        fig, axes = _figure(2, 1, size=(7.6, 5.2 + 0.18 * n), height_ratios=[4.0, 0.8 + 0.25 * n], hspace=0.02)
        ax = axes[0, 0]
    else:
        fig, axes = _figure(size=(7.6, 5.0))
        ax = axes[0, 0]
    colours = [_viridis(k, n) for k in range(n)]
    sym, units = symbol(ds, f.name)
    for row, (i, colour) in enumerate(zip(indices, colours, strict=True)):
        ax.plot(x.values, data.values[i], "-", color=colour, marker=".", ms=3, gid=f"curve {row}",
                label=f"{sym} = {f.values[i]:g}" + (f" {units}" if units else ""))
    moving = _second_states(ds, var, indices)
    for row, (values, colour) in enumerate(zip(moving, colours, strict=True)):
        if np.isfinite(values).any():
            ax.plot(x.values, values, "--", color=colour, marker="o", ms=3, mfc="none", gid=f"moving {row}")
    handles, _ = ax.get_legend_handles_labels()
    if np.isfinite(moving).any():
        from matplotlib.lines import Line2D

        handles.append(Line2D([], [], ls="--", marker="o", mfc="none", ms=3, color="0.3", gid="moving key",
                              label="dashed: a second state\n(from a moving start)"))
    ax.set_yscale(choose_yscale(data.values[list(indices)], yscale) if var in LOG_VARIABLES else "linear")
    excitation = scene(ds).excitation
    scale = length_scale(ds) if var == "transmissibility" else None  # what the ratio is of, in mm
    unit = "" if scale is None else f" (${LENGTH[excitation].strip('()')}$ = {scale * 1e3:.4g} mm)"
    ax.set_ylabel(_wrapped(label(ds, var) + unit))
    what = {"transmissibility": "amplitude" if excitation == "force" else "transmissibility",
            "phase": "phase lag"}.get(var, var)
    phrases = title_phrases(ds, f"{what} curves")
    if n != ds.sizes[force]:
        phrases.append(f"({n} of {ds.sizes[force]} force ratios; choose with --sel {force}=...)")
    fit_title(fig, phrases)
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    ax.set_xlim(*_edges(x.values)[[0, -1]])
    if "regime" not in ds:
        ax.set_xlabel(x.label)
        return fig
    ax.tick_params(labelbottom=False)
    strip = axes[1, 0]
    strip.sharex(ax)
    regime = ds["regime"].transpose(force, frequency).values.astype(int)[list(indices)]
    _regime_strip(strip, x, regime, colours)
    strip.set(xlabel=x.label, ylim=(n - 0.5, -0.5), yticks=range(n), yticklabels=[f"{f.values[i]:g}" for i in indices])
    strip.set_ylabel(f"{sym} [{units}]" if units else sym, fontsize=8)
    return fig


def _second_states(ds: xr.Dataset, var: str, indices: Sequence[int]) -> np.ndarray:
    """Rows of `var` from the moving start (`var` + MOVING_SUFFIX, where static exceeds kinetic friction) at
    the points the cube counts two steady states (`steady_states` 2), NaN elsewhere and everywhere without
    them: a second state that the curve from rest hides."""
    from friction_sweep.storage.schema import MOVING_SUFFIX

    force, frequency = grid_dims(ds)
    shape = (len(indices), ds.sizes[frequency])
    if var + MOVING_SUFFIX not in ds or "steady_states" not in ds:
        return np.full(shape, np.nan)
    rows = list(indices)
    moving = ds[var + MOVING_SUFFIX].transpose(force, frequency).values[rows].astype(float)
    two = ds["steady_states"].transpose(force, frequency).values[rows] == 2
    return np.where(two, moving, np.nan)


#: the curves' variables a log axis suits (amplitudes: positive; a phase lag changes sign)
LOG_VARIABLES = ("transmissibility",)
#: YSCALES: what --yscale takes; auto draws a log axis where the curves' values span more than WIDE_RANGE
YSCALES = ("auto", "linear", "log")
#: the spread (largest finite value over the median positive one) beyond which auto draws a log axis: a
#: frictionless peak of 1000 beside damped curves near 1 would flatten them on a linear one
WIDE_RANGE = 30.0


def choose_yscale(values: np.ndarray, yscale: str = "auto") -> str:
    """The y scale of curves through `values`: `yscale` where "linear" or "log", else (auto) "log" where the
    largest finite value exceeds WIDE_RANGE times the median positive one, "linear" otherwise."""
    if yscale != "auto":
        return yscale
    v = np.asarray(values, dtype=float)
    positive = v[np.isfinite(v) & (v > 0.0)]
    if positive.size == 0 or (v[np.isfinite(v)] < 0.0).any():
        return "linear"
    return "log" if positive.max() > WIDE_RANGE * float(np.median(positive)) else "linear"


def _regime_strip(strip: Axes, x: Axis, regime: np.ndarray, colours: Sequence) -> None:
    """One row per curve (regime[row] along r): stick-slip spans shaded in the curve's colour, stuck
    spans grey, both running halfway to the neighbouring points; unbounded and unsettled points marked.
    Each row's artists carry the gid "<regime> <row>"."""
    from matplotlib.artist import Artist
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    edges = _edges(x.values)
    for row, (codes, colour) in enumerate(zip(regime, colours, strict=True)):
        for code, face in ((Regime.STICK_SLIP, colour), (Regime.STUCK, "0.55")):
            bars = [(edges[a], edges[b] - edges[a]) for c, a, b in regime_runs(codes) if c == code]
            if bars:
                strip.broken_barh(bars, (row - 0.4, 0.8), facecolors=face, alpha=0.6, lw=0,
                                  gid=f"{code.name.lower()} {row}")
        for code, (marker, mcolour) in POINT_MARKERS.items():
            at = codes == code
            if at.any():
                strip.plot(x.values[at], np.full(int(at.sum()), row), marker, color=mcolour, ms=6, ls="none",
                           gid=f"{code.name.lower()} {row}")
    strip.grid(False)
    drawn = set(np.unique(regime).tolist())
    keys: list[Artist] = []
    if Regime.STICK_SLIP in drawn:
        keys.append(Patch(facecolor=colours[0], alpha=0.6, label="stick-slip (curve's colour)"))
    if Regime.STUCK in drawn:
        keys.append(Patch(facecolor="0.55", alpha=0.6, label="stuck"))
    keys += [Line2D([], [], marker=m, color=c, ls="none", label=code.name.lower())
             for code, (m, c) in POINT_MARKERS.items() if code in drawn]
    if keys:
        strip.legend(handles=keys, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7)


def _viridis(k: int, n: int):
    from matplotlib import colormaps

    return colormaps["viridis"](0.85 * k / max(n - 1, 1))


# --- orbit ---------------------------------------------------------------------------------------------


def history_index(ds: xr.Dataset, chosen: dict[str, list[float]]) -> int:
    """The stored orbit to draw: --sel history_point=K, else the one nearest the chosen frequency and force
    ratios (physical coordinates converted to ratios), else the first."""
    n = ds.sizes[HISTORY_DIM]
    for name, values in chosen.items():
        if len(values) > 1:
            raise PlotError(f"--sel {name}: --kind orbit draws one orbit; give {name} once")
    if HISTORY_DIM in chosen:
        if len(chosen) > 1:
            raise PlotError(f"--sel {HISTORY_DIM}=K picks the orbit by itself; leave out the other --sel")
        k = int(chosen[HISTORY_DIM][0])
        if not 0 <= k < n:
            raise PlotError(f"--sel {HISTORY_DIM}={k}: the cube holds histories 0..{n - 1}")
        return k
    if not chosen:
        return 0
    distance = np.zeros(n)
    force, frequency = grid_dims(ds)
    for dim, stored in ((frequency, "history_frequency_ratio"), (force, "history_force_ratio")):
        axis = grid_axis(ds, dim)
        for name, values in chosen.items():
            if name == dim or ds[name].dims == (dim,):
                if stored not in ds:
                    raise PlotError(f"--sel {name}: the cube does not record its histories' {dim} ({stored})")
                if dim == "friction_force":  # beta varies with the frequency: no one ratio to compare
                    raise PlotError(f"--sel {name}: at constant acceleration pick the history by {HISTORY_DIM}=K or "
                                    "by its frequency")
                target = values[0] if name == dim else float(
                    _interp(np.array([values[0]]), ds[name].values.astype(float), axis.ratio)[0])
                distance += (ds[stored].values.astype(float) - target) ** 2
    return int(np.nanargmin(distance)) if np.isfinite(distance).any() else 0


def physical_system(ds: xr.Dataset):
    """The physical system the cube records (storage.physical.PhysicalMap), None where it records none or
    not readably."""
    from friction_sweep.storage import physical

    try:
        return physical.from_attribute(ds.attrs[physical.ATTRIBUTE])
    except (KeyError, ValueError, TypeError):
        return None


def length_scale(ds: xr.Dataset) -> float | None:
    """The cube's length unit L in metres (Y, or F0/k for force) where one holds for the whole cube (not at
    constant acceleration, where Y = a / omega^2 changes along the sweep), else None."""
    system = physical_system(ds)
    if system is None or system.acceleration is not None or system.length_scale is None:
        return None
    return float(system.length_scale)


class OrbitUnits(NamedTuple):
    """How a stored orbit is drawn: dimensionless (scales 1), or in seconds and metres where the cube holds
    its physical time and displacement (`system:`), the rest scaled alike (storage.physical)."""

    physical: bool
    length: float  # m per the scene's length unit L (Y, or F0/k for force)
    velocity: float  # m/s per L omega_n
    force: float  # N per F0 (force excitation)
    frequency: float  # the orbit's forcing frequency [Hz] (NaN where unknown)
    friction_force: float  # its friction force [N] (NaN where unknown)


def orbit_units(ds: xr.Dataset, k: int) -> OrbitUnits:
    """The units history `k` is drawn in (OrbitUnits): physical where the cube holds history_physical_time
    and history_physical_displacement and records its physical system, else dimensionless."""
    dimensionless = OrbitUnits(False, 1.0, 1.0, 1.0, math.nan, math.nan)
    if not all(n in ds for n in ("history_physical_time", "history_physical_displacement", "history_frequency_ratio")):
        return dimensionless
    system = physical_system(ds)
    if system is None or system.natural_frequency is None:
        return dimensionless
    frequency = float(ds["history_frequency_ratio"].values[k]) * system.natural_frequency
    force, length = system.scales_at(frequency)
    if length is None:
        return dimensionless
    beta = float(ds["history_force_ratio"].values[k]) if "history_force_ratio" in ds else math.nan
    force = math.nan if force is None else float(force)
    return OrbitUnits(True, float(length), float(length) * 2.0 * math.pi * system.natural_frequency, force,
                      frequency, beta * force)


def draw_orbit(ds: xr.Dataset, k: int) -> Figure:
    """History `k`: response and excitation against time (a force on an axis of its own), and its phase
    plane (relative displacement against relative velocity) where the cube has them; in seconds and metres
    where the cube holds them (orbit_units)."""
    t = ds["history_time"].values[k].astype(float)
    ok = np.isfinite(t)
    if not ok.any():
        raise PlotError(f"history {k} ({_history_point(ds, k)}) holds no steady orbit")
    sc = scene(ds)
    units = orbit_units(ds, k)
    has_plane = all(n in ds for n in ("history_relative_displacement", "history_relative_velocity"))
    fig, axes = _figure(1, 2 if has_plane else 1, size=(10.0 if has_plane else 7.0, 4.6))
    ax = axes[0, 0]
    time, x = ("history_physical_time", "history_physical_displacement") if units.physical else \
        ("history_time", "history_displacement")
    ax.plot(ds[time].values[k][ok], ds[x].values[k][ok], "-", label="response $x$", gid="history_displacement")
    handles = []
    if "history_excitation" in ds:
        drive = ds["history_excitation"].values[k][ok]
        if sc.excitation == "force":  # a force, not a displacement: its own axis
            twin = ax.twinx()
            scale, what = (units.force, "force $F$ [N]") if units.physical and math.isfinite(units.force) else \
                (1.0, "force $F/F_0$")
            twin.plot(ds[time].values[k][ok], drive * scale, "--", color="C1", label="force $F$",
                      gid="history_excitation")
            twin.set_ylabel(what)
            handles = twin.get_lines()
        else:
            ax.plot(ds[time].values[k][ok], drive * units.length, "--", color="C1", label="base $y$",
                    gid="history_excitation")
    ax.set(xlabel=label(ds, time), ylabel=_wrapped(label(ds, x)))
    ax.legend(handles=[*ax.get_lines(), *handles], fontsize=8, ncols=2, loc="lower center",
              bbox_to_anchor=(0.5, 1.0))  # above the axes: over none of the curves
    if has_plane:
        q, v = ds["history_relative_displacement"].values[k], ds["history_relative_velocity"].values[k]
        plane = axes[0, 1]
        closed = np.r_[np.flatnonzero(ok), np.flatnonzero(ok)[:1]]  # the orbit repeats: back to its start
        plane.plot(q[closed] * units.length, v[closed] * units.velocity, "-", color="C2", gid="phase_plane")
        start = closed[0]  # the section: shows where the orbit starts, and a point where it never moves
        plane.plot(q[start] * units.length, v[start] * units.velocity, "o", color="C2", ms=5, gid="section",
                   label="section ($t$ = 0)")
        plane.legend(fontsize=8, loc="upper right")
        if units.physical:
            z = "z" if sc.excitation == "joined" else "x"
            relative = "relative " if sc.excitation == "joined" else ""
            xlabel, ylabel = rf"{relative}displacement ${z}$ [m]", rf"{relative}velocity $\dot{{{z}}}$ [m/s]"
        else:
            xlabel = label(ds, "history_relative_displacement")
            ylabel = label(ds, "history_relative_velocity")
        plane.set(xlabel=_wrapped(xlabel), ylabel=_wrapped(ylabel), title="phase plane")
    fit_title(fig, title_phrases(ds, f"orbit {k} of {ds.sizes[HISTORY_DIM]} at {_history_point(ds, k, units)}"))
    return fig


def _history_point(ds: xr.Dataset, k: int, units: OrbitUnits | None = None) -> str:
    """Where history `k` lies and what it is, in words: plain for a message, mathtext (with the physical
    frequency and friction force where known) for a title when `units` are given."""
    math_text = units is not None
    parts = []
    for name, plain, symbol_ in (("history_frequency_ratio", "r", "$r$"), ("history_force_ratio", "beta", r"$\beta$")):
        if name in ds:
            parts.append(f"{symbol_ if math_text else plain} = {float(ds[name].values[k]):g}")
    if units is not None and units.physical:
        physical_values = ((units.frequency, "$f$", "Hz"), (units.friction_force, r"$F_\mu$", "N"))
        parts += [f"{sym} = {value:.3g} {unit}" for value, sym, unit in physical_values if math.isfinite(value)]
    if "history_regime" in ds:
        from friction_sweep.codes import name_of

        name = name_of(Regime, int(ds["history_regime"].values[k]))
        parts.append(name.replace("_", "-") if math_text else name)
    if "history_orbit_period" in ds and ds["history_orbit_period"].values[k] > 0:  # 0: no steady state
        parts.append(f"period {float(ds['history_orbit_period'].values[k]):g}")
    return ", ".join(parts)
