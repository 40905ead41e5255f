"""The one place that holds numba options for every kernel.

`NUMBA_DISABLE_JIT=1` runs the same code as plain Python (debugging, coverage).
"""

from __future__ import annotations

import numba

#: cache=True: compile once per machine, not per process; nogil: tiles may run in threads
jit = numba.njit(cache=True, nogil=True, error_model="numpy")
