"""Paper Fig. 8: the transition force ratio beta*(r) between continuous and stick-slip motion, base
motion with a fixed wall (cube variable `continuous_limit`), with its asymptote 2/sqrt(4 + pi^2)
for r -> infinity (Eq. 25) and its maximum (Eq. 26) marked; above beta = 1 the mass never moves.

    python figures/fig08.py results/fig08_transition_force_ratio.nc figures/out/fig08.png
"""


import common as C
import numpy as np

ASYMPTOTE = 2.0 / np.sqrt(4.0 + np.pi**2)  # 0.5370


def refined_maximum(r, limit):
    """The maximum of beta*(r): the best grid point, refined between its neighbours with the theory."""
    from scipy.optimize import minimize_scalar

    from friction_sweep.theory import den_hartog as dh

    i = int(np.nanargmax(np.where(np.isfinite(limit), limit, -np.inf)))
    lo, hi = r[max(i - 1, 0)], r[min(i + 1, r.size - 1)]
    if hi <= lo:
        return float(r[i]), float(limit[i])
    res = minimize_scalar(lambda x: -float(dh.continuous_limit(np.array([x]))[0]), bounds=(lo, hi),
                          method="bounded", options={"xatol": 1e-9})
    if not res.success or -res.fun < limit[i]:
        return float(r[i]), float(limit[i])
    return float(res.x), float(-res.fun)


def main(argv=None):
    (path,), out = C.parse_args(argv, "python figures/fig08.py CUBE.nc OUT.png", 1)
    ds = C.open_cube(path)
    C.require(ds, path, "continuous_limit")
    r = ds["frequency_ratio"].values
    limit = ds["continuous_limit"].values
    fig, axes = C.new_figure()
    ax = axes[0, 0]
    ax.fill_between(r, limit, 1.0, color=C.REGIME_COLORS[1], alpha=0.6, lw=0, label="stick-slip")
    ax.axhspan(1.0, 1.1, color=C.REGIME_COLORS[0], alpha=0.6, lw=0, label=r"stuck ($F_\mu/F_k \geq 1$)")
    ax.plot(r, limit, color="k", lw=1.6, label=r"transition force ratio $\beta^*(r)$")
    ax.axhline(ASYMPTOTE, color="tab:blue", ls="--", lw=1.1,
               label=rf"asymptote $2/\sqrt{{4+\pi^2}} = {ASYMPTOTE:.4f}$")
    ok = np.isfinite(limit)
    if ok.any():
        r_max, b_max = refined_maximum(r, limit)
        ax.plot(r_max, b_max, "o", color="tab:red", ms=6, label=rf"maximum {b_max:.4f} at $r = {r_max:.4f}$")
        ax.annotate(f"{b_max:.4f}", (r_max, b_max), xytext=(8, 6), textcoords="offset points", color="tab:red")
    ax.text(0.97, 0.3, "continuous motion", transform=ax.transAxes, ha="right", va="center")
    ax.set(xlabel=C.R_LABEL, ylabel=C.FORCE_RATIO_LABEL,
           title="Fig. 8: transition force ratio, base motion with a fixed wall")
    ax.set_xlim(r.min(), r.max())
    ax.set_ylim(0.0, 1.1)
    ax.legend(loc="lower right")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
