"""The linear limits of a structure with friction contacts (DESIGN §7, "Checks"), in plain numpy: the
first harmonic X of every mass (x = Re(X e^{i w t})) with every contact free (zero friction) or stuck
(rigid contacts as constraints, Jenkins contacts as their springs). `fsweep check` holds a cube to them
(consistency_structure) and the worked example's figure draws them (figures/blade_damper.py).

    free:  (K - w^2 M + i w C) X = f
    stuck: X = x_p + N xi,  (N^T D N) xi = N^T (f + sum_Jenkins k_t w_j e_j Y - D x_p),
           D = K + sum_Jenkins k_t w_j w_j^T - w^2 M + i w C,  W_rigid x_p = e_rigid Y

f = F_cos - i w F_sin_per_w is the complex forcing (F under force excitation; Y (K_b + i w C_b) under base
excitation), N a basis of the rigid contacts' w_j.x = 0 and x_p the least-norm motion the rigid contacts
to the moving base impose. Constant offsets (where a contact stuck, a slider's position) do not reach the
first harmonic. None where the dynamic stiffness is singular to MAX_CONDITION (an undamped natural
frequency).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.structures.model import BASE, Assembled, stuck_matrices

#: condition number beyond which a linear limit is not computed (an undamped natural frequency)
MAX_CONDITION = 1e12


def forcing(a: Assembled, w: float) -> np.ndarray:
    """The complex forcing amplitude f (force = Re(f e^{iwt})): F_cos cos wt + w F_sin_per_w sin wt."""
    return a.F_cos - 1j * w * a.F_sin_per_w


def dynamic_stiffness(a: Assembled, w: float, K: np.ndarray | None = None) -> np.ndarray:
    """K - w^2 M + i w C (K: the structure's springs unless given)."""
    return (a.K if K is None else K) - w * w * a.M + 1j * w * a.C


def _conditioned(D: np.ndarray) -> bool:
    return bool(np.isfinite(D).all()) and np.linalg.cond(D) < MAX_CONDITION


def free_response(a: Assembled, w: float) -> np.ndarray | None:
    """X with every contact free (no friction): (K - w^2 M + i w C)^-1 f."""
    D = dynamic_stiffness(a, w)
    return np.linalg.solve(D, forcing(a, w)) if _conditioned(D) else None


def stuck_response(a: Assembled, w: float) -> np.ndarray | None:
    """X with every contact stuck (the module's docstring)."""
    Y = a.base_amplitude if a.excitation == BASE else 0.0
    rigid = a.kt == 0.0
    N, _, _ = stuck_matrices(a)
    K = a.K + (a.W.T * a.kt) @ a.W
    f = forcing(a, w) + a.W.T @ (a.kt * a.e * Y)
    Wr = a.W[rigid]
    xp = np.linalg.pinv(Wr) @ (a.e[rigid] * Y) if Wr.shape[0] else np.zeros(a.M.shape[0])
    if N.shape[1] == 0:
        return xp.astype(complex)
    D = dynamic_stiffness(a, w, K)
    Dr = N.T @ D @ N
    if not _conditioned(Dr):
        return None
    return xp + N @ np.linalg.solve(Dr, N.T @ (f - D @ xp))


def compliances(a: Assembled, w: float) -> tuple[np.ndarray, np.ndarray] | None:
    """(H f, H W^T) with H = (K - w^2 M + i w C)^-1: the free response and each contact's unit force's
    (rule `bound`); None where singular."""
    D = dynamic_stiffness(a, w)
    if not _conditioned(D):
        return None
    H = np.linalg.solve(D, np.column_stack([forcing(a, w), a.W.T]))
    return H[:, 0], H[:, 1:]
