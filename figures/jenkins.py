"""The Jenkins contact (not in the paper; issue 19): base motion with a fixed wall, the contact a tangential
spring k_t = kappa k in series with the Coulomb slider (docs/equations.md §7). One panel per force ratio,
the first-harmonic transmissibility against r at several kappa (colours), kappa -> oo being the rigid
contact (black; Den Hartog's theory dashed where it forecasts continuous motion). The line style tells the
simulation's regime: solid continuous, dashed stick-slip, dotted stuck (the slider's state: the mass then
vibrates on the contact spring, a linear oscillator whose resonance r = sqrt(1 + kappa) is ticked on the
axis). Near that resonance the stuck response outgrows beta / kappa and the slider slips, which softens
the contact: the peaks of small kappa lie between r = 1 and sqrt(1 + kappa). As kappa grows the curves
close in on the rigid one. Gaps: unbounded (r = 1 below pi/4) and unsettled points.

    python figures/jenkins.py results/numerical/jenkins_base_kappa1.nc ... \
        results/numerical/jenkins_base_rigid.nc figures/out/jenkins.png

The cubes may come in any order; the one without `contact_stiffness` is the rigid contact.
"""


import common as C
import numpy as np
from matplotlib.lines import Line2D

from friction_sweep.catalogue import effect_value
from friction_sweep.codes import Regime
from friction_sweep.methods import theory

VAR = "transmissibility"
#: the line style of each regime the simulation reports (others are left out: gaps)
STYLES = {int(Regime.CONTINUOUS): "-", int(Regime.STICK_SLIP): "--", int(Regime.STUCK): ":"}


def kappa_of(ds) -> float:
    """The cube's contact stiffness; inf for the rigid contact (effect not declared)."""
    kappa = effect_value(C.effects_of(ds), "contact_stiffness")
    return float(kappa) if kappa > 0 else np.inf


def by_regime(ax, r, y, codes, color, lw):
    """y against r, each run of one regime in its style; a run is drawn on to the next run's first point,
    so the curve stays joined where the regime changes."""
    codes = np.asarray(codes).astype(int)
    start = 0
    for i in range(1, r.size + 1):
        if i < r.size and codes[i] == codes[start]:
            continue
        style = STYLES.get(int(codes[start]))
        if style is not None:
            stop = i + 1 if i < r.size and int(codes[i]) in STYLES else i
            ax.plot(r[start:stop], y[start:stop], style, color=color, lw=lw)
        start = i


def main(argv=None):
    paths, out = C.parse_args(argv, "python figures/jenkins.py CUBE.nc [CUBE.nc ...] OUT.png")
    cubes = [C.open_cube(p) for p in paths]
    for ds, path in zip(cubes, paths, strict=True):
        C.require(ds, path, VAR, "regime")
    cubes.sort(key=kappa_of)
    kappas = [kappa_of(ds) for ds in cubes]
    finite = [k for k in kappas if np.isfinite(k)]
    palette = dict(zip(finite, C.colors(len(finite), "plasma"), strict=True))
    betas = cubes[0]["force_ratio"].values
    fig, axes = C.new_figure(1, len(betas), size=(4.0 * len(betas), 4.4), sharey=True)
    for ax, beta in zip(axes[0], betas, strict=True):
        for ds, kappa in zip(cubes, kappas, strict=True):
            r = ds["frequency_ratio"].values
            sel = ds.sel(force_ratio=beta)
            y = np.where(np.isfinite(sel[VAR].values), sel[VAR].values, np.nan)
            if np.isfinite(kappa):
                colour = palette[kappa]
                by_regime(ax, r, y, sel["regime"].values, colour, 1.2)
                resonance = np.sqrt(1.0 + kappa)  # the stuck slider's linear oscillator
                if r.min() <= resonance <= r.max():
                    ax.axvline(resonance, ymax=0.04, color=colour, lw=2.5)
            else:
                by_regime(ax, r, y, sel["regime"].values, "k", 2.0)
                dh = theory.compute_points("base", r, np.full(r.shape, beta), ["transmissibility", "regime"])
                dh_y = np.where(dh["regime"] == Regime.CONTINUOUS, dh[VAR], np.nan)
                ax.plot(r, dh_y, color="tab:cyan", lw=1.0, dashes=(1, 1.5))
        ax.set(xlabel=C.R_LABEL, title=C.ratio_label("base", beta), xlim=(float(r.min()), float(r.max())), ylim=(0, 5))
    axes[0, 0].set_ylabel(C.TRANS_LABEL + " (first harmonic)")
    handles = [Line2D([], [], color=palette[k], label=rf"$\kappa = {k:g}$") for k in finite]
    if not all(np.isfinite(kappas)):
        handles += [Line2D([], [], color="k", lw=2.0, label=r"rigid ($\kappa \to \infty$)"),
                    Line2D([], [], color="tab:cyan", lw=1.0, dashes=(1, 1.5), label="Den Hartog (rigid, continuous)")]
    handles += [Line2D([], [], ls=s, color="0.3", label=C.REGIME_NAMES[c]) for c, s in STYLES.items()]
    handles.append(Line2D([], [], color="0.3", lw=2.5, label=r"tick: $r = \sqrt{1+\kappa}$"))
    axes[0, -1].legend(handles=handles, loc="upper right")
    fig.suptitle("Jenkins contact (contact spring κ in series with the slider): base motion, fixed wall, "
                 "event simulation")
    return C.save(fig, out)


if __name__ == "__main__":
    main()
