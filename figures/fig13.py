"""Paper Fig. 13: the motion regime on the frequency ratio - force ratio plane, joined base-wall
excitation (cube variable `regime` of Den Hartog's forecast): stuck where beta >= r^2 (above the
curve beta = r^2, Eq. 42), continuous where beta <= r^2 beta*(r) (below the dashed limit, Eq. 40),
stick-slip between the two curves. Shown up to r = 2.5; beyond it every force ratio of the cube is
continuous.

    python figures/fig13.py results/fig13_joined_regime_map.nc figures/out/fig13.png
"""


import common as C
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from friction_sweep.codes import Regime

#: regime code -> face colour (white where the motion is continuous)
MAP_COLORS = ["0.55", "0.85", "white", "tab:red", "tab:orange"]


def main(argv=None):
    (path,), out = C.parse_args(argv, "python figures/fig13.py CUBE.nc OUT.png", 1)
    ds = C.open_cube(path)
    C.require(ds, path, "regime", "continuous_limit")
    r = ds["frequency_ratio"].values
    beta = ds["force_ratio"].values
    code = ds["regime"].values.astype(int)
    fig, axes = C.new_figure(size=(6.4, 4.6))
    ax = axes[0, 0]
    cmap = ListedColormap(MAP_COLORS)
    norm = BoundaryNorm(np.arange(len(MAP_COLORS) + 1) - 0.5, cmap.N)
    ax.pcolormesh(r, beta, code, cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    fine = np.linspace(r.min(), r.max(), 2000)
    ax.plot(fine, fine**2, color="k", lw=1.5, label=r"$F_\mu/F_k = r^2$ (stuck above, Eq. 42)")
    ax.plot(r, ds["continuous_limit"].values, "--", color="k", lw=1.5,
            label=r"$F_\mu/F_k = r^2\beta^*(r)$ (continuous below, Eq. 40)")
    present = sorted(set(np.unique(code)))
    handles = C.regime_handles([c for c in present if c != int(Regime.CONTINUOUS)], alpha=1.0)
    from matplotlib.patches import Patch

    handles.insert(2 if len(handles) >= 2 else len(handles),
                   Patch(facecolor="white", edgecolor="0.5", label="continuous"))
    line_handles, _ = ax.get_legend_handles_labels()
    ax.legend(handles=line_handles + handles, loc="lower right", framealpha=0.95)
    ax.set(xlabel=C.R_LABEL, ylabel=C.FORCE_RATIO_LABEL,
           title="Fig. 13: motion regime, joined base-wall excitation (theory)")
    ax.set_xlim(0.0, min(r.max(), 2.5))
    ax.set_ylim(beta.min(), beta.max())
    return C.save(fig, out)


if __name__ == "__main__":
    main()
