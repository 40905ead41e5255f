"""How a grid is cut into tiles: fixed blocks, so results never depend on how tiles are scheduled.

Numba-free, so that the cost estimate and the checkpoint's fingerprint need no kernel.
"""

from __future__ import annotations

#: frequency ratios per tile; fixed so results never depend on how tiles are scheduled
TILE_FREQUENCIES = 32
#: force ratios per tile of a swept run (each force ratio is one sequential sweep)
TILE_FORCES = 4


def tiles(n_frequencies: int, size: int = TILE_FREQUENCIES) -> list[slice]:
    return [slice(i, min(i + size, n_frequencies)) for i in range(0, n_frequencies, size)]


def layout(n_frequencies: int, n_forces: int, sweep: str | None = None) -> list[slice]:
    """The run's tiles: slices of the frequency ratios, or of the force ratios for a swept run."""
    return tiles(n_forces, TILE_FORCES) if sweep else tiles(n_frequencies)
