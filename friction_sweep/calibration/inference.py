"""ArviZ, imported once the calibration's way: without the FutureWarning ArviZ 0.2x prints on import (once
a day) to announce its 1.0 refactor. A calibration pins arviz < 1 (pyproject's `calibrate` extra), so the
warning says nothing its user can act on, and `fsweep calibrate --quiet` must print nothing but results.
"""

from __future__ import annotations

import warnings
from typing import Any


def import_arviz() -> Any:
    """The arviz module, its import's FutureWarning silenced (every other warning as it comes)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=FutureWarning, module=r"arviz(\.|$)")
        import arviz

    return arviz
