"""Helpers shared by the figure scripts: arguments, styling, labels, regime shading, the theory's
continuous-motion boundary curves, transients from rest, and atomic PNG writing.

Every script is called as

    python figures/figNN.py CUBE [CUBE ...] OUT.png

reads its cubes with xarray (engine h5netcdf) and writes one PNG. Scripts expose `main(argv)` so
the tests can run them in-process.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.patches import Patch

from friction_sweep.codes import Regime
from friction_sweep.storage.atomic import save_figure
from friction_sweep.storage.cube import legacy_names

plt.switch_backend("Agg")  # no display: every figure is written to a file

# --- labels ---------------------------------------------------------------------------------------------

R_LABEL = r"frequency ratio $r = \omega/\omega_n$"
TRANS_LABEL = r"transmissibility $|X|/|Y|$"
PHASE_LABEL = "phase (deg)"
FORCE_RATIO_LABEL = r"force ratio $F_\mu/F_k$"


def ratio_label(excitation: str, beta: float) -> str:
    """Legend text for one force ratio in the scene's convention."""
    if excitation == "force":
        return rf"$\mu N/F_0 = {beta:g}$"
    return rf"$F_\mu/F_k = {beta:g}$"


# --- arguments and input --------------------------------------------------------------------------------


def parse_args(argv, usage: str, n_inputs: int | None = None) -> tuple[list[Path], Path]:
    """Split `CUBE ... OUT.png`; exit with the usage line on a wrong call."""
    args = list(sys.argv[1:] if argv is None else argv)
    ok = len(args) >= 2 and args[-1].lower().endswith(".png")
    if ok and n_inputs is not None:
        ok = len(args) - 1 == n_inputs
    if not ok:
        raise SystemExit(f"usage: {usage}")
    return [Path(a) for a in args[:-1]], Path(args[-1])


def open_cube(path) -> xr.Dataset:
    """A result cube, loaded into memory and the file closed; one written before issue 33 with today's
    names (storage.cube.legacy_names), as results/ may still hold."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return legacy_names(ds.load())


def excitation_of(ds: xr.Dataset) -> str:
    return str(ds.attrs.get("excitation", "base"))


def effects_of(ds: xr.Dataset) -> dict:
    """The scene effects recorded in a cube's provenance (empty for the theory)."""
    try:
        return dict(json.loads(ds.attrs.get("method_settings", "{}")).get("effects", {}))
    except (TypeError, ValueError):
        return {}


# --- styling --------------------------------------------------------------------------------------------


def style() -> None:
    plt.rcParams.update({
        "figure.dpi": 110,
        "savefig.dpi": 150,
        "font.size": 9,
        "axes.titlesize": 10,
        "axes.labelsize": 9,
        "legend.fontsize": 7.5,
        "legend.framealpha": 0.9,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "lines.linewidth": 1.3,
    })


def new_figure(nrows: int = 1, ncols: int = 1, size=(6.4, 4.4), **kwargs):
    style()
    fig, axes = plt.subplots(nrows, ncols, figsize=size, squeeze=False, constrained_layout=True, **kwargs)
    return fig, axes


def colors(n: int, cmap: str = "viridis"):
    """n distinguishable colours along a colormap (dark to light, avoiding the palest end)."""
    return [plt.get_cmap(cmap)(x) for x in np.linspace(0.0, 0.85, max(n, 1))]


def plot_family(ax, ds: xr.Dataset, var: str, *, excitation: str | None = None, linestyle: str = "-",
                label: bool = True, palette=None, **kwargs):
    """One curve of `var` against r per force ratio of the cube, coloured along the force ratios."""
    excitation = excitation or excitation_of(ds)
    betas = ds["force_ratio"].values
    palette = palette or colors(len(betas))
    r = ds["frequency_ratio"].values
    for beta, colour in zip(betas, palette, strict=False):
        y = ds[var].sel(force_ratio=beta).values
        ax.plot(r, y, linestyle, color=colour, label=ratio_label(excitation, beta) if label else None, **kwargs)
    return palette


# --- regimes --------------------------------------------------------------------------------------------

