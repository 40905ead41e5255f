"""Paper Fig. 19: the mass response x (solid) against the base motion y (thin grey) in the motion
regimes of base excitation with a fixed wall: (a) multiple stops, (b) two stops, (c) continuous,
(d) beating, (e) finite resonance. Panels a, b, c, e are the steady-state orbits stored in the
cube (`outputs: [..., time_history]`, in the order of its `time_history.points`), repeated over two
forcing periods, with the time the mass is stuck shaded. Panel d is a transient, which no steady
state can show: the motion from rest near resonance with little friction (r = 0.95, F_mu/F_k = 0.05
by default) over 40 forcing periods, computed here with the exact event kernel.

    python figures/fig19.py results/numerical/fig19_base_time_histories.nc figures/out/fig19.png
"""


import common as C
import numpy as np

from friction_sweep.codes import Regime

BEATING = {"r": 0.95, "beta": 0.05, "periods": 40}


def describe(r, beta, regime, stops):
    """Panel title from what the simulation found at the point."""
    where = rf"$r = {r:g}$, " + C.ratio_label("base", beta)
    if regime == Regime.CONTINUOUS:
        return "continuous motion, " + where
    if regime == Regime.STICK_SLIP:
        if r == 1.0:
            return "finite resonance (stick-slip at resonance), " + where
        if np.isfinite(stops) and stops == 2:
            return "two stops per period, " + where
        if np.isfinite(stops):
            return f"multiple stops ({stops:g} per period), " + where
        return "stick-slip, " + where
    return f"{C.REGIME_NAMES.get(int(regime), 'unknown')}, " + where


def stops_at(ds, r, beta):
    if "stops_per_period" not in ds:
        return np.nan
    try:
        return float(ds["stops_per_period"].sel(frequency_ratio=r, force_ratio=beta).values)
    except KeyError:
        return np.nan


def shade_stuck(ax, t, v, scale):
    """Shade the time where the mass is at rest (velocity zero to rounding)."""
    stuck = np.abs(v) <= 1e-9 * max(scale, 1e-300)
    first = True
    for code, lo, hi in C.regime_runs(t, stuck.astype(int)):
        if code == 1 and hi > lo:
            ax.axvspan(lo, hi, color=C.REGIME_COLORS[int(Regime.STICK_SLIP)], alpha=0.8, lw=0, zorder=0,
                       label="mass at rest" if first else None)
            first = False


def main(argv=None):
    (path,), out = C.parse_args(argv, "python figures/fig19.py CUBE.nc OUT.png", 1)
    ds = C.open_cube(path)
    C.require(ds, path, "history_time", "history_displacement", "history_excitation", "history_relative_velocity")
    n = ds.sizes["history_point"]
    steady_panels = list(range(n))
    # the beating transient goes in as panel (d), after the first three steady states
    order = steady_panels[:3] + ["beating"] + steady_panels[3:]
    fig, axes = C.new_figure(len(order), 1, size=(7.0, 2.0 * len(order) + 0.8))
    legend = {}
    for k, (item, ax) in enumerate(zip(order, axes.ravel(), strict=False)):
        label = f"({chr(ord('a') + k)}) "
        if item == "beating":
            t, x, y, q, v = C.transient_from_rest("base", BEATING["r"], BEATING["beta"], BEATING["periods"])
            ax.plot(t, y, color="0.55", lw=0.7, label="base $y/Y$")
            ax.plot(t, x, color="tab:blue", lw=0.9, label="mass $x/Y$")
            ax.set_title(label + rf"beating: transient from rest, $r = {BEATING['r']:g}$, "
                         + C.ratio_label("base", BEATING["beta"]))
            ax.set_xlim(0, BEATING["periods"])
        else:
            h = ds.isel(history_point=item)
            r = float(h["history_frequency_ratio"])
            beta = float(h["history_force_ratio"])
            regime = int(h["history_regime"])
            t, x, y, v = C.repeat_orbit(h["history_time"].values, h["history_displacement"].values,
                                        h["history_excitation"].values, h["history_relative_velocity"].values)
            if t.size:
                shade_stuck(ax, t, v, float(np.nanmax(np.abs(x))) if np.isfinite(x).any() else 1.0)
            ax.plot(t, y, color="0.55", lw=0.9, label="base $y/Y$")
            ax.plot(t, x, color="tab:blue", lw=1.4, label="mass $x/Y$")
            ax.set_title(label + describe(r, beta, regime, stops_at(ds, r, beta)))
            ax.set_xlim(0, 2)
        ax.set_ylabel(r"displacement / $Y$")
        for handle, text in zip(*ax.get_legend_handles_labels(), strict=True):
            legend.setdefault(text, handle)
    axes.ravel()[-1].set_xlabel(r"time $t\,\omega/2\pi$ (forcing periods)")
    fig.legend(list(legend.values()), list(legend.keys()), loc="outside lower center", ncols=len(legend))
    fig.suptitle("Fig. 19: base motion, fixed wall: response in the motion regimes (event simulation)")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
