"""Reduced models from finite elements (issue 31): a structure's M, K and C read from a file, or built from
its modes, in plain numpy and scipy.

    M x'' + C x' + K x = F cos wt - sum_j w_j lambda_j          (DESIGN §7; x: the named DoFs)

A file is a NumPy `.npz` or a MATLAB `.mat` (scipy.io.loadmat, formats 4 to 7.2) holding arrays `M` and `K`
and optionally `C` (dense or sparse), as a Craig-Bampton or modal reduction exports them; its DoFs are named
by the spec, in the matrices' order. Without `C`, modal damping ratios zeta_r give

    C = M Phi diag(2 zeta_r omega_r) Phi^T M,    K Phi = M Phi Omega^2,  Phi^T M Phi = I.

A structure known by its modes (omega_r, zeta_r, mass-normalised shapes Phi at as many named DoFs as modes)
has, with Psi = Phi^-1,

    M = Psi^T Psi,   K = Psi^T Omega^2 Psi,   C = Psi^T diag(2 zeta_r omega_r) Psi.

Every reason a matrix cannot be a structure's is a ModelError whose message names the file (or "modes") and
the reason; which key of the spec it belongs to is the spec's to say.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

#: the largest model file read (bytes): a reduced model of thousands of DoFs is a few tens of MB
MAX_FILE_BYTES = 64 * 2**20
#: the file types read, by suffix
SUFFIXES = (".npz", ".mat")
#: a matrix is symmetric where |A - A^T| <= SYMMETRY_RTOL max|A| elementwise (an export's rounding is ~1e-16)
SYMMETRY_RTOL = 1e-10
#: a symmetric matrix is semi-definite where its least eigenvalue is >= -DEFINITE_RTOL max|eigenvalue|,
#: and M is positive definite where its Cholesky factor exists
DEFINITE_RTOL = 1e-12
#: mode shapes are refused where Phi's condition number exceeds this (M, K and C would be noise)
MAX_CONDITION = 1e12


class ModelError(ValueError):
    """A model file or a modal description that gives no structure; the message is the reason."""


def load_matrices(path: str | os.PathLike[str], n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(M, K, C or None) from the .npz or .mat file at `path`, for n named DoFs, each checked (check_matrices)."""
    path = Path(path)
    where = str(path)
    if path.suffix.lower() not in SUFFIXES:
        raise ModelError(f"{where}: a reduced model is a .npz or a .mat file (got {path.suffix or 'no suffix'!r})")
    try:
        size = path.stat().st_size
    except OSError as err:
        raise ModelError(f"{where}: cannot read it: {err.strerror or err}") from None
    if not path.is_file():
        raise ModelError(f"{where}: not a file")
    if size > MAX_FILE_BYTES:
        raise ModelError(f"{where}: {size} bytes, over the {MAX_FILE_BYTES // 2**20} MiB a reduced model may have")
    try:
        arrays = _read_npz(path) if path.suffix.lower() == ".npz" else _read_mat(path)
    except ModelError:
        raise
    except Exception as err:  # a damaged or foreign file: every reader's own error, said in one line
        raise ModelError(f"{where}: cannot read it as {path.suffix.lower()}: {type(err).__name__}: {err}") from None
    missing = [k for k in ("M", "K") if k not in arrays]
    if missing:
        raise ModelError(f"{where}: no {' and no '.join(missing)} in it (it holds: "
                         f"{', '.join(sorted(arrays)) or 'nothing'}); a reduced model holds M, K and optionally C")
    return check_matrices(where, n, arrays["M"], arrays["K"], arrays.get("C"))


def _read_npz(path: Path) -> dict[str, object]:
    with np.load(path, allow_pickle=False) as z:  # no pickles: a file must not run code
        return {k: (z[k] if k in ("M", "K", "C") else None) for k in z.files}


def _read_mat(path: Path) -> dict[str, object]:
    from scipy.io import loadmat

    return {k: v for k, v in loadmat(path).items() if not k.startswith("__")}


def _dense(where: str, name: str, a: object) -> np.ndarray:
    import scipy.sparse

    if scipy.sparse.issparse(a):
        a = a.toarray()  # type: ignore[attr-defined]
    arr = np.asarray(a)
    if arr.dtype.kind not in "iuf":
        raise ModelError(f"{where}: {name} is not a real matrix (dtype {arr.dtype})")
    return np.ascontiguousarray(arr, dtype=np.float64)


