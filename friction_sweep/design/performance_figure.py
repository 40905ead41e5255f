"""The performance curve as a picture (fsweep optimize --plot; `make demo`): the resonance peak against
friction (fs.optimize's Dataset: optimum.py), the optimum marked, and Den Hartog's prediction where it
holds. In physical units where the spec has a `system:` (the Dataset's attributes reference_force, F_k in N,
and length_scale, L in m: friction force beta F_k, peak amplitude T L), else in (beta, T).

Den Hartog's prediction of the peak at beta is the largest of his closed-form first harmonic over the
frequencies where his continuous motion exists (regime continuous, beta below his limit beta*(r):
methods.theory, theory.den_hartog), on DH_POINTS frequency ratios over the search grid's range. It holds
where the exact peak's motion is continuous, and is drawn there only; elsewhere the peak lies in stick-slip,
which the closed form does not describe. Friction levels whose peak is infinite (no bounded resonance,
below pi/4 for an undamped mass), and every level below the largest such, are shaded, not drawn.

A structure's curve (design.structure: dim friction_scale, the Dataset's `dof` the mass) is drawn against
friction_scale, in the structure's units, without Den Hartog (a one-mass theory).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from friction_sweep.codes import Regime
from friction_sweep.methods import theory
from friction_sweep.theory import den_hartog, scenes

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

#: frequency ratios Den Hartog's closed form is maximised on
DH_POINTS = 20001


def den_hartog_peaks(excitation: str, beta: np.ndarray, r_lo: float, r_hi: float) -> np.ndarray:
    """Den Hartog's peak at each beta (module docstring); NaN where his motion exists at no frequency."""
    r = np.linspace(r_lo, r_hi, DH_POINTS)
    bstar = den_hartog.continuous_limit(r)
    limit = scenes.forcing_amplitude(excitation, r) * bstar  # beta*(r) in the scene's convention
    out = np.full(np.size(beta), np.nan)
    for j, b in enumerate(np.atleast_1d(beta)):
        th = theory.compute_points(excitation, r, np.full_like(r, b), ("transmissibility", "regime"), bstar)
        holds = (th["regime"] == Regime.CONTINUOUS) & (b < limit) & np.isfinite(th["transmissibility"])
        if holds.any():
            out[j] = float(np.max(th["transmissibility"][holds]))
    return out


def draw(ds: xr.Dataset) -> Figure:
    """The performance curve of fs.optimize's Dataset `ds` (its attribute frequency_ratio_range: the span of
    the frequency grid the peaks were searched on)."""
    from matplotlib.figure import Figure

    structure = "friction_scale" in ds.dims
    level = "friction_scale" if structure else "force_ratio"
    beta = ds[level].values
    peak = ds.resonance_peak.values
    physical = "reference_force" in ds.attrs and "length_scale" in ds.attrs
    # beta -> N and T -> mm where the spec has a system, else the ratios themselves
    force = float(ds.attrs["reference_force"]) if physical else 1.0
    mm = 1e3 * float(ds.attrs["length_scale"]) if physical else 1.0
    xs, ys = beta * force, peak * mm
    fig = Figure(figsize=(6.4, 4.2))
    ax = fig.add_subplot()
    unbounded = np.isinf(peak)
    if unbounded.any():  # and every level below the last unbounded one (beta = 0 undamped: 1/eps at r -> 1)
        unbounded[: int(np.nonzero(unbounded)[0].max()) + 1] = True
    finite = np.isfinite(ys) & (ys > 0) & ~unbounded
    refined = "in the angular frequency" if structure else "in r"
    ax.plot(xs[finite], ys[finite], "-o", ms=3, color="tab:blue",
            label=f"exact peak (event, refined to 1e-10 {refined})")
    if unbounded.any():
        edge = xs[unbounded].max()
        ax.axvspan(xs.min(), edge, color="tab:red", alpha=0.12, lw=0, label="no bounded resonance")
    if not structure:
        regime = ds.resonance_regime.values
        r_lo, r_hi = (float(v) for v in np.ravel(ds.attrs["frequency_ratio_range"]))
        dh = den_hartog_peaks(ds.attrs["excitation"], beta, r_lo, r_hi)
        holds = (regime == Regime.CONTINUOUS) & np.isfinite(dh) & finite
        if holds.any():
            ax.plot(xs[holds], (dh * mm)[holds], "--x", color="black", lw=1, ms=7,
                    label="Den Hartog (where the peak's motion is continuous)")
    opt_b, opt_p = float(ds[f"optimum_{level}"]), float(ds.optimum_peak)
    opt_x, opt_y = opt_b * force, opt_p * mm
    kind = ds.attrs.get("optimum_kind", "")
    what = f"optimum ({kind}): {opt_x:.4g} {'N' if physical else ''}".rstrip()
    ax.set_yscale("log")
    if opt_y > 0:
        ax.plot([opt_x], [opt_y], "*", ms=14, color="tab:green", label=what)
    else:  # a peak of 0 (the mass held): marked on the axis
        ax.axvline(opt_x, color="tab:green", lw=1.5, label=f"{what}, peak 0 (held)")
    if structure:
        ax.set_xlabel("friction_scale (normal load over the nominal one)")
        ax.set_ylabel(f"resonance peak of {ds.attrs['dof']}")
        ax.set_title(f"Resonance peak against friction (structure, {ds.attrs['excitation']} excitation)")
    else:
        ax.set_xlabel("friction force (N)" if physical else "force ratio β")
        ax.set_ylabel("resonance peak, amplitude (mm)" if physical else "resonance peak T")
        ax.set_title(f"Resonance peak against friction ({ds.attrs['excitation']} scene)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def save(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """The picture written as PNG, atomically (quicklook.save)."""
    from friction_sweep import quicklook

    return quicklook.save(draw(ds), path)
