"""A structure of masses, springs, dashpots and friction contacts, and its matrices (DESIGN §7), in plain numpy.

    M x'' + C x' + K x = F cos wt (force)  or  K_b y + C_b y' (springs and dashpots to the base)
                         - sum_j w_j lambda_j,        y = Y cos wt

Contact j acts on u_j = w_j.x - e_j y: w_j is +1 at its first end and -1 at its second where both are
masses, one entry where the other end is ground or the base; e_j = 1 where that end is the base.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from friction_sweep.spec import natural_frequencies as linear_modes

#: the two nodes that are not masses
GROUND, BASE = "ground", "base"
EXCITATIONS = ("force", "base")


@dataclass(frozen=True)
class ContactDef:
    name: str
    between: tuple[str, str]  # each a mass name, "ground" or "base"
    friction: float  # kinetic friction force (before friction_scale)
    stiffness: float | None = None  # None: rigid Coulomb; else Jenkins contact stiffness k_t
    static_friction_ratio: float = 1.0


@dataclass(frozen=True)
class StructureDef:
    excitation: str  # "force" | "base"
    masses: dict[str, float]  # ordered: the dof order of the cube
    springs: tuple[tuple[str, str, float], ...] = ()
    dampers: tuple[tuple[str, str, float], ...] = ()
    contacts: tuple[ContactDef, ...] = ()
    forcing: dict[str, float] = field(default_factory=dict)  # force excitation: amplitude per mass
    base_amplitude: float = 1.0  # base excitation
    #: a reduced model (spec.reduced): its DoF names and (M, K, C), in place of masses, springs, dampers
    dofs: tuple[str, ...] = ()
    matrices: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


@dataclass(frozen=True)
class Assembled:
    """The matrices of a structure. F_cos, F_sin_per_w: the forcing is F_cos cos wt + w F_sin_per_w sin wt
    (force: F and 0; base: Y K_b and -Y C_b); ey: Y where a contact's other end is the base."""

    excitation: str
    dof_names: tuple[str, ...]
    contact_names: tuple[str, ...]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    W: np.ndarray  # (m, n) contact directions
    e: np.ndarray  # (m,) 1 where the contact's other end is the base
    K_base: np.ndarray  # (n,) stiffness to the base
    C_base: np.ndarray  # (n,) damping to the base
    F_cos: np.ndarray
    F_sin_per_w: np.ndarray
    mu: np.ndarray  # kinetic friction
    mu_s: np.ndarray  # static friction
    kt: np.ndarray  # Jenkins stiffness, 0 for a rigid contact
    base_amplitude: float

    @property
    def amplitude_unit(self) -> float:
        """What amplitudes are divided by: Y for base excitation (a transmissibility), 1 for force."""
        return self.base_amplitude if self.excitation == BASE else 1.0


def scaled(d: StructureDef, mass: float, stiffness: float, damping: float, force: float,
           length: float) -> StructureDef:
    """The dimensionless structure of the SI structure d (spec.structure_units): masses over m_0,
    stiffnesses over k_0, dashpots over c_0, frictions and forcing over F_0, the base's amplitude over L."""
    contacts = tuple(replace(c, friction=c.friction / force,
                             stiffness=None if c.stiffness is None else c.stiffness / stiffness) for c in d.contacts)
    return replace(
        d, masses={k: v / mass for k, v in d.masses.items()},
        springs=tuple((p, q, v / stiffness) for p, q, v in d.springs),
        dampers=tuple((p, q, v / damping) for p, q, v in d.dampers), contacts=contacts,
        forcing={k: v / force for k, v in d.forcing.items()},
        base_amplitude=d.base_amplitude / length if d.excitation == BASE else d.base_amplitude,
        matrices=None if d.matrices is None else (d.matrices[0] / mass, d.matrices[1] / stiffness,
                                                  d.matrices[2] / damping))


def _ends(a: str, b: str, index: dict[str, int], what: str) -> None:
    for node in (a, b):
        if node not in index and node not in (GROUND, BASE):
            raise ValueError(f"{what}: unknown mass {node!r}")
    if a == b:
        raise ValueError(f"{what}: both ends are {a!r}")
    if a not in index and b not in index:
        raise ValueError(f"{what}: between {a!r} and {b!r}, no mass")


def _couple(mat: np.ndarray, to_base: np.ndarray, a: str, b: str, value: float, index: dict[str, int]) -> None:
    ia, ib = index.get(a), index.get(b)
    for i, j in ((ia, ib), (ib, ia)):
        if i is None:
            continue
        mat[i, i] += value
        if j is not None:
            mat[i, j] -= value
        elif (b if i == ia else a) == BASE:
            to_base[i] += value


