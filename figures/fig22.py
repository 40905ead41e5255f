"""Paper Fig. 22: relative stick-slip between mass and wall under joined base-wall motion
(r = 0.95, F_mu/F_k = 0.8 in configs/numerical/fig22_joined_stick_slip_history.yaml): the steady
orbit from the exact simulation over two forcing periods. Top: the relative displacement z = x - y
and relative velocity z' (the mass sticks to the wall where z' = 0, shaded). Bottom: the absolute
mass motion x against the base and wall motion y.

    python figures/fig22.py results/numerical/fig22_joined_stick_slip_history.nc figures/out/fig22.png
"""


import common as C
import numpy as np

from friction_sweep.codes import Regime


def main(argv=None):
    (path,), out = C.parse_args(argv, "python figures/fig22.py CUBE.nc OUT.png", 1)
    ds = C.open_cube(path)
    C.require(ds, path, "history_time", "history_displacement", "history_excitation",
              "history_relative_displacement", "history_relative_velocity")
    h = ds.isel(history_point=0)
    r = float(h["history_frequency_ratio"])
    beta = float(h["history_force_ratio"])
    regime = int(h["history_regime"])
    t, x, y, z, v = C.repeat_orbit(h["history_time"].values, h["history_displacement"].values,
                                   h["history_excitation"].values, h["history_relative_displacement"].values,
                                   h["history_relative_velocity"].values)
    fig, axes = C.new_figure(2, 1, size=(7.0, 5.6), sharex=True)
    top, bottom = axes[0, 0], axes[1, 0]
    scale = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0
    stuck = (np.abs(v) <= 1e-9 * max(scale, 1e-300)).astype(int)
    for ax in (top, bottom):
        first = True
        for code, lo, hi in C.regime_runs(t, stuck):
            if code == 1 and hi > lo:
                ax.axvspan(lo, hi, color=C.REGIME_COLORS[int(Regime.STICK_SLIP)], alpha=0.8, lw=0, zorder=0,
                           label="mass stuck to the wall" if first else None)
                first = False
    top.plot(t, z, color="tab:purple", lw=1.4, label="relative displacement $z/Y = (x - y)/Y$")
    top.plot(t, v, color="tab:green", lw=1.0, label=r"relative velocity $z'/(Y\omega_n)$")
    top.axhline(0, color="0.3", lw=0.6)
    top.set_ylabel("relative motion")
    top.legend(loc="upper right", fontsize=7)
    bottom.plot(t, y, color="0.55", lw=1.0, label="base and wall $y/Y$")
    bottom.plot(t, x, color="tab:blue", lw=1.4, label="mass $x/Y$")
    bottom.set_ylabel(r"displacement / $Y$")
    bottom.set_xlabel(r"time $t\,\omega/2\pi$ (forcing periods)")
    bottom.legend(loc="upper right", fontsize=7)
    bottom.set_xlim(0, 2)
    name = C.REGIME_NAMES.get(regime, "unknown")
    fig.suptitle(f"Fig. 22: joined base-wall motion, relative {name}: $r = {r:g}$, "
                 + C.ratio_label("joined", beta))
    return C.save(fig, out)


if __name__ == "__main__":
    main()
