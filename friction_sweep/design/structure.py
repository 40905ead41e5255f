"""The designer's answers for a structure (issue 32 on the multi-DoF engine, DESIGN §7): the resonance peak
of one mass, the friction_scale that minimises it, and the backbone, each by the 1-DoF search (peak.py,
optimum.py, phase_resonance.py) reading the structure's response instead of a 1-DoF scene's.

The response: the chosen mass's (`settings: {peak_dof: NAME}`; by default the one forced mass under force
excitation, else the first mass) first-harmonic amplitude |X_i| (variable `transmissibility`; over the base's
amplitude Y under base excitation, the cube's `amplitude`) or max |x_i| over the orbit (`peak_transmissibility`,
the cube's `peak_amplitude`), against the angular frequency w (the engine's, dimensionless where the structure
is physical: spec.structure_units) and friction_scale s, solved point by point on the exact engine
(structures.solve_points). Its phase is the mass's lag behind the excitation cos wt, its regime one code per
contact. As for a 1-DoF scene, an unbounded point counts as +inf, an unsettled one as -inf.

The backbone (force excitation): at every phase resonance of the chosen mass (its first harmonic lags the
forcing by 90 degrees), from the exact orbit's first harmonics X (x = Re(X e^{iwt})) and contact energies:

    E_d   the forcing's work per period, pi sum_i F_i |X_i| sin(phi_i) (only the first harmonic works against
          F cos wt): the energy dissipated per period, the friction's and the dashpots' together
    E_f   the contacts' friction energy per period (the engine's, per contact)
    E_p   the largest elastic energy of the first-harmonic motion over the period,
              max_t 1/2 x1(t)^T K_s x1(t) = (X^H K_s X + |X^T K_s X|) / 4,
          K_s the structure's springs plus k_t w_j w_j^T of each Jenkins contact held all period (its spring
          acts about the slider's fixed position; the offset is no first harmonic), plus, for each Jenkins
          contact that slips, its spring's energy at the slip limit (mu_j s)^2 / (2 k_t), as the 1-DoF
          backbone (design/backbone.py) takes it. Rigid contacts store nothing. For one mass this is the
          first harmonic's T^2/2 where the 1-DoF backbone takes max|x|^2/2: the two agree where the orbit is
          harmonic (the linear limits).
    zeta_eq = E_d / (4 pi E_p)

Without friction and with one mode near the phase resonance zeta_eq is that mode's damping ratio.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.design import backbone as one_dof_backbone
from friction_sweep.design import phase_resonance
from friction_sweep.design.peak import R_TOL, Axes
from friction_sweep.structures.model import Assembled
from friction_sweep.theory.phase import complex_amplitude

#: the variables a structure's peak is taken of: the 1-DoF names, and the cube variable each reads
VARIABLES = {"transmissibility": "amplitude", "peak_transmissibility": "peak_amplitude"}
#: the spec setting that chooses the mass (settings: {peak_dof: NAME})
DOF_SETTING = "peak_dof"
#: what a structure's backbone_potential_energy is (the Dataset's attribute)
POTENTIAL = ("the largest elastic energy of the first-harmonic motion, (X^H K_s X + |X^T K_s X|)/4, K_s the springs "
             "and each Jenkins contact held all period; plus (mu s)^2/(2 k_t) per slipping Jenkins contact")
#: the engine's outputs the search reads (regime brings steady_state)
_OUTPUTS = ("amplitude", "phase", "regime")


def default_dof(a: Assembled) -> str:
    """The mass whose peak is taken where the spec names none: the one forced mass (force excitation), else
    the first mass."""
    forced = np.nonzero(a.F_cos)[0] if a.excitation == "force" else np.zeros(0, dtype=int)
    return a.dof_names[int(forced[0])] if forced.size == 1 else a.dof_names[0]


def axes(a: Assembled) -> Axes:
    """The Datasets' axes: friction_scale, the angular frequency, the contacts."""
    return Axes(friction="friction_scale", frequency="frequency", contacts=a.contact_names)