def check_matrices(where: str, n: int, M: object, K: object, C: object | None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """M, K and C (or None) as float64 n x n matrices, refused (ModelError naming `where`) where not square,
    not n x n, not finite, not symmetric (SYMMETRY_RTOL), M not positive definite, K or C not positive
    semi-definite (DEFINITE_RTOL). Returned as given, bit for bit: a symmetric export stays as it is."""
    out: list[np.ndarray | None] = []
    for name, a in (("M", M), ("K", K), ("C", C)):
        if a is None:
            out.append(None)
            continue
        arr = _dense(where, name, a)
        if arr.ndim != 2 or arr.shape[0] != arr.shape[1]:
            raise ModelError(f"{where}: {name} is not square (shape {'x'.join(map(str, arr.shape))})")
        if arr.shape[0] != n:
            raise ModelError(f"{where}: {name} is {arr.shape[0]}x{arr.shape[0]}, but dofs names {n} DoFs: name one "
                             "DoF per row, in the matrices' order")
        if not np.isfinite(arr).all():
            bad = np.argwhere(~np.isfinite(arr))[0]
            value = float(arr[tuple(bad)])
            raise ModelError(f"{where}: {name}[{bad[0]}, {bad[1]}] is {value!r}: every entry must be finite")
        scale = float(np.abs(arr).max(initial=0.0))
        asym = float(np.abs(arr - arr.T).max(initial=0.0))
        if asym > SYMMETRY_RTOL * scale:
            raise ModelError(f"{where}: {name} is not symmetric: max|{name} - {name}^T| = {asym:.3g}, over "
                             f"{SYMMETRY_RTOL:g} x max|{name}| = {SYMMETRY_RTOL * scale:.3g}")
        if name == "M":
            try:
                np.linalg.cholesky(0.5 * (arr + arr.T))
            except np.linalg.LinAlgError:
                raise ModelError(f"{where}: M is not positive definite (a mass matrix must be: every motion has "
                                 "inertia)") from None
        else:
            least = float(np.linalg.eigvalsh(0.5 * (arr + arr.T))[0]) if n else 0.0
            if least < -DEFINITE_RTOL * max(scale, 1e-300) * n:
                what = "stiffness stores" if name == "K" else "damping dissipates"
                raise ModelError(f"{where}: {name} is not positive semi-definite (least eigenvalue {least:.3g}): "
                                 f"a {what} no energy it does not take")
        out.append(arr)
    assert out[0] is not None and out[1] is not None
    return out[0], out[1], out[2]


def modal_damping(M: np.ndarray, K: np.ndarray, ratios: np.ndarray) -> np.ndarray:
    """C = M Phi diag(2 zeta_r omega_r) Phi^T M for the modes of (K, M) in ascending order (module docstring),
    exactly symmetric."""
    from scipy.linalg import eigh

    lam, phi = eigh(K, M)
    omega = np.sqrt(np.clip(lam, 0.0, None))
    mp = M @ phi
    C = (mp * (2.0 * ratios * omega)) @ mp.T
    return 0.5 * (C + C.T)


def from_modes(frequencies: np.ndarray, ratios: np.ndarray, shapes: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M, K, C) of the modes: angular natural frequencies omega_r, damping ratios zeta_r, and mass-normalised
    shapes Phi (DoF by mode, square), as the module docstring gives them; ModelError where Phi is singular."""
    n = shapes.shape[0]
    cond = float(np.linalg.cond(shapes)) if n else 1.0
    if not np.isfinite(cond) or cond > MAX_CONDITION:
        raise ModelError(f"modes: the shapes are singular (condition number {cond:.3g}, over {MAX_CONDITION:g}): "
                         "each mode must move the named DoFs differently")
    psi = np.linalg.inv(shapes)

    def congruent(d: np.ndarray) -> np.ndarray:
        a = (psi.T * d) @ psi
        return 0.5 * (a + a.T)

    return congruent(np.ones(n)), congruent(frequencies**2), congruent(2.0 * ratios * frequencies)
