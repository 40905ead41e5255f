"""Den Hartog's theory as a sweep method: closed forms on one tile of the (beta, r) grid.

Validity and the forecast regime, for friction ratio beta (the scene's convention) at r:

    stuck       force/base: beta >= 1 (paper Eq. 24);  joined: beta >= r^2 (Eq. 41-42)
    unbounded   r = 1 and b <= pi/4 (b = beta, or beta/r^2 for joined; Eqs. 14-15)
    continuous  b == 0 (linear, r != 1), or b <= beta*(r) (Eq. 16 / 23b / 40)
    stick_slip  everything else

Ties (friction_sweep.ties, shared with the simulation): beta = 1 (or r^2) is stuck, as the paper's
Eqs. (24) and (41) put it, and so is beta within TIE_RTOL below it; r within TIE_RTOL of 1 is r = 1,
where b up to pi/4 (1 + TIE_RTOL) is unbounded: the finite peak needs b > pi/4 strictly, since at
b = pi/4 the continuous amplitude still diverges like 1/sqrt|1 - r| (the event simulation agrees: the
amplitude keeps growing). b exactly beta*(r) is continuous: there the velocity only touches zero (a
grazing contact) and the mass never rests for a positive time; the simulation counts such contacts,
and any stick shorter than 1e-10 of a period, as grazing, not as stops. r^2 is the double-precision
product r*r.

Numbers are written only where the theory backs them: continuous points get every output; stuck
points get the exact no-motion values (force/base: no motion, transmissibility 0, phases undefined;
joined: the mass rides with the wall, transmissibility 1, phase 0; friction energy 0 and the
transmitted force of that motion); stick_slip and unbounded points get NaN and their regime.
"""

from __future__ import annotations

import numpy as np

from friction_sweep import catalogue, ties
from friction_sweep.codes import Regime
from friction_sweep.theory import den_hartog as dh
from friction_sweep.theory import joined, scenes
from friction_sweep.theory.phase import wrap_lag_degrees
from friction_sweep.theory.transmitted import transmitted_force

CATALOGUE = catalogue.method("theory")

#: what this method writes for each requested output group, per excitation
VARIABLES = {
    "transmissibility": ("transmissibility", "peak_transmissibility"),
    "phase": ("phase", "peak_phase"),
    "regime": ("regime", "stops_per_period"),
    "friction_energy": ("friction_energy",),
    "transmitted_force": ("transmitted_force",),
}
JOINED_EXTRA = {
    "transmissibility": ("relative_peak_amplitude",),
    "phase": ("relative_peak_phase", "peak_phase_xz"),
}


def variables_for(excitation: str, outputs) -> tuple[str, ...]:
    """Per-point variable names this method writes for the requested output groups."""
    names: list[str] = []
    for group in outputs:
        names.extend(VARIABLES[group])
        if excitation == "joined":
            names.extend(JOINED_EXTRA.get(group, ()))
    return tuple(names)


def forecast_regime(excitation, r, beta, beta_star):
    """Regime forecast on broadcast arrays (see the module docstring for the rules and ties)."""
    r, beta, beta_star = np.broadcast_arrays(r, beta, beta_star)
    b = scenes.friction_ratio(excitation, r, beta)
    stuck = ties.never_moves(scenes.forcing_amplitude(excitation, r), beta)
    at_resonance = ties.at_resonance(r)
    continuous = ((b == 0.0) | (b <= beta_star)) & ~at_resonance
    code = np.full(r.shape, Regime.STICK_SLIP, dtype=np.int8)
    code[continuous] = Regime.CONTINUOUS
    code[at_resonance & (b <= dh.RESONANCE_FRICTION_LIMIT * (1.0 + ties.TIE_RTOL))] = Regime.UNBOUNDED
    code[stuck] = Regime.STUCK
    return code


def continuous_limit(excitation, r):
    """beta*(r) in the scene's force-ratio convention: r^2 beta*(r) for joined (Eq. 40)."""
    r = np.asarray(r, dtype=float)
    return _in_scene_convention(excitation, r, dh.continuous_limit(r))


def _in_scene_convention(excitation, r, bstar):
    return scenes.forcing_amplitude(excitation, r) * bstar


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None) -> dict[str, np.ndarray]:
    """All requested outputs on the tile beta x r, arrays of shape (len(beta), len(r)).

    Returns the per-point variables plus `continuous_limit` (shape (len(r),)). The theory models
    no effects and has no settings (the spec layer refuses both before this is called).
    """
    if effects:
        raise ValueError(f"the theory models no effects (got {sorted(effects)})")
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    bstar = dh.continuous_limit(r)
    R, B = np.meshgrid(r, beta)
    out = compute_points(excitation, R, B, outputs, np.broadcast_to(bstar[None, :], R.shape))
    out["continuous_limit"] = _in_scene_convention(excitation, r, bstar)
    return out


