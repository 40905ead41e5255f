"""Paper Fig. 21: theory against the exact simulation, joined base-wall motion, one panel per force
ratio (up to six, the largest ones last: the resonant peak fades). Theory dashed (max|x|/Y, Eq. 37,
only where it forecasts continuous motion or sticking), simulation solid (the same quantity) and
dotted (first harmonic). Shading: the theory's forecast of the regime, dark grey stuck, light grey
stick-slip, white continuous (sliding), as in the paper.

    python figures/fig21.py results/numerical/fig20_joined_numerical.nc \
        results/fig21_joined_theory.nc figures/out/fig21.png
"""


import common as C
import numpy as np

PREFERRED = (0.2, 0.6, 1.0, 1.4, 2.0, 3.0)


def pick_force_ratios(sim, theory, n=6):
    common = [b for b in sim["force_ratio"].values if b > 0 and np.any(np.isclose(theory["force_ratio"].values, b))]
    chosen = [b for b in common if np.any(np.isclose(PREFERRED, b))]
    if len(chosen) < min(n, len(common)):
        idx = np.unique(np.linspace(0, len(common) - 1, min(n, len(common))).round().astype(int))
        chosen = [common[i] for i in idx]
    return chosen[:n]


def main(argv=None):
    (path_sim, path_theory), out = C.parse_args(argv, "python figures/fig21.py SIM.nc THEORY.nc OUT.png", 2)
    sim, theory = C.open_cube(path_sim), C.open_cube(path_theory)
    C.require(sim, path_sim, "transmissibility", "peak_transmissibility")
    C.require(theory, path_theory, "peak_transmissibility", "regime")
    betas = pick_force_ratios(sim, theory)
    if not betas:
        raise SystemExit(f"{path_sim} and {path_theory} share no positive force ratio")
    ncols = min(3, len(betas))
    nrows = int(np.ceil(len(betas) / ncols))
    fig, axes = C.new_figure(nrows, ncols, size=(4.4 * ncols, 3.5 * nrows))
    rs = sim["frequency_ratio"].values
    rt = theory["frequency_ratio"].values
    shaded = set()
    for k, (beta, ax) in enumerate(zip(betas, axes.ravel(), strict=False)):
        s = sim.sel(force_ratio=beta)
        t = theory.sel(force_ratio=beta, method="nearest")
        shaded.update(C.shade_regimes(ax, rt, t["regime"].values))
        ax.plot(rs, s["peak_transmissibility"].values, "-", color="tab:blue", label="simulation, peak max$|x|/Y$")
        ax.plot(rs, s["transmissibility"].values, ":", color="tab:blue", lw=1.1, label="simulation, first harmonic")
        ax.plot(rt, t["peak_transmissibility"].values, "--", color="k", lw=1.2, label="theory (Eq. 37)")
        ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL, title=f"({chr(ord('a') + k)}) " + C.ratio_label("joined", beta))
        ax.set_xlim(rs.min(), min(rs.max(), 3.0))
        away = np.abs(rs - 1) > 0.03
        top = np.nanmax(np.where(away, s["peak_transmissibility"].values, np.nan))
        ax.set_ylim(0, min(6.0, 1.15 * top) if np.isfinite(top) else 6.0)
    for ax in axes.ravel()[len(betas):]:
        ax.set_visible(False)
    handles, _ = axes[0, 0].get_legend_handles_labels()
    from matplotlib.patches import Patch

    regime_patches = C.regime_handles(shaded)
    regime_patches.append(Patch(facecolor="white", edgecolor="0.6", label="continuous"))
    fig.legend(handles=handles + regime_patches, loc="outside lower center", ncols=len(handles) + len(regime_patches))
    fig.suptitle("Fig. 21: joined base-wall motion: theory (dashed) against simulation (solid); "
                 "shading: theory's regime forecast")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
