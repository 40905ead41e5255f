"""The backbone: how friction softens and damps the structure with amplitude, read along the phase-resonance
curve (phase_resonance.py: the first harmonic lags the forcing by 90 degrees, the forcing then balancing
the dissipation alone). At every phase-resonance point r* of each friction level beta the exact orbit there
(the method's simulation, Problem.rows) gives, in the kernel's units (force: F0/k and F0^2/k; base: Y and kY^2):

    amplitude       T, the first-harmonic amplitude of q (= x: see SCENES)
    peak_amplitude  a = max |q| over the orbit
    E_d             the energy dissipated per forcing period: the forcing's work
                        E_d = W = pi A T sin(phase)                       (docs/equations.md §6)
                    (only q's first harmonic does work against A cos(r t); exact, the dashpot's loss included)
    E_f             friction_energy, the slider's share of E_d (the dashpot's is E_d - E_f)
    E_p             the potential energy of the springs at the orbit's maximum displacement |q| = a:
                        E_p = a^2 / 2 + kappa s^2 / 2
                    s the Jenkins spring's stretch there (kappa = 0: the rigid contact, no such spring).
                    Where the slider slips, s = beta_k / kappa: a slip ends at the mass's velocity zero
                    with the spring at its limit, |kappa s| = beta_k (docs/equations.md §7), and the
                    largest displacement is such a turning point. Where it never slips, the contact is a
                    spring about the slider's fixed position w (end_w, wherever the start left it): the
                    orbit is linear about its centre q0 = kappa w / (1 + kappa), and a and s are measured
                    from there, a - |q0| both (a preload the start left is no energy of the oscillation).
                    Without friction (beta = 0) the spring carries nothing: s = 0.
    zeta_eq         = E_d / (4 pi E_p)    (the equivalent damping ratio; Chopra's, with the stored energy)

Limits: without friction the phase resonance is r* = 1 and zeta_eq = (2 pi zeta r a^2) / (2 pi a^2) = zeta
(E_d = 2 pi zeta r T^2, the linear dashpot's loss); with a stuck Jenkins contact, r* = sqrt(1 + kappa).

Coulomb friction is homogeneous: scaling the forcing and the friction together scales the motion (the
Jenkins spring's stretch too), so the curve over beta at the scene's forcing is the curve over amplitude
at one friction force: T and a are the amplitude per forcing, beta the friction per forcing.

SCENES: the backbone needs q = x and the forcing in phase with the excitation, so that the phase
resonance is q's quadrature with its own forcing: the force scene, and base with the dashpot (if any)
to the ground. joined (q = z = x - y) and base with the dashpot to the base (its forcing leads) are
refused by `refusal`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from friction_sweep.codes import Regime
from friction_sweep.design import phase_resonance
from friction_sweep.design.peak import R_TOL, Problem
from friction_sweep.kernels import steady
from friction_sweep.methods import event


@dataclass
class Backbone:
    """Every phase-resonance point of each friction level and its orbit's measures (module docstring),
    (levels, size) each, in increasing r, NaN-padded."""

    frequency_ratio: np.ndarray
    amplitude: np.ndarray
    peak_amplitude: np.ndarray
    regime: np.ndarray
    dissipated_energy: np.ndarray
    friction_energy: np.ndarray
    potential_energy: np.ndarray
    damping_ratio: np.ndarray


def refusal(problem: Problem) -> str | None:
    """Why the backbone is not defined for the problem's scene (SCENES in the module docstring), or None."""
    r = np.array([0.5, 1.0, 2.0])
    _, c, _, _, _ = event.point_parameters(problem.excitation, r, 0.0 * r, problem.effects)
    if np.any(c != 0.0) or np.any(event.forcing_lead(problem.excitation, r, problem.effects) != 0.0):
        return ("the backbone is the phase resonance of the mass against its own forcing: scene force, or base "
                "with the dashpot (if any) to the ground")
    return None


