"""Multi-degree-of-freedom structures with friction contacts (issue 30, DESIGN §7): the model and its
matrices (model.py, plain numpy), the batch entry to the exact engine (solve.py; kernels in
friction_sweep.kernels.structure), where points start (starts.py: the second start, stepped-sine sweeps),
the steady orbits' time histories (history.py) and exact harmonics (harmonics.py)."""

from friction_sweep.structures.history import time_histories
from friction_sweep.structures.model import (
    Assembled,
    ContactDef,
    StructureDef,
    assemble,
    natural_frequencies,
)
from friction_sweep.structures.solve import solve_points

__all__ = ["Assembled", "ContactDef", "StructureDef", "assemble", "natural_frequencies", "solve_points",
           "time_histories"]