#: colours of the regime shading: the paper's dark grey (stuck), light grey (stick-slip), white
REGIME_COLORS = {
    int(Regime.STUCK): "0.55",
    int(Regime.STICK_SLIP): "0.85",
    int(Regime.UNBOUNDED): "tab:red",
    int(Regime.UNSETTLED): "tab:orange",
}
REGIME_NAMES = {int(code): code.name.lower().replace("_", "-") for code in Regime}  # legend words


def regime_runs(r, codes):
    """Contiguous runs (code, r_lo, r_hi) of one regime code along r; edges halfway between points."""
    r = np.asarray(r, dtype=float)
    codes = np.asarray(codes).astype(int)
    if r.size == 0:
        return []
    mids = 0.5 * (r[1:] + r[:-1])
    edges = np.concatenate([[r[0]], mids, [r[-1]]])
    runs = []
    start = 0
    for i in range(1, r.size + 1):
        if i == r.size or codes[i] != codes[start]:
            runs.append((int(codes[start]), float(edges[start]), float(edges[i])))
            start = i
    return runs


def shade_regimes(ax, r, codes, alpha: float = 0.6, skip=(int(Regime.CONTINUOUS),)):
    """Shade the r-axis by regime: stuck dark grey, stick-slip light grey, continuous white."""
    seen = []
    for code, lo, hi in regime_runs(r, codes):
        if code in skip:
            continue
        ax.axvspan(lo, hi, color=REGIME_COLORS.get(code, "0.7"), alpha=alpha, lw=0, zorder=0)
        if code not in seen:
            seen.append(code)
    return seen


def regime_handles(codes, alpha: float = 0.6):
    """Legend patches for the shaded regimes among `codes`."""
    return [Patch(facecolor=REGIME_COLORS[c], alpha=alpha, label=REGIME_NAMES[c])
            for c in sorted(set(int(c) for c in codes)) if c in REGIME_COLORS]


# --- the theory's continuous-motion boundary ------------------------------------------------------------


def continuous_boundary(excitation: str, r, limit, quantity: str):
    """`quantity` evaluated on the continuous limit, i.e. at the force ratio `limit` (the cube's
    `continuous_limit`, r^2 beta*(r) for joined): the dotted boundary curves of Figs. 4, 5, 7, 10,
    14a. quantity: peak_transmissibility, peak_phase, relative_peak_amplitude, relative_peak_phase."""
    from friction_sweep.theory import den_hartog as dh
    from friction_sweep.theory import joined, scenes
    from friction_sweep.theory.phase import wrap_lag_degrees

    r = np.asarray(r, dtype=float)
    limit = np.asarray(limit, dtype=float)
    b = scenes.friction_ratio(excitation, r, limit)
    with np.errstate(all="ignore"):
        x0 = dh.amplitude(r, b)
        phi = dh.phase(r, b)
        if quantity == "relative_peak_amplitude" and excitation == "joined":
            return scenes.forcing_amplitude(excitation, r) * x0  # Eq. 35
        if quantity == "relative_peak_phase" and excitation == "joined":
            return wrap_lag_degrees(phi)
        if quantity == "peak_phase" and excitation != "joined":
            return wrap_lag_degrees(phi)
        if quantity == "peak_transmissibility" and excitation != "joined":
            return x0  # Eq. 13
        if quantity == "peak_transmissibility":  # joined: max |x| of Eq. 37 on the limit
            out = np.full(r.shape, np.nan)
            ok = np.isfinite(phi) & np.isfinite(x0)
            if ok.any():
                out[ok] = joined.peak_of_absolute(r[ok], b[ok], phi[ok])[0]
            return out
    raise ValueError(f"no boundary curve for {quantity!r} ({excitation})")


# --- transients from rest (the beating of Fig. 19d) -----------------------------------------------------


