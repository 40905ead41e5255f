"""Paper Fig. 18: theory against the exact simulation, base motion with a fixed wall, one panel per
force ratio. Theory dashed (Den Hartog's x0/Y, Eq. 22: only where it forecasts continuous motion),
simulation solid (the same quantity, max|x|/Y) and dotted (the first harmonic |X(r)|/|Y(r)|, the
paper's FFT definition). The simulated regime is shaded (stick-slip light grey).

    python figures/fig18.py results/numerical/fig17_base_numerical.nc \
        results/fig07_base_transmissibility.nc figures/out/fig18.png
"""


import common as C
import numpy as np

PREFERRED = (0.2, 0.4, 0.6, 0.8)


def pick_force_ratios(sim, theory, n=4):
    """Up to n force ratios present in both cubes, the paper's 0.2, 0.4, 0.6, 0.8 if there."""
    common = [b for b in sim["force_ratio"].values if b > 0 and np.any(np.isclose(theory["force_ratio"].values, b))]
    chosen = [b for b in common if np.any(np.isclose(PREFERRED, b))]
    if not chosen:
        idx = np.unique(np.linspace(0, len(common) - 1, min(n, len(common))).round().astype(int)) if common else []
        chosen = [common[i] for i in idx]
    return chosen[:n]


def main(argv=None):
    (path_sim, path_theory), out = C.parse_args(argv, "python figures/fig18.py SIM.nc THEORY.nc OUT.png", 2)
    sim, theory = C.open_cube(path_sim), C.open_cube(path_theory)
    C.require(sim, path_sim, "transmissibility", "peak_transmissibility", "regime")
    C.require(theory, path_theory, "peak_transmissibility")
    betas = pick_force_ratios(sim, theory)
    if not betas:
        raise SystemExit(f"{path_sim} and {path_theory} share no positive force ratio")
    ncols = 2 if len(betas) > 1 else 1
    nrows = int(np.ceil(len(betas) / ncols))
    fig, axes = C.new_figure(nrows, ncols, size=(5.5 * ncols, 3.6 * nrows))
    rs = sim["frequency_ratio"].values
    rt = theory["frequency_ratio"].values
    shaded = set()
    for k, (beta, ax) in enumerate(zip(betas, axes.ravel(), strict=False)):
        s = sim.sel(force_ratio=beta)
        t = theory.sel(force_ratio=beta, method="nearest")
        shaded.update(C.shade_regimes(ax, rs, s["regime"].values))
        ax.plot(rs, s["peak_transmissibility"].values, "-", color="tab:blue", label="simulation, peak max$|x|/Y$")
        ax.plot(rs, s["transmissibility"].values, ":", color="tab:blue", lw=1.1,
                label="simulation, first harmonic")
        ax.plot(rt, t["peak_transmissibility"].values, "--", color="k", lw=1.2, label=r"theory $x_0/Y$ (Eq. 22)")
        ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL,
               title=f"({chr(ord('a') + k)}) " + C.ratio_label("base", beta))
        ax.set_xlim(rs.min(), rs.max())
        top = np.nanmax(np.where(np.abs(rs - 1) > 0.03, s["peak_transmissibility"].values, np.nan))
        ax.set_ylim(0, min(6.0, 1.15 * top) if np.isfinite(top) else 6.0)
        if k == 0:
            handles, _ = ax.get_legend_handles_labels()
            ax.legend(handles=handles + C.regime_handles(shaded or [1]), loc="upper right")
    for ax in axes.ravel()[len(betas):]:
        ax.set_visible(False)
    fig.suptitle("Fig. 18: base motion, fixed wall: theory (dashed) against simulation (solid)")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
