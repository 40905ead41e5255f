"""Paper Fig. 1b: displacement transmissibility of the viscous mass-spring-damper under base motion,
one curve per damping ratio zeta (one cube each, the event simulation with the viscous_damping
effect and no friction), over the closed form |1 + 2i zeta r| / |1 - r^2 + 2i zeta r| (thin dashed,
a check). All curves pass through 1 at r = sqrt(2), where damping stops reducing the transmission.

    python figures/fig01b.py results/numerical/fig01b_viscous_zeta005.nc ... figures/out/fig01b.png
"""


import common as C
import numpy as np

from friction_sweep.catalogue import effect_value


def classical(r, zeta):
    """|X|/|Y| of the linear base-excited oscillator with the damper between mass and base."""
    return np.abs((1.0 + 2j * zeta * r) / (1.0 - r * r + 2j * zeta * r))


def main(argv=None):
    paths, out = C.parse_args(argv, "python figures/fig01b.py CUBE.nc [CUBE.nc ...] OUT.png")
    cubes = []
    for path in paths:
        ds = C.open_cube(path)
        C.require(ds, path, "transmissibility")
        zeta = effect_value(C.effects_of(ds), "viscous_damping")
        cubes.append((zeta, ds))
    cubes.sort(key=lambda item: item[0])
    fig, axes = C.new_figure()
    ax = axes[0, 0]
    for (zeta, ds), colour in zip(cubes, C.colors(len(cubes)), strict=True):
        r = ds["frequency_ratio"].values
        t = ds["transmissibility"].isel(force_ratio=0).values
        ax.plot(r, t, color=colour, label=rf"$\zeta = {zeta:g}$")
        ax.plot(r, classical(r, zeta), "--", color="k", lw=0.6, alpha=0.7)
    ax.plot([], [], "--", color="k", lw=0.6, label="closed form")
    ax.axvline(np.sqrt(2.0), color="0.4", ls=":", lw=1)
    ax.annotate(r"$r = \sqrt{2}$", (np.sqrt(2.0), 5.6), xytext=(4, 0), textcoords="offset points", color="0.3")
    ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL,
           title="Fig. 1b: viscous damper, base motion (simulation, no friction)")
    ax.set_xlim(0, 3)
    ax.set_ylim(0, 6)
    ax.legend()
    return C.save(fig, out)


if __name__ == "__main__":
    main()
