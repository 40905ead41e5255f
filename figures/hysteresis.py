"""Hysteresis of a friction damper with static friction (not in the paper): the transmissibility of
stepped-sine sweeps up and down in frequency (each point started from its neighbour's orbit, as a rig
is run), over the two states the default cube reports at each point (from rest, from a moving start).
Where the sweeps differ (shaded) the damper has two steady states: the band a rig shows as hysteresis.

    python figures/hysteresis.py UP.nc DOWN.nc STARTS.nc OUT.png
"""


import common as C
import numpy as np

from friction_sweep.catalogue import effect_value
from friction_sweep.methods.event import SAME_STATE_RTOL


def main(argv=None):
    (up_path, down_path, starts_path), out = C.parse_args(
        argv, "python figures/hysteresis.py UP.nc DOWN.nc STARTS.nc OUT.png", 3)
    up, down, starts = (C.open_cube(p) for p in (up_path, down_path, starts_path))
    C.require(starts, starts_path, "transmissibility", "transmissibility_moving")
    beta = float(up["force_ratio"].values[0])
    r = up["frequency_ratio"].values
    t_up = up["transmissibility"].values[0]
    t_down = down["transmissibility"].values[0]
    band = ~np.isclose(t_up, t_down, rtol=SAME_STATE_RTOL, equal_nan=True)  # the cube's own test of one state
    fig, axes = C.new_figure()
    ax = axes[0, 0]
    for lo, hi in _runs(r, band):
        ax.axvspan(lo, hi, color="0.88", lw=0)
    ax.plot(r, starts["transmissibility"].values[0], "o", ms=2.5, color="tab:blue", label="from rest")
    ax.plot(r, starts["transmissibility_moving"].values[0], "o", ms=2.5, mfc="none", color="tab:orange",
            label="from a moving start")
    ax.plot(r, t_up, "-", color="tab:blue", lw=1.2, label="sweep up")
    ax.plot(r, t_down, "--", color="tab:red", lw=1.2, label="sweep down")
    mu = effect_value(C.effects_of(up), "static_friction_ratio")
    ax.set(xlabel=C.R_LABEL, ylabel=C.TRANS_LABEL + " (first harmonic)", ylim=(0, 5),
           title=f"Hysteresis: joined, {C.ratio_label('joined', beta)}, static/kinetic {mu:g} "
                 f"(shaded: up and down differ)")
    ax.legend(loc="upper right")
    return C.save(fig, out)


def _runs(r, mask):
    """(start, end) of each run of True in mask, widened by half a grid step."""
    half = 0.5 * np.diff(r).min() if r.size > 1 else 0.0
    runs, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if start is not None and (not m or i == mask.size - 1):
            end = i if m else i - 1
            runs.append((r[start] - half, r[end] + half))
            start = None
    return runs


if __name__ == "__main__":
    main()
