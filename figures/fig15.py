"""Paper Fig. 15: phase phi_xz between the absolute mass motion x and the relative mass-wall
motion z, between maxima (Eq. 43), joined base-wall excitation, one curve per force ratio.

    python figures/fig15.py results/fig11_joined_relative_phase.nc figures/out/fig15.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig15.py", var="peak_phase_xz",
        ylabel=r"phase $\varphi_{xz}$ (deg)",
        title="Fig. 15: joined base-wall motion: phase between absolute and relative motion",
        xlim=(0, 5), ylim=(-5, 185), legend_loc="lower right",
    )


if __name__ == "__main__":
    main()
