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
from friction_sweep.structures.model import Assembled, ContactDef, StructureDef, assemble, natural_frequencies


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
        return StructureDef(
            excitation=excitation, masses={str(k): float(v) for k, v in dict(st["masses"]).items()},
            springs=_triples(st.get("springs") or [], "springs"), dampers=_triples(st.get("dampers") or [], "dampers"),
            contacts=contacts, forcing={str(k): float(v) for k, v in dict(st.get("forcing") or {}).items()},
            base_amplitude=float(st.get("base_amplitude", 1.0)))
    except (KeyError, IndexError, TypeError, ValueError, AttributeError) as err:
        raise UnreadableStructure(f"attribute {STRUCTURE_ATTRIBUTE}: {type(err).__name__}: {err}") from None


def assembled(ds) -> Assembled:
    """The assembled structure of cube `ds` (UnreadableStructure with the reason), checked against the
    cube's dof and contact coordinates (the same names in the same order)."""
    d = definition(ds.attrs, str(ds.attrs.get("excitation", "")))
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
