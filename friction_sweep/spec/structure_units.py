"""Physical units for a structure spec (issue 31 item 2): quantities read with pint (spec.quantities, as the
1-DoF `system:` does), and the map from the physical structure to the dimensionless one the engine solves.

A structure is physical where any of its quantities is written with a unit ("2 kg", "40 kN/m") or it says
`units: physical`; then every quantity must carry its unit: masses in kg, stiffnesses in N/m, dashpots in
N s/m, frictions as a force or `{coefficient: mu, normal_load: N}`, forcing in N, base_amplitude in m, modal
frequencies in Hz or rad/s (the README's rad/s rule: units holding an angle are angular), and a reduced
model's matrices are read as SI (kg, N/m, N s/m). The grid then gives `frequency` with its unit, or
`frequency_ratio` against the first natural frequency omega_0 of the structure with every contact stuck or
every contact free (`grid.reference`, default stuck).

The map (DESIGN §7's equation divided through by k_0 L):

    m_0 = M[0, 0] (the first DoF's mass),  omega_0 = the reference natural frequency,  k_0 = m_0 omega_0^2,
    c_0 = m_0 omega_0,  F_0 = max|F| (force) or k_0 Y (base),  L = F_0 / k_0 (force) or Y (base):
    M / m_0, K / k_0, C / c_0, k_t / k_0, friction / F_0, F / F_0, Y / L = 1, omega / omega_0

so the dimensionless structure's time unit is 1 / omega_0, its lengths L and its forces F_0: an amplitude
times L is metres, a friction energy times F_0 L joules. The engine solves the dimensionless structure, so a
physical spec gives, bit for bit, the cube of the plain spec holding these ratios.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from .base import problem, show
from .quantities import FORCE, FREQUENCY, LENGTH, MASS, RATIO, STIFFNESS, Kind, QuantityError, to_si

DAMPING = Kind("a damping coefficient", "N*s/m", "12 N*s/m")
#: the reference natural frequencies a frequency ratio may be taken against
REFERENCES = ("stuck", "free")
DEFAULT_REFERENCE = "stuck"
#: a natural frequency below this fraction of the largest is a rigid-body motion's (no reference)
RIGID_RTOL = 1e-9


#: text that reads as a quantity: a number first ("2 kg", "-1.5e3 N", ".5 m"); other text ("heavy") is no
#: quantity, and a plain structure's refusal says what it is
_QUANTITY = re.compile(r"\s*[-+]?(\d|\.\d)")


def _quantity(value: Any) -> bool:
    return isinstance(value, dict) or (isinstance(value, str) and _QUANTITY.match(value) is not None)


def is_physical(structure: Any) -> bool:
    """Whether a raw `structure:` mapping is physical (the module docstring's rule)."""
    if not isinstance(structure, dict):
        return False
    if structure.get("units") == "physical":
        return True
    values: list[Any] = []
    if isinstance(structure.get("masses"), dict):
        values += list(structure["masses"].values())
    for key in ("springs", "dampers"):
        if isinstance(structure.get(key), list):
            values += [e[2] for e in structure[key] if isinstance(e, list) and len(e) == 3]
    if isinstance(structure.get("contacts"), list):
        for c in structure["contacts"]:
            if isinstance(c, dict):
                values += [c.get("friction"), c.get("stiffness")]
    if isinstance(structure.get("forcing"), dict):
        values += list(structure["forcing"].values())
    values.append(structure.get("base_amplitude"))
    modes = structure.get("modes")
    if isinstance(modes, dict) and isinstance(modes.get("frequencies"), list):
        values += modes["frequencies"]
    return any(_quantity(v) for v in values)


def to_si_structure(structure: dict) -> tuple[dict, list]:
    """The physical `structure:` mapping with each quantity in SI (a plain number), and the problems (each
    located below `structure`); a friction `{coefficient, normal_load}` becomes their product."""
    problems: list = []
    out = dict(structure)
    out["units"] = "physical"

    def read(value: Any, kind: Kind, at: tuple, *, zero: bool = False) -> Any:
        try:
            x = to_si(value, kind)
        except QuantityError as err:
            problems.append(problem("quantity", str(err), at))
            return value
        if x < 0 or (x == 0 and not zero):
            sign = "zero or positive" if zero else "positive"
            problems.append(problem("quantity_sign", f"must be {sign} (got {show(value)})", at))
        return x

    if isinstance(structure.get("masses"), dict):
        out["masses"] = {k: read(v, MASS, ("masses", k)) for k, v in structure["masses"].items()}
    for key, kind in (("springs", STIFFNESS), ("dampers", DAMPING)):
        if isinstance(structure.get(key), list):
            out[key] = [[*e[:2], read(e[2], kind, (key, i, 2), zero=True)] if isinstance(e, list) and len(e) == 3 else e
                        for i, e in enumerate(structure[key])]
    if isinstance(structure.get("contacts"), list):
        contacts = []
        for j, c in enumerate(structure["contacts"]):
            if isinstance(c, dict):
                c = dict(c)
                if "friction" in c:
                    c["friction"] = _friction(c["friction"], read, ("contacts", j, "friction"), problems)
                if c.get("stiffness") is not None:
                    c["stiffness"] = read(c["stiffness"], STIFFNESS, ("contacts", j, "stiffness"))
            contacts.append(c)
        out["contacts"] = contacts
    if isinstance(structure.get("forcing"), dict):
        out["forcing"] = {k: _signed_force(v, ("forcing", k), problems) for k, v in structure["forcing"].items()}
    if structure.get("base_amplitude") is not None:
        out["base_amplitude"] = read(structure["base_amplitude"], LENGTH, ("base_amplitude",))
    modes = structure.get("modes")
    if isinstance(modes, dict) and isinstance(modes.get("frequencies"), list):
        # angular, as the engine's: Hz x 2 pi, an angular unit's value as it is (quantities' rad/s rule)
        hz = [read(v, FREQUENCY, ("modes", "frequencies", i), zero=True) for i, v in enumerate(modes["frequencies"])]
        out["modes"] = {**modes, "frequencies": [2.0 * math.pi * x if isinstance(x, float) else x for x in hz]}
    return out, problems


def _friction(value: Any, read, at: tuple, problems: list) -> Any:
    """A friction force: "12 N", or {coefficient: mu, normal_load: "40 N"} giving mu N."""
    if not isinstance(value, dict):
        return read(value, FORCE, at, zero=True)
    unknown = sorted(set(value) - {"coefficient", "normal_load"})
    missing = [k for k in ("coefficient", "normal_load") if k not in value]
    if unknown or missing:
        problems.append(problem("friction_form", "a friction is a force (\"12 N\") or {coefficient: mu, normal_load: "
                                f"N}} (got {show(value)})", at))
        return value
    mu = read(value["coefficient"], RATIO, (*at, "coefficient"), zero=True)
    load = read(value["normal_load"], FORCE, (*at, "normal_load"))
    return mu * load if isinstance(mu, float) and isinstance(load, float) else value


def _signed_force(value: Any, at: tuple, problems: list) -> Any:
    """A forcing amplitude in N (its sign is a phase: any finite value)."""
    try:
        return to_si(value, FORCE)
    except QuantityError as err:
        problems.append(problem("quantity", str(err), at))
        return value


def frequency_axis_is_physical(value: Any) -> bool:
    """Whether a raw grid frequency axis is written with units (a quantity, a list of them, or a range)."""
    if isinstance(value, list):
        return any(isinstance(v, str) and _quantity(v) for v in value)
    if isinstance(value, dict):
        return any(isinstance(value.get(k), str) and _quantity(value.get(k)) for k in ("start", "stop", "step"))
    return isinstance(value, str) and _quantity(value)


@dataclass(frozen=True)
class StructureMap:
    """A physical structure's scales (SI), which divide it into the dimensionless structure the engine solves
    (module docstring; structures.model.scaled)."""

    reference: str  # "stuck" | "free": which natural frequency omega_0 is
    mass: float  # m_0, kg
    omega: float  # omega_0, rad/s
    stiffness: float  # k_0, N/m
    damping: float  # c_0, N s/m
    force: float  # F_0, N
    length: float  # L, m


    def describe(self) -> list[str]:
        """What the cube's dimensionless numbers mean physically (fsweep validate)."""
        return [f"omega_0 = {self.omega:.6g} rad/s (f_0 = {self.omega / (2 * math.pi):.6g} Hz), the first natural "
                f"frequency with every contact {self.reference}: the cube's frequency is omega / omega_0",
                f"amplitudes in L = {self.length:.6g} m, forces in F_0 = {self.force:.6g} N, masses in m_0 = "
                f"{self.mass:.6g} kg, stiffnesses in k_0 = {self.stiffness:.6g} N/m"]


def first_frequency(values: np.ndarray) -> float:
    """The least natural frequency that is no rigid-body motion's (NaN where every one is)."""
    values = np.asarray(values, dtype=float)
    top = float(values.max(initial=0.0))
    moving = values[values > RIGID_RTOL * top]
    return float(moving[0]) if moving.size and moving[0] == values[0] else math.nan


def structure_map(structure, excitation: str, reference: str) -> StructureMap:
    """The map of the SI structure (spec.structure.Structure) against its first natural frequency with every
    contact `reference` ("stuck" | "free"); ValueError with the reason where that structure has a rigid-body
    motion (no such frequency)."""
    from .natural_frequencies import natural_frequencies

    M, K, W, kt = structure.linear()
    omega = first_frequency(natural_frequencies(M, K, W, kt, reference))
    if not math.isfinite(omega):
        raise ValueError(f"with every contact {reference}, the structure has a rigid-body motion (a natural frequency "
                         "of 0): take the frequency ratio against the stuck structure (reference: stuck)")
    m0 = float(M[0, 0])
    k0 = m0 * omega * omega
    if excitation == "force":
        force = float(max(abs(v) for v in (structure.forcing or {}).values()))
        length = force / k0
    else:
        length = float(structure.base_motion)
        force = k0 * length
    return StructureMap(reference, m0, omega, k0, m0 * omega, force, length)
