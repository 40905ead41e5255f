"""The linear structure behind a structure spec (DESIGN §7), in plain numpy: its natural frequencies with
every contact stuck or free. Here, below the engine's layer, so that a spec can take a frequency ratio
against them (spec.structure_units); structures.model reads them from here.

    free:  K phi = omega^2 M phi
    stuck: N^T (K + sum_j k_t,j w_j w_j^T) N phi = omega^2 N^T M N phi,  N a basis of {x : w_j.x = 0, j rigid}
"""

from __future__ import annotations

import numpy as np


def null_space(A: np.ndarray, n: int) -> np.ndarray:
    """An orthonormal basis (columns) of {x : A x = 0}."""
    if A.shape[0] == 0:
        return np.eye(n)
    _, s, vt = np.linalg.svd(A)
    rank = int(np.sum(s > 1e-12 * max(s.max(initial=0.0), 1.0)))
    return vt[rank:].T


def stuck_matrices(M: np.ndarray, K: np.ndarray, W: np.ndarray, kt: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(N, M_r, K_r): the structure with every contact stuck, in coordinates x = N q (N a basis of the rigid
    contacts' w_j.x = 0; kt[j] = 0 marks a rigid contact), Jenkins contacts as their springs."""
    n = M.shape[0]
    rigid = kt == 0.0
    basis = null_space(W[rigid], n)
    K = K + (W.T * kt) @ W
    return basis, basis.T @ M @ basis, basis.T @ K @ basis


def natural_frequencies(M: np.ndarray, K: np.ndarray, W: np.ndarray, kt: np.ndarray, contacts: str) -> np.ndarray:
    """The natural angular frequencies, ascending: contacts "free" (no friction) or "stuck" (rigid contacts as
    constraints, Jenkins contacts as their springs)."""
    if contacts == "stuck":
        _, M, K = stuck_matrices(M, K, W, kt)
    elif contacts != "free":
        raise ValueError(f"contacts: {contacts!r} is not 'stuck' or 'free'")
    if M.shape[0] == 0:
        return np.zeros(0)
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    lam = np.linalg.eigvalsh(Li @ K @ Li.T)
    return np.sqrt(np.clip(lam, 0.0, None))
