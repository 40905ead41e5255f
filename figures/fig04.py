"""Paper Fig. 4: Den Hartog's dimensionless amplitude x0/(F0/k) under a harmonic force, one curve
per force ratio muN/F0, and the limit of continuous motion (dotted, Eq. 13).

    python figures/fig04.py results/fig04_force_amplitude.nc figures/out/fig04.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig04.py", var="peak_transmissibility", boundary="peak_transmissibility",
        ylabel=r"amplitude ratio $x_0/(F_0/k)$",
        title="Fig. 4: amplitude under a harmonic force (Den Hartog)", xlim=(0, 3), ylim=(0, 6),
    )


if __name__ == "__main__":
    main()
