"""Quick looks at a structure cube (`fsweep plot` on a cube of several masses and contacts, issue 31):

    curves   `amplitude` of each mass against the frequency, a panel per mass and a curve per friction_scale
             (at most quicklook.MAX_CURVES unless chosen), the y axis logarithmic where asked or (auto) where
             the values span more than quicklook.WIDE_RANGE, as the 1-DoF curves; under them a regime strip
             per contact, a row per curve (quicklook._regime_strip: stick-slip and stuck spans shaded,
             unbounded and unsettled points marked)
    phase    the same for `phase` (linear: a lag changes sign)
    map      `regime` of each contact over the (frequency, friction_scale) plane, a panel per contact,
             coloured by its flags (quicklook.regime_mesh) with each regime's count
    orbit    a stored time history (outputs: time_history): each mass's displacement against time, a panel
             per mass, then each contact's force against its relative displacement (its hysteresis loop, whose
             area is its friction energy per period), a panel per contact

--sel chooses: friction_scale=V (curves, phase; nearest value, repeatable), dof=NAME (curves, phase, orbit:
the masses drawn), contact=NAME (every kind: the contacts drawn), history_point=K (orbit: the stored orbit,
by default the first). The figures are the 1-DoF quick looks' kind
(quicklook._figure: Agg, no pyplot state); matplotlib is imported only inside the drawing functions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from friction_sweep import quicklook as ql
from friction_sweep.quicklook import PlotError
from friction_sweep.storage.schema import HISTORY_DIM

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

KINDS = ("map", "curves", "phase", "orbit")
PLANE = ("friction_scale", "frequency")
CURVE_VARIABLE = {"curves": "amplitude", "phase": "phase"}
NEEDS = {"map": "regime", "curves": "amplitude", "phase": "phase", "orbit": "history_displacement"}
#: which --sel names each kind takes
SELECTIONS = {"map": ("contact",), "curves": ("friction_scale", "dof", "contact"),
              "phase": ("friction_scale", "dof", "contact"), "orbit": (HISTORY_DIM, "dof", "contact")}
#: a log axis shows at most this far below the panel's largest amplitude (a mass that barely moves, a contact
#: slipping by little beside it, would otherwise squeeze the curves into the top decades; one standing still has
#: amplitude 0 and is not drawn)
FLOOR = 1e-6
LABELS: dict[str, str | dict[str, str]] = {
          "frequency": r"angular frequency $\omega$", "friction_scale": r"friction scale $s$",
          "amplitude": {"force": "first-harmonic amplitude $|X|$", "base": "transmissibility $|X|/Y$"},
          "phase": r"phase lag $\varphi$ behind the excitation [°]"}


class Choice:
    """What --sel chose: friction-scale indices, masses and contacts (None: the default)."""

    def __init__(self, ds: xr.Dataset, kind: str, items: Sequence[str]):
        self.scales: list[int] = []
        self.dofs: list[str] = []
        self.contacts: list[str] = []
        self.history = 0
        for name, text in ql.parse_selection(items):
            if name not in SELECTIONS[kind]:
                raise PlotError(f"--sel {name}={text} does not apply to --kind {kind} of a structure cube (it "
                                f"takes {', '.join(SELECTIONS[kind])})")
            if name == HISTORY_DIM:
                n = ds.sizes[HISTORY_DIM]
                if not (text.isdigit() and int(text) < n):
                    raise PlotError(f"--sel {name}={text}: the cube holds histories 0..{n - 1}")
                self.history = int(text)
                continue
            if name == "friction_scale":
                try:
                    value = float(text)
                except ValueError:
                    raise PlotError(f"--sel {name}={text}: {text!r} is not a number") from None
                if not math.isfinite(value):
                    raise PlotError(f"--sel {name}={text}: the value must be finite")
                self.scales.append(int(np.argmin(np.abs(ds[name].values - value))))
                continue
            names = [str(v) for v in ds[name].values.tolist()]
            if text not in names:
                raise PlotError(f"--sel {name}={text}: the cube has no {name} {text!r} (it has {', '.join(names)})")
            (self.dofs if name == "dof" else self.contacts).append(text)
        self.scales = sorted(set(self.scales)) or curve_indices(ds.sizes["friction_scale"])
        self.dofs = list(dict.fromkeys(self.dofs)) or [str(v) for v in ds["dof"].values.tolist()]
        self.contacts = list(dict.fromkeys(self.contacts)) or [str(v) for v in ds["contact"].values.tolist()]


def curve_indices(n: int) -> list[int]:
    """At most quicklook.MAX_CURVES friction-scale indices, spread evenly from the first to the last."""
    if n <= ql.MAX_CURVES:
        return list(range(n))
    return sorted({int(i) for i in np.rint(np.linspace(0, n - 1, ql.MAX_CURVES))})


def default_kind(ds: xr.Dataset, sel: Sequence[str] = ()) -> str:
    """As the 1-DoF rule: `orbit` with a history_point selection; `curves` with a friction_scale or dof one;
    `map` for a plane (more than one frequency and friction scale) with regimes; `curves` otherwise."""
    names = {name for name, _ in ql.parse_selection(sel)}
    if HISTORY_DIM in names:
        return "orbit"
    if names & {"friction_scale", "dof"}:
        return "curves"
    plane = all(ds.sizes.get(d, 0) > 1 for d in PLANE)
    return "map" if plane and "regime" in ds else "curves"


def label(ds: xr.Dataset, name: str) -> str:
    """The axis label of `name` (LABELS), with the cube's units where they are not "1"."""
    entry = LABELS[name]
    text = entry.get(str(ds.attrs.get("excitation")), entry["force"]) if isinstance(entry, dict) else str(entry)
    units = str(ds[name].attrs.get("units", "1")).strip()
    return text if units in ("", "1", "degree") else f"{text} [{units}]"


