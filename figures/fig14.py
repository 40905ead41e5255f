"""Paper Fig. 14: theoretical displacement transmissibility |X|/|Y| = max|x|/Y (Eq. 37) under joined
base-wall motion, one curve per force ratio, with the limit of continuous motion (dotted) (a), and
the detail of the inversion of the curves inside 1.4 < r < 1.55 (b), where the crossings of curves
of adjacent force ratios are marked.

    python figures/fig14.py results/fig14a_joined_transmissibility.nc \
        results/fig14b_joined_inversion.nc figures/out/fig14.png
"""


import common as C
import numpy as np

VAR = "peak_transmissibility"


def crossings(r, y1, y2):
    """(r, y) where two sampled curves cross, by linear interpolation between grid points."""
    d = y1 - y2
    ok = np.isfinite(d[:-1]) & np.isfinite(d[1:]) & (np.sign(d[:-1]) != np.sign(d[1:]))
    out = []
    for i in np.flatnonzero(ok):
        f = d[i] / (d[i] - d[i + 1])
        out.append((r[i] + f * (r[i + 1] - r[i]), y1[i] + f * (y1[i + 1] - y1[i])))
    return out


def main(argv=None):
    (path_a, path_b), out = C.parse_args(argv, "python figures/fig14.py CUBE_A.nc CUBE_B.nc OUT.png", 2)
    a, b = C.open_cube(path_a), C.open_cube(path_b)
    C.require(a, path_a, VAR)
    C.require(b, path_b, VAR)
    fig, axes = C.new_figure(1, 2, size=(11, 4.4))
    ax = axes[0, 0]
    palette = C.plot_family(ax, a, VAR)
    r = a["frequency_ratio"].values
    if "continuous_limit" in a:
        ax.plot(r, C.continuous_boundary("joined", r, a["continuous_limit"].values, VAR), ":", color="k", lw=1.4,
                label="limit of continuous motion")
    ax.axvspan(1.4, 1.55, color="tab:orange", alpha=0.15, lw=0, label=r"inversion, $1.4 < r < 1.55$")
    ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL + r" (peak, max$|x|/Y$)",
           title="(a) joined base-wall motion: theory")
    ax.set_xlim(0, r.max())
    ax.set_ylim(0, 5)
    ax.legend(ncols=2)

    ax = axes[0, 1]
    betas_b = b["force_ratio"].values
    palette_b = palette if b.sizes["force_ratio"] == a.sizes["force_ratio"] else C.colors(betas_b.size)
    C.plot_family(ax, b, VAR, palette=palette_b)
    rb = b["frequency_ratio"].values
    first = True
    for lo, hi in zip(betas_b[:-1], betas_b[1:], strict=True):
        for rc, yc in crossings(rb, b[VAR].sel(force_ratio=lo).values, b[VAR].sel(force_ratio=hi).values):
            ax.plot(rc, yc, "o", color="tab:red", ms=4, label="crossing of adjacent curves" if first else None)
            first = False
    ax.axvspan(1.4, 1.55, color="tab:orange", alpha=0.15, lw=0)
    ax.axvline(np.sqrt(2.0), color="0.4", ls="--", lw=1, label=r"viscous inversion $r = \sqrt{2}$")
    ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL + r" (peak, max$|x|/Y$)", title="(b) detail of the inversion")
    ax.set_xlim(rb.min(), rb.max())
    finite = b[VAR].where(np.isfinite(b[VAR])).sel(frequency_ratio=slice(1.38, 1.57))
    if np.isfinite(finite).any():
        ax.set_ylim(float(finite.min()) * 0.95, float(finite.max()) * 1.05)
    ax.legend(ncols=2, loc="upper right")
    fig.suptitle("Fig. 14: displacement transmissibility, joined base-wall motion")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