def compute_points(excitation: str, r, beta, outputs, bstar=None) -> dict[str, np.ndarray]:
    """The requested outputs at the points (r, beta) (arrays of one shape), without `continuous_limit`;
    bstar: Den Hartog's beta*(r) at each point where the caller has it (else computed)."""
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    if bstar is None:
        bstar = dh.continuous_limit(r)
    code = forecast_regime(excitation, r, beta, bstar)
    names = variables_for(excitation, outputs)
    out = {name: np.full(r.shape, np.nan) for name in names if name != "regime"}
    if "regime" in names:
        out["regime"] = code
        out["stops_per_period"] = np.where(
            (code == Regime.CONTINUOUS) | (code == Regime.STUCK), 0.0, np.nan
        )
    _fill_stuck(excitation, out, code == Regime.STUCK, r)
    sel = code == Regime.CONTINUOUS
    if np.any(sel):
        _fill_continuous(excitation, out, r[sel], beta[sel], sel)
    return out


def _put(out, name, sel, values):
    if name in out:
        out[name][sel] = values


def _fill_stuck(excitation, out, sel, R):
    _put(out, "friction_energy", sel, 0.0)  # nothing slides
    if excitation == "joined":  # the mass rides with the wall: x = y exactly
        for name, value in (
            ("transmissibility", 1.0),
            ("peak_transmissibility", 1.0),
            ("phase", 0.0),
            ("peak_phase", 0.0),
            ("relative_peak_amplitude", 0.0),
        ):
            _put(out, name, sel, value)
        _put(out, "transmitted_force", sel, transmitted_force(excitation, R[sel], 1.0, 0.0))
    else:  # no motion: amplitude 0, phase undefined (stays NaN)
        _put(out, "transmissibility", sel, 0.0)
        _put(out, "peak_transmissibility", sel, 0.0)
        _put(out, "transmitted_force", sel, transmitted_force(excitation, R[sel], 0.0, np.nan))


def _fill_continuous(excitation, out, r, beta, sel):
    b = scenes.friction_ratio(excitation, r, beta)
    x0 = dh.amplitude(r, b)
    phi = dh.phase(r, b)
    a1, b1 = dh.first_harmonic(r, b)
    # friction dissipates beta x the sliding distance, 4 x the peak amplitude of q (q = z for joined: r^2 x0)
    _put(out, "friction_energy", sel, 4.0 * beta * scenes.forcing_amplitude(excitation, r) * x0)
    if excitation == "joined":
        # x = z + y: first harmonic r^2 (a1, b1) + (cos phi, -sin phi); y lags nothing (theta_y = -phi)
        xa = r * r * a1 + np.cos(phi)
        xb = r * r * b1 - np.sin(phi)
        _put(out, "transmissibility", sel, np.hypot(xa, xb))
        _put(out, "phase", sel, wrap_lag_degrees(np.arctan2(xb, xa) + phi))
        _put(out, "transmitted_force", sel, transmitted_force(excitation, r, np.hypot(xa, xb), np.nan))
        _put(out, "relative_peak_amplitude", sel, r * r * x0)  # Eq. 34: z0 / Y
        _put(out, "relative_peak_phase", sel, wrap_lag_degrees(phi))  # phi_yz, Eq. 33
        if "peak_transmissibility" in out or "peak_phase" in out:
            peak, t_pos = _per_frequency(joined.peak_of_absolute, r, b, phi)
            theta_x = r * t_pos  # phase position of the maximum of x; z peaks at 0, y at -phi
            _put(out, "peak_transmissibility", sel, peak)  # Eq. 37
            _put(out, "peak_phase", sel, wrap_lag_degrees(theta_x + phi))  # phi_xy, Eq. 44
            _put(out, "peak_phase_xz", sel, wrap_lag_degrees(-theta_x))  # phi_xz, Eq. 43
    else:
        _put(out, "transmissibility", sel, np.hypot(a1, b1))
        _put(out, "phase", sel, wrap_lag_degrees(np.arctan2(b1, a1) + phi))
        _put(out, "transmitted_force", sel, transmitted_force(excitation, r, np.hypot(a1, b1),
                                                              wrap_lag_degrees(np.arctan2(b1, a1) + phi)))
        _put(out, "peak_transmissibility", sel, x0)  # Eq. 11 / 21-22
        _put(out, "peak_phase", sel, wrap_lag_degrees(phi))  # Eq. 10 / 20


def _per_frequency(fun, r, *args):
    """fun(r, *args) column by column: its sampling is sized by r (~16/r samples a period), so one
    call over a tile spanning 0.01..100 would allocate 10^4 times more than each column needs."""
    out = [np.empty(r.shape), np.empty(r.shape)]
    for value in np.unique(r):
        at = r == value
        for o, part in zip(out, fun(r[at], *(a[at] for a in args)), strict=True):
            o[at] = part
    return out
