"""The structure a structure cube solved, read back from its `structure` attribute (written by
batch.structure_sweep.structure_attribute), for the commands that read a cube: `fsweep info` (its natural
frequencies), `fsweep check` (its linear limits) and `fsweep plot`.

One reader: the attribute through storage.attributes.read_json (bounded), its items into the engine's
StructureDef, assembled by structures.model.assemble, so that every command sees the matrices the run
solved and a cube that holds no solvable structure is refused in one sentence.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from friction_sweep.storage.schema import STRUCTURE_ATTRIBUTE
from friction_sweep.structures.model import (
    Assembled,
    ContactDef,
    StructureDef,
    assemble,
    natural_frequencies,
    scaled,
)


class UnreadableStructure(ValueError):
    """The cube's `structure` attribute does not hold a structure fsweep can solve (the reason)."""


def _triples(items: Any, key: str) -> tuple[tuple[str, str, float], ...]:
    if not isinstance(items, list) or not all(isinstance(e, list) and len(e) == 3 for e in items):
        raise UnreadableStructure(f"{key} is not a list of [a, b, value]")
    return tuple((str(a), str(b), float(v)) for a, b, v in items)


def definition(attrs: Mapping, excitation: str) -> StructureDef:
    """The StructureDef of a cube's attributes (UnreadableStructure with the reason)."""
    from friction_sweep.storage import attributes

    try:
        st = attributes.read_json(attrs, STRUCTURE_ATTRIBUTE)
    except attributes.BadAttribute as err:
        raise UnreadableStructure(str(err)) from None
    if not isinstance(st, dict):
        raise UnreadableStructure(f"the cube has no {STRUCTURE_ATTRIBUTE} attribute")
    try:
        contacts = tuple(
            ContactDef(name=str(c["name"]), between=(str(c["between"][0]), str(c["between"][1])),
                       friction=float(c["friction"]),
                       stiffness=None if c.get("stiffness") is None else float(c["stiffness"]),
                       static_friction_ratio=float(c.get("static_friction_ratio", 1.0)))
            for c in st.get("contacts") or [])
        masses: dict[str, float] = {}
        dofs: tuple[str, ...] = ()
        matrices = None
        if "masses" in st:
            masses = {str(k): float(v) for k, v in dict(st["masses"]).items()}
        else:  # a reduced model (matrices or modes): the matrices the run solved, recorded beside their source
            dofs = tuple(str(name) for name in st["dofs"])
            solved = dict(st["solved_matrices"])
            M, K, C = (np.array(solved[name], dtype=float).reshape(len(dofs), len(dofs)) for name in "MKC")
            matrices = (M, K, C)
        return StructureDef(
            excitation=excitation, masses=masses,
            springs=_triples(st.get("springs") or [], "springs"), dampers=_triples(st.get("dampers") or [], "dampers"),
            contacts=contacts, forcing={str(k): float(v) for k, v in dict(st.get("forcing") or {}).items()},
            base_amplitude=float(st.get("base_amplitude", 1.0)), dofs=dofs, matrices=matrices)
    except (KeyError, IndexError, TypeError, ValueError, AttributeError) as err:
        raise UnreadableStructure(f"attribute {STRUCTURE_ATTRIBUTE}: {type(err).__name__}: {err}") from None


def assembled(ds) -> Assembled:
    """The assembled structure of cube `ds` (UnreadableStructure with the reason), checked against the
    cube's dof and contact coordinates (the same names in the same order)."""
    d = definition(ds.attrs, str(ds.attrs.get("excitation", "")))
    if "mass_scale" in ds.coords:
        # a physical structure: the attribute holds it as written (SI), the cube the dimensionless structure
        # the engine solved (batch.structure_sweep.structure_def; spec.structure_units: c_0 = m_0 omega_0)
        try:
            mass, omega = (float(ds[name]) for name in ("mass_scale", "reference_frequency"))
            d = scaled(d, mass, float(ds["stiffness_scale"]), mass * omega, float(ds["force_scale"]),
                       float(ds["length_scale"]))
        except (KeyError, TypeError, ValueError) as err:
            raise UnreadableStructure(f"the physical scales: {type(err).__name__}: {err}") from None
    try:
        a = assemble(d)
    except ValueError as err:
        raise UnreadableStructure(f"attribute {STRUCTURE_ATTRIBUTE}: {err}") from None
    for dim, names in (("dof", a.dof_names), ("contact", a.contact_names)):
        if dim in ds.coords and tuple(map(str, ds[dim].values.tolist())) != names:
            raise UnreadableStructure(f"attribute {STRUCTURE_ATTRIBUTE} names the {dim}s {', '.join(names)}; "
                                      f"the cube's {dim} coordinate holds {', '.join(map(str, ds[dim].values))}")
    return a


def frequencies(a: Assembled) -> dict[str, np.ndarray]:
    """The linear structure's natural angular frequencies, ascending, with every contact stuck and with
    every contact free (structures.model.natural_frequencies)."""
    return {contacts: natural_frequencies(a, contacts) for contacts in ("stuck", "free")}