@dataclass(frozen=True)
class StructureProblem:
    """The response of mass `dof` of an assembled structure (the module docstring): peak.Response."""

    assembled: Assembled
    dof: str
    settings: dict[str, Any] | None = None
    variable: str = "transmissibility"

    def __post_init__(self) -> None:
        if self.variable not in VARIABLES:
            raise ValueError(f"the peak is taken of {', '.join(VARIABLES)} (got {self.variable!r})")
        if self.dof not in self.assembled.dof_names:
            raise ValueError(f"{self.dof!r} is not a mass of the structure ({', '.join(self.assembled.dof_names)})")

    @property
    def index(self) -> int:
        return self.assembled.dof_names.index(self.dof)

    def points(self, w: np.ndarray, s: np.ndarray, outputs=_OUTPUTS) -> dict[str, np.ndarray]:
        """The engine's arrays at the points (w[i], s[i]) (structures.solve_points)."""
        from friction_sweep.structures import solve_points

        return solve_points(self.assembled, w, s, dict(self.settings or {}), outputs)

    def solve(self, w: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(value, regime per contact (P, m) as floats, phase in degrees) of the chosen mass at the points."""
        out = self.points(np.asarray(w, dtype=float), np.asarray(s, dtype=float))
        i = self.index
        value = np.array(out[VARIABLES[self.variable]][:, i], dtype=float)
        steady = out["steady_state"]
        value = np.where(steady == SteadyState.CONVERGED, value, -np.inf)
        value = np.where(steady == SteadyState.GROWING, np.inf, value)
        return value, out["regime"].astype(float), np.array(out["phase"][:, i], dtype=float)


def backbone_refusal(problem: StructureProblem) -> str | None:
    """Why the backbone is not defined for the structure (its phase resonance is the mass's lag behind its
    own forcing: force excitation), or None."""
    if problem.assembled.excitation != "force":
        return "a structure's backbone is the phase resonance against a force: excitation force"
    return None


def potential_energy(a: Assembled, X: np.ndarray, s: np.ndarray, regime: np.ndarray,
                     slips: np.ndarray | None) -> np.ndarray:
    """E_p (module docstring) at each point: X (P, n) complex first harmonics, s (P,) friction scales, regime
    (P, m) per contact, slips (P, m) per contact (None without a Jenkins contact)."""
    e_p = np.zeros(X.shape[0])
    for p in range(X.shape[0]):
        K = a.K.copy()
        extra = 0.0
        for j in range(a.kt.size):
            if a.kt[j] <= 0.0:
                continue
            if regime[p, j] == Regime.STUCK:
                K += a.kt[j] * np.outer(a.W[j], a.W[j])
            elif slips is not None and slips[p, j] > 0:
                extra += (a.mu[j] * s[p]) ** 2 / (2.0 * a.kt[j])
        x = X[p]
        e_p[p] = 0.25 * (np.real(np.conj(x) @ K @ x) + abs(x @ K @ x)) + extra
    return e_p


def backbone(problem: StructureProblem, w: np.ndarray, s: np.ndarray, r_tol: float = R_TOL):
    """The backbone (design.backbone.Backbone, the frequency in its frequency_ratio; regime and
    friction_energy per contact) over the increasing frequency grid w for each friction scale in s."""
    reason = backbone_refusal(problem)
    if reason is not None:
        raise ValueError(reason)
    a = problem.assembled
    s = np.atleast_1d(np.asarray(s, dtype=float))
    cross = phase_resonance.crossings(problem, w, s, r_tol)
    shape, m = cross.frequency_ratio.shape, len(a.contact_names)
    per_contact = ("regime", "friction_energy")
    out = one_dof_backbone.Backbone(*(np.full(shape + ((m,) if f.name in per_contact else ()), np.nan)
                                      for f in fields(one_dof_backbone.Backbone)))
    level, k = np.nonzero(np.isfinite(cross.frequency_ratio))
    if level.size == 0:
        return out
    ws, ss = cross.frequency_ratio[level, k], s[level]
    res = problem.points(ws, ss, ("amplitude", "phase", "regime", "friction_energy"))
    X = complex_amplitude(res["amplitude"], res["phase"])  # amplitude unit 1 under force excitation
    e_d = -np.pi * np.sum(a.F_cos[None, :] * X.imag, axis=1)  # pi sum_i F_i |X_i| sin(phase_i)
    e_p = potential_energy(a, X, ss, res["regime"], res.get("slips_per_period") if (a.kt > 0).any() else None)
    i = problem.index
    settled = res["steady_state"] == SteadyState.CONVERGED
    values = {"frequency_ratio": ws, "amplitude": res["amplitude"][:, i], "peak_amplitude": res["peak_amplitude"][:, i],
              "regime": res["regime"].astype(float), "dissipated_energy": e_d,
              "friction_energy": res["friction_energy"], "potential_energy": e_p,
              "damping_ratio": e_d / (4.0 * np.pi * e_p)}
    for name, v in values.items():
        keep = v if name in ("frequency_ratio", "regime") else np.where(
            settled.reshape(settled.shape + (1,) * (np.ndim(v) - 1)), v, np.nan)
        getattr(out, name)[level, k] = keep
    return out
