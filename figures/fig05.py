"""Paper Fig. 5: Den Hartog's phase angle between the maxima of force and displacement, one curve
per force ratio muN/F0, and its value on the limit of continuous motion (dotted, drawn from r = 0.5
on: below, the limit is tiny and swings at r = 1/3, 1/5, ... where U(r) is singular).

    python figures/fig05.py results/fig05_force_phase.nc figures/out/fig05.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig05.py", var="peak_phase", boundary="peak_phase", boundary_min_r=0.5,
        ylabel=r"phase $\varphi$ between force and displacement maxima (deg)",
        title="Fig. 5: phase under a harmonic force (Den Hartog)", xlim=(0, 3), ylim=(-5, 185),
        legend_loc="lower right",
    )


if __name__ == "__main__":
    main()
