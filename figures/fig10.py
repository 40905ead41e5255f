"""Paper Fig. 10: amplitude |Z|/|Y| of the relative mass-wall motion under joined base-wall
excitation (Eq. 34), one curve per force ratio, and the limit of continuous motion (dotted, Eq. 35).

    python figures/fig10.py results/fig10_joined_relative_amplitude.nc figures/out/fig10.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig10.py", var="relative_peak_amplitude", boundary="relative_peak_amplitude",
        ylabel=r"relative amplitude $|Z|/|Y|$",
        title="Fig. 10: joined base-wall motion: relative mass-wall amplitude", xlim=(0, 5), ylim=(0, 5),
    )


if __name__ == "__main__":
    main()