def title_phrases(ds: xr.Dataset, what: str) -> list[str]:
    return [f"{what};", f"structure of {ds.sizes['dof']} masses and {ds.sizes['contact']} contacts,",
            f"{ds.attrs.get('excitation', '?')} excitation, method {ds.attrs.get('method', '?')}"]


def draw(ds: xr.Dataset, kind: str | None = None, sel: Sequence[str] = (), yscale: str = "auto") -> Figure:
    """The quick look of `kind` (default: default_kind) of structure cube `ds`; PlotError where the cube
    cannot be drawn so."""
    kind = kind or default_kind(ds, sel)
    if kind not in KINDS:
        raise PlotError(f"--kind {kind}: a structure cube draws {', '.join(KINDS)}")
    if not all(d in ds.dims for d in (*PLANE, "dof", "contact")):
        raise PlotError("not a structure cube: it lacks the dims friction_scale, frequency, dof, contact")
    if kind == "orbit" and NEEDS[kind] not in ds:
        raise PlotError("--kind orbit: the cube holds no time history (add time_history to the spec's outputs, "
                        "with a time_history: section)")
    if NEEDS[kind] not in ds:
        raise PlotError(f"--kind {kind} needs the variable {NEEDS[kind]}, which the cube lacks (it has "
                        f"{', '.join(map(str, ds.data_vars))}); add it to the spec's outputs")
    if yscale not in ql.YSCALES:
        raise PlotError(f"unknown y scale {yscale!r} (scales: {', '.join(ql.YSCALES)})")
    if yscale == "log" and kind != "curves":
        raise PlotError(f"--yscale log applies to --kind curves (amplitudes); --kind {kind} draws "
                        + {"map": "friction scales", "phase": "phase lags, which change sign",
                           "orbit": "displacements, which change sign"}[kind])
    choice = Choice(ds, kind, sel)
    if kind == "map":
        return draw_map(ds, choice.contacts)
    if kind == "orbit":
        return draw_orbit(ds, choice)
    return draw_curves(ds, CURVE_VARIABLE[kind], choice, yscale)


def draw_map(ds: xr.Dataset, contacts: Sequence[str]) -> Figure:
    """`regime` of each contact over (frequency, friction_scale), a panel per contact (gid "regime NAME"),
    each with a legend of the regimes it has and their counts."""
    m = len(contacts)
    fig, axes = ql._figure(m, 1, size=(7.6, 1.0 + 3.0 * m))
    x, y = ds["frequency"].values.astype(float), ds["friction_scale"].values.astype(float)
    for ax, name in zip(axes[:, 0], contacts, strict=True):
        regime = ds["regime"].sel(contact=name).transpose(*PLANE)
        patches = ql.regime_mesh(ax, x, y, regime, f"regime {name}")
        ax.legend(handles=patches, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, framealpha=0.95,
                  title=f"contact {name}", title_fontsize=8)
        ax.set(xlabel=label(ds, "frequency"), ylabel=label(ds, "friction_scale"))
    ql.fit_title(fig, title_phrases(ds, "regime map per contact"))
    return fig