def potential_energy(a: np.ndarray, beta: np.ndarray, kappa: float, slips: np.ndarray,
                     end_w: np.ndarray) -> np.ndarray:
    """E_p = a^2/2 + kappa s^2/2 at the largest displacement a (module docstring): a^2 (1 + kappa)/2 about
    the centre of an orbit whose slider never slips."""
    if kappa <= 0.0:
        return 0.5 * a * a
    slipping = (slips > 0) | (beta == 0.0)
    about = np.where(slipping, a, a - np.abs(kappa * end_w / (1.0 + kappa)))  # from the stuck orbit's centre
    s = np.where(slipping, beta / kappa, about)
    return 0.5 * about * about + 0.5 * kappa * s * s


def backbone(problem: Problem, r: np.ndarray, beta: np.ndarray, r_tol: float = R_TOL) -> Backbone:
    """The backbone over the increasing frequency grid r (the search grid of phase_resonance.crossings) for
    each friction level in beta (1-D)."""
    reason = refusal(problem)
    if reason is not None:
        raise ValueError(reason)
    beta = np.atleast_1d(np.asarray(beta, dtype=float))
    cross = phase_resonance.crossings(problem, r, beta, r_tol)
    out = Backbone(*(np.full(cross.frequency_ratio.shape, np.nan) for _ in fields(Backbone)))
    level, k = np.nonzero(np.isfinite(cross.frequency_ratio))
    if level.size == 0:
        return out
    rs, bs = cross.frequency_ratio[level, k], beta[level]
    rows = problem.rows(rs, bs)
    A = event.point_parameters(problem.excitation, rs, bs, problem.effects)[0]
    kappa = event.contact_stiffness(problem.effects)
    t = rows[:, steady.OUT_TRANSMISSIBILITY]
    a = rows[:, steady.OUT_PEAK_TRANSMISSIBILITY]
    e_d = np.pi * A * t * np.sin(np.radians(rows[:, steady.OUT_PHASE]))
    if kappa > 0.0:
        from friction_sweep.kernels import jenkins_steady

        slips, end_w = rows[:, jenkins_steady.JOUT_SLIPS], rows[:, jenkins_steady.JOUT_END_W]
    else:
        slips = end_w = np.zeros_like(rs)
    e_p = potential_energy(a, bs, kappa, slips, end_w)
    settled = np.isin(rows[:, steady.OUT_REGIME], (Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS))
    values = {"frequency_ratio": rs, "amplitude": t, "peak_amplitude": a, "regime": rows[:, steady.OUT_REGIME],
              "dissipated_energy": e_d, "friction_energy": rows[:, steady.OUT_FRICTION_ENERGY],
              "potential_energy": e_p, "damping_ratio": e_d / (4.0 * np.pi * e_p)}
    for name, v in values.items():
        getattr(out, name)[level, k] = v if name in ("frequency_ratio", "regime") else np.where(settled, v, np.nan)
    return out


def dataset(found: Backbone, beta: np.ndarray, attrs: dict, axes=None, potential: str | None = None):
    """The backbone as an xarray Dataset over (force_ratio, crossing): backbone_* per variable of Backbone,
    `damping_ratio` being zeta_eq. `axes` (peak.Axes) names a structure's: (friction_scale, crossing), the
    frequency backbone_frequency, regime and friction_energy per contact; `potential` says what E_p is."""
    import xarray as xr

    from friction_sweep.design import peak

    axes = peak.ONE_DOF if axes is None else axes
    dims = (axes.friction, "crossing")

    def entry(name: str):
        v = getattr(found, name)
        return (dims + ("contact",) * (v.ndim - 2), v)

    names = {f.name: f"backbone_{axes.frequency if f.name == 'frequency_ratio' else f.name}" for f in fields(Backbone)}
    coords = {axes.friction: np.asarray(beta, dtype=float), "crossing": np.arange(found.frequency_ratio.shape[1])}
    if axes.contacts is not None:
        coords["contact"] = np.array(axes.contacts, dtype=str)
    ds = xr.Dataset({names[f.name]: entry(f.name) for f in fields(Backbone)}, coords=coords,
                    attrs={**attrs, "potential_energy": potential or "a^2/2 + kappa s^2/2 at the largest "
                           "displacement a (s: the Jenkins spring's stretch there)",
                           "damping_ratio": "E_d / (4 pi E_p), E_d the forcing's work per period"})
    return ds