def assemble(d: StructureDef) -> Assembled:
    """M, C, K, the contact directions and the forcing of structure d; ValueError with a reason where it
    cannot be solved."""
    if d.excitation not in EXCITATIONS:
        raise ValueError(f"excitation: {d.excitation!r} is not one of {', '.join(EXCITATIONS)}")
    if d.matrices is not None and (d.masses or d.springs or d.dampers):
        raise ValueError("matrices: given with masses, springs or dampers (a reduced model's are in its matrices)")
    names = tuple(d.masses) if d.matrices is None else tuple(d.dofs)
    if not names:
        raise ValueError("masses: none")
    index = {name: i for i, name in enumerate(names)}
    for name in names:
        if name in (GROUND, BASE):
            raise ValueError(f"masses: {name!r} is a reserved node name")
        if d.matrices is None and not (np.isfinite(d.masses[name]) and d.masses[name] > 0):
            raise ValueError(f"masses: {name}: {d.masses[name]!r} is not a positive mass")
    n = len(names)
    if d.matrices is None:
        M = np.diag([float(d.masses[name]) for name in names])
        K, C = np.zeros((n, n)), np.zeros((n, n))
    else:  # checked where read (spec.reduced.check_matrices); copied so the definition stays as given
        M, K, C = (np.array(a, dtype=np.float64, order="C") for a in d.matrices)
        if not all(a.shape == (n, n) for a in (M, K, C)):
            raise ValueError(f"matrices: M, K and C must be {n}x{n} for {n} dofs")
    Kb, Cb = np.zeros(n), np.zeros(n)
    for kind, items, mat, to_base in (("springs", d.springs, K, Kb), ("dampers", d.dampers, C, Cb)):
        for a, b, value in items:
            _ends(a, b, index, f"{kind}: [{a}, {b}]")
            if not (np.isfinite(value) and value >= 0):
                raise ValueError(f"{kind}: [{a}, {b}]: {value!r} is negative or not finite")
            _couple(mat, to_base, a, b, float(value), index)
    m = len(d.contacts)
    W, e = np.zeros((m, n)), np.zeros(m)
    mu, mus, kt = np.zeros(m), np.zeros(m), np.zeros(m)
    seen = set()
    for j, c in enumerate(d.contacts):
        what = f"contacts: {c.name}"
        if c.name in seen:
            raise ValueError(f"{what}: a second contact of that name")
        seen.add(c.name)
        a, b = c.between
        _ends(a, b, index, what)
        if a in index:
            W[j, index[a]] = 1.0
        if b in index:
            W[j, index[b]] -= 1.0
        if a not in index:  # keep u = first mass's motion - the other end's
            W[j] = -W[j]
        e[j] = 1.0 if BASE in (a, b) else 0.0
        if not (np.isfinite(c.friction) and c.friction >= 0):
            raise ValueError(f"{what}: friction {c.friction!r} is negative or not finite")
        if not (np.isfinite(c.static_friction_ratio) and c.static_friction_ratio >= 1):
            raise ValueError(f"{what}: static_friction_ratio {c.static_friction_ratio!r} is below 1")
        if c.stiffness is not None and not (np.isfinite(c.stiffness) and c.stiffness > 0):
            raise ValueError(f"{what}: stiffness {c.stiffness!r} is not positive")
        mu[j] = c.friction
        mus[j] = c.friction * c.static_friction_ratio
        kt[j] = 0.0 if c.stiffness is None else float(c.stiffness)
    Y = float(d.base_amplitude)
    F = np.zeros(n)
    if d.excitation == "force":
        for name, value in d.forcing.items():
            if name not in index:
                raise ValueError(f"forcing: unknown mass {name!r}")
            if not np.isfinite(value):
                raise ValueError(f"forcing: {name}: {value!r} is not finite")
            F[index[name]] = float(value)
        F_cos, F_sin = F, np.zeros(n)
    else:
        if d.forcing:
            raise ValueError("forcing: given with base excitation (the base drives the structure)")
        if not (np.isfinite(Y) and Y > 0):
            raise ValueError(f"base_amplitude: {Y!r} is not positive")
        F_cos, F_sin = Y * Kb, -Y * Cb
    out = Assembled(d.excitation, names, tuple(c.name for c in d.contacts), M, C, K, W, e, Kb, Cb, F_cos, F_sin,
                    mu, mus, kt, Y)
    _restrained(out)
    return out


def _restrained(a: Assembled) -> None:
    """Refuse a rigid-body motion that no spring and no contact resists (x with K x = 0 and w_j.x = 0)."""
    n = a.M.shape[0]
    scale = max(np.abs(a.K).max(initial=0.0), 1.0)
    null = linear_modes.null_space(np.vstack([a.K / scale, a.W]), n)
    if null.shape[1]:
        free = ", ".join(name for name, v in zip(a.dof_names, np.abs(null).max(axis=1), strict=True) if v > 1e-9)
        raise ValueError(f"structure: unrestrained rigid-body motion of {free} (no spring or contact holds it)")


def stuck_matrices(a: Assembled) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(N, M_r, K_r): the linear structure with every contact stuck (spec.natural_frequencies.stuck_matrices)."""
    return linear_modes.stuck_matrices(a.M, a.K, a.W, a.kt)


def natural_frequencies(a: Assembled, contacts: str) -> np.ndarray:
    """The linear structure's natural angular frequencies, ascending: contacts "free" (no friction) or
    "stuck" (rigid contacts as constraints, Jenkins contacts as their springs; spec.natural_frequencies)."""
    return linear_modes.natural_frequencies(a.M, a.K, a.W, a.kt, contacts)


def rest_state(a: Assembled) -> np.ndarray:
    """Where a march starts (with zero velocities): every contact unstretched (w_j.x = e_j y(0), y(0) = Y
    for base excitation), and in the directions the contacts leave free the springs' equilibrium with
    the base at y(0) (min 1/2 x.K x - x.K_b y(0)); the least-norm such x where that is not unique. The 1-DoF
    scenes' starts: force and base x = 0, joined x = y(0) (relative rest)."""
    n, m = a.M.shape[0], a.W.shape[0]
    y0 = a.base_amplitude if a.excitation == BASE else 0.0
    kkt = np.block([[a.K, a.W.T], [a.W, np.zeros((m, m))]])
    rhs = np.concatenate([a.K_base * y0, a.e * y0])
    return np.ascontiguousarray(np.linalg.lstsq(kkt, rhs, rcond=None)[0][:n])