def draw_curves(ds: xr.Dataset, var: str, choice: Choice, yscale: str = "auto") -> Figure:
    """`var` of each chosen mass against the frequency, a panel per mass (gid "curve DOF ROW" per friction
    scale), then, where the cube has regimes, a strip per chosen contact with a row per curve."""
    x = ql.Axis("frequency", "frequency", ds["frequency"].values.astype(float),
                ds["frequency"].values.astype(float), label(ds, "frequency"))
    rows, dofs = choice.scales, choice.dofs
    contacts = choice.contacts if "regime" in ds else []
    n = len(rows)
    heights = [3.0] * len(dofs) + [0.5 + 0.22 * n] * len(contacts)
    fig, axes = ql._figure(len(heights), 1, size=(7.6, 1.0 + sum(heights)), height_ratios=heights)
    colours = [ql._viridis(k, n) for k in range(n)]
    scale = ds["friction_scale"].values.astype(float)
    data = ds[var].transpose(*PLANE, "dof")
    for panel, dof in enumerate(dofs):
        ax = axes[panel, 0]
        values = data.sel(dof=dof).values[rows]
        for row, (i, colour) in enumerate(zip(rows, colours, strict=True)):
            ax.plot(x.values, values[row], "-", color=colour, marker=".", ms=3, gid=f"curve {dof} {row}",
                    label=f"$s$ = {scale[i]:g}")
        ax.set_yscale(ql.choose_yscale(values, yscale) if var == "amplitude" else "linear")
        top = np.nanmax(values, initial=0.0)
        if ax.get_yscale() == "log" and top > 0:  # a stuck mass's rounding-level amplitude would set the decades
            ax.set_ylim(bottom=max(np.nanmin(np.where(values > 0, values, np.inf)), top * FLOOR))
        ax.set_ylabel(ql._wrapped(f"{label(ds, var)} of {dof}", 30))
        if panel == 0:
            ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, title="friction scale",
                      title_fontsize=8)
    regime = ds["regime"].transpose(*PLANE, "contact") if contacts else None
    for k, name in enumerate(contacts):
        strip = axes[len(dofs) + k, 0]
        assert regime is not None
        ql._regime_strip(strip, x, regime.sel(contact=name).values.astype(int)[rows], colours)
        strip.set(ylim=(n - 0.5, -0.5), yticks=range(n), yticklabels=[f"{scale[i]:g}" for i in rows])
        strip.set_ylabel(f"{name}\n$s$", fontsize=8)
    for ax in axes[1:, 0]:
        ax.sharex(axes[0, 0])
    for ax in axes[:-1, 0]:
        ax.tick_params(labelbottom=False)
    axes[0, 0].set_xlim(*ql._edges(x.values)[[0, -1]])
    axes[-1, 0].set_xlabel(x.label)
    what = {"amplitude": "amplitude of each mass", "phase": "phase lag of each mass"}[var]
    phrases = title_phrases(ds, what + (", regime strip per contact" if contacts else ""))
    if n != ds.sizes["friction_scale"]:
        phrases.append(f"({n} of {ds.sizes['friction_scale']} friction scales; choose with --sel friction_scale=...)")
    ql.fit_title(fig, phrases)
    return fig


def draw_orbit(ds: xr.Dataset, choice: Choice) -> Figure:
    """Stored orbit choice.history: each chosen mass's displacement against time (gid "orbit DOF"), then each
    chosen contact's force against its relative displacement (gid "loop CONTACT"), closed over the orbit."""
    k = choice.history
    one = ds.isel({HISTORY_DIM: k})
    t = one["history_time"].values.astype(float)
    keep = np.isfinite(t)
    if not keep.any():
        raise PlotError(f"history {k} holds no steady orbit (its point has no steady state)")
    dofs, contacts = choice.dofs, choice.contacts
    loops = all(n in ds for n in ("history_contact_force", "history_relative_displacement"))
    rows = len(dofs) + (len(contacts) if loops else 0)
    fig, axes = ql._figure(rows, 1, size=(7.6, 1.0 + 2.6 * rows))
    for ax, dof in zip(axes[:len(dofs), 0], dofs, strict=True):
        x = one["history_displacement"].sel(dof=dof).values[keep]
        ax.plot(t[keep], x, "-", gid=f"orbit {dof}")
        ax.set(xlabel="time [forcing periods]", ylabel=ql._wrapped(f"displacement of {dof}", 30))
    if loops:
        for ax, name in zip(axes[len(dofs):, 0], contacts, strict=True):
            u = one["history_relative_displacement"].sel(contact=name).values[keep]
            f = one["history_contact_force"].sel(contact=name).values[keep]
            ax.plot(np.append(u, u[:1]), np.append(f, f[:1]), "-", gid=f"loop {name}")
            ax.set(xlabel=f"relative displacement u of {name}", ylabel=ql._wrapped(f"force of {name}", 30))
    where = (f"frequency {float(one['history_frequency']):g}, friction scale "
             f"{float(one['history_friction_scale']):g}") if "history_frequency" in one.coords else f"history {k}"
    ql.fit_title(fig, title_phrases(ds, f"orbit {k} of {ds.sizes[HISTORY_DIM]} at {where}"))
    return fig
