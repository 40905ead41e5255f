"""Paper Fig. 20: displacement transmissibility from the exact event-driven simulation, joined
base-wall motion, one curve per force ratio: 1 where the mass rides with the wall (stuck), a narrow
dip when relative stick-slip begins, and a resonant peak that fades as the force ratio grows. The
transmissibility is the first harmonic |X(r)|/|Y(r)| (the paper's FFT definition).

    python figures/fig20.py results/numerical/fig20_joined_numerical.nc figures/out/fig20.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig20.py", var="transmissibility",
        ylabel=C.TRANS_LABEL + " (first harmonic)",
        title="Fig. 20: joined base-wall motion: numerical transmissibility (event simulation)",
        xlim=(0, 5), ylim=(0, 5), legend_loc="upper right",
    )


if __name__ == "__main__":
    main()
