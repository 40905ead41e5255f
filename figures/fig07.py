"""Paper Fig. 7: theoretical displacement transmissibility x0/Y under base motion with a fixed wall
(Eq. 22), one curve per force ratio, and the limit of continuous motion (dotted, Eq. 23a).

    python figures/fig07.py results/fig07_base_transmissibility.nc figures/out/fig07.png
"""


import common as C


def main(argv=None):
    return C.family_figure(
        argv, script="fig07.py", var="peak_transmissibility", boundary="peak_transmissibility",
        ylabel=C.TRANS_LABEL + r" (peak, $x_0/Y$)",
        title="Fig. 7: base motion, fixed wall: theory", xlim=(0, 5), ylim=(0, 5),
    )


if __name__ == "__main__":
    main()
