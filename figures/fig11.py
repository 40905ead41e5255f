"""Paper Fig. 11: phase phi_yz between the base motion y and the relative mass-wall motion z
(Eq. 33), joined base-wall excitation, one curve per force ratio, and its value on the limit of
continuous motion (dotted, drawn from r = 0.5 on: below, the limit is tiny and swings at r = 1/3,
1/5, ... where U(r) is singular).

    python figures/fig11.py results/fig11_joined_relative_phase.nc figures/out/fig11.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig11.py", var="relative_peak_phase", boundary="relative_peak_phase", boundary_min_r=0.5,
        ylabel=r"phase $\varphi_{yz}$ (deg)",
        title="Fig. 11: joined base-wall motion: phase of the relative motion", xlim=(0, 5), ylim=(-5, 185),
        legend_loc="lower right",
    )


if __name__ == "__main__":
    main()