def transient_from_rest(excitation: str, r: float, beta: float, periods: int, samples_per_period: int = 128,
                        effects=None, settings=None):
    """The motion from rest at the excitation's maximum over `periods` forcing periods, by the exact
    event kernel. Returns (time in forcing periods, x, excitation, q, q'), each of length
    periods * samples_per_period."""
    from friction_sweep.kernels import steady, stick
    from friction_sweep.kernels.point import Point
    from friction_sweep.kernels.settings import SET_STOP_TOL, SET_WORK_BUDGET
    from friction_sweep.methods import event as event_method

    A, c, bk, bs, zeta = (float(a[0]) for a in event_method.point_parameters(
        excitation, np.array([r]), np.array([beta]), effects))
    sett = event_method.kernel_settings(settings)
    T = 2.0 * np.pi / r
    ts = np.arange(samples_per_period) / samples_per_period * T
    sq = np.empty((periods, samples_per_period))
    sv = np.empty((periods, samples_per_period))
    q0, v0 = 0.0, 0.0
    mode = stick.decide(0.0, q0, A, r, bs)
    steady.sample_orbit(q0, v0, mode, Point(A, r, bk, bs, zeta, c), sett[SET_STOP_TOL], int(sett[SET_WORK_BUDGET]),
                        periods, ts, sq, sv)
    n = periods * samples_per_period
    t = np.arange(n) / samples_per_period
    y = np.cos(2.0 * np.pi * t)
    q = sq.ravel()
    return t, q + c * y, y, q, sv.ravel()


def repeat_orbit(time, *series, periods: float = 2.0):
    """Extend one stored steady orbit (NaN-padded, `history_*`) to `periods` forcing periods."""
    time = np.asarray(time, dtype=float)
    ok = np.isfinite(time)
    time = time[ok]
    if time.size == 0:
        return (time, *(np.asarray(s)[ok] for s in series))
    span = time[-1] + (time[1] - time[0] if time.size > 1 else 1.0)
    reps = int(np.ceil(periods / span))
    t = np.concatenate([time + k * span for k in range(reps)])
    keep = t <= periods
    out = [t[keep]]
    for s in series:
        s = np.asarray(s, dtype=float)[ok]
        out.append(np.tile(s, reps)[keep])
    return tuple(out)


# --- output ---------------------------------------------------------------------------------------------


def save(fig, path) -> Path:
    """Write the PNG atomically (friction_sweep.storage.atomic): never a partial figure."""
    return save_figure(fig, path)


# --- the common shape of the theory figures: one curve per force ratio ----------------------------------


def require(ds: xr.Dataset, path, *names: str) -> None:
    """Fail with a clear message if the cube lacks a variable the figure needs."""
    missing = [n for n in names if n not in ds]
    if missing:
        raise SystemExit(f"{path}: the cube has no {', '.join(missing)} (variables: {', '.join(ds.data_vars)}); "
                         "check the spec's outputs")


def family_figure(argv, *, script: str, var: str, ylabel: str, title: str, boundary: str | None = None,
                  boundary_min_r: float = 0.0, xlim=None, ylim=None, legend_loc: str = "best", decorate=None):
    """A figure with one curve of `var` against r per force ratio, optionally with the theory's
    continuous-motion boundary (dotted; drawn from r = boundary_min_r on), as in the paper's
    Figs. 4, 5, 7, 10, 11, 15, 16."""
    (path,), out = parse_args(argv, f"python figures/{script} CUBE.nc OUT.png", 1)
    ds = open_cube(path)
    require(ds, path, var)
    excitation = excitation_of(ds)
    fig, axes = new_figure()
    ax = axes[0, 0]
    plot_family(ax, ds, var, excitation=excitation)
    if boundary is not None and "continuous_limit" in ds:
        r = ds["frequency_ratio"].values
        curve = continuous_boundary(excitation, r, ds["continuous_limit"].values, boundary)
        curve = np.where(r >= boundary_min_r, curve, np.nan)
        ax.plot(r, curve, ":", color="k", lw=1.4, label="limit of continuous motion")
    if decorate is not None:
        decorate(ax, ds)
    ax.set(xlabel=R_LABEL, ylabel=ylabel, title=title)
    if xlim is not None:
        ax.set_xlim(*xlim)
    if ylim is not None:
        ax.set_ylim(*ylim)
    ax.legend(loc=legend_loc, ncols=2 if ds.sizes["force_ratio"] > 5 else 1)
    return save(fig, out)
