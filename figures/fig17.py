"""Paper Fig. 17: displacement transmissibility from the exact event-driven simulation, base motion
with a fixed wall, one curve per force ratio (a), and the detail at low frequency ratios, outside
the region where Den Hartog's theory applies (b). The transmissibility is the first harmonic
|X(r)|/|Y(r)| (the paper's FFT definition); the theory's limit of continuous motion is dotted.
Gaps: r = 1 below pi/4 (unbounded) and the few points the simulation reports `unsettled` (r = 1/2
and small force ratios just below r = 1/3, 0.41, 0.48, where the orbit creeps to its limit).

    python figures/fig17.py results/numerical/fig17_base_numerical.nc \
        results/numerical/fig17b_base_numerical_low_r.nc figures/out/fig17.png
"""


import common as C

VAR = "transmissibility"


def panel(ax, ds, title, xlim, ylim, palette=None, legend_loc="upper right"):
    palette = C.plot_family(ax, ds, VAR, palette=palette)
    if "continuous_limit" in ds:
        r = ds["frequency_ratio"].values
        ax.plot(r, C.continuous_boundary("base", r, ds["continuous_limit"].values, "peak_transmissibility"), ":",
                color="k", lw=1.4, label="theory: limit of continuous motion")
    ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL + " (first harmonic)", title=title)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.legend(ncols=2, loc=legend_loc)
    return palette


def main(argv=None):
    (path_a, path_b), out = C.parse_args(argv, "python figures/fig17.py CUBE_A.nc CUBE_B.nc OUT.png", 2)
    a, b = C.open_cube(path_a), C.open_cube(path_b)
    C.require(a, path_a, VAR)
    C.require(b, path_b, VAR)
    fig, axes = C.new_figure(1, 2, size=(11, 4.4))
    panel(axes[0, 0], a, "(a) whole range", (0, float(a["frequency_ratio"].max())), (0, 5))
    # the same colour for the same force ratio in both panels
    all_betas = list(a["force_ratio"].values)
    palette_a = C.colors(len(all_betas))
    palette_b = [palette_a[all_betas.index(x)] if x in all_betas else "0.3" for x in b["force_ratio"].values]
    rb = b["frequency_ratio"]
    panel(axes[0, 1], b, "(b) low frequency ratios", (float(rb.min()), float(rb.max())), (0, 2.5), palette=palette_b,
          legend_loc="upper left")
    fig.suptitle("Fig. 17: base motion, fixed wall: numerical transmissibility (event simulation)")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
