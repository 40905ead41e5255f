"""Paper Fig. 16: phase phi_xy = phi_yz - phi_xz between the base motion y and the absolute mass
motion x, between maxima (Eq. 44), joined base-wall excitation, one curve per force ratio.

    python figures/fig16.py results/fig11_joined_relative_phase.nc figures/out/fig16.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig16.py", var="peak_phase",
        ylabel=r"phase $\varphi_{xy}$ (deg)",
        title="Fig. 16: joined base-wall motion: phase between base and absolute motion",
        xlim=(0, 5), ylim=(-5, 185), legend_loc="lower right",
    )


if __name__ == "__main__":
    main()
