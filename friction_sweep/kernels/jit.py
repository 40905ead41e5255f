"""The one place that holds numba options for every kernel.

`NUMBA_DISABLE_JIT=1` runs the same code as plain Python (debugging, coverage).
"""

from __future__ import annotations

import functools

import numba

#: cache=True: compile once per machine, not per process; nogil: tiles may run in threads
_njit = functools.partial(numba.njit, cache=True, nogil=True, error_model="numpy")
jit = _njit()

#: the same, inlined into each caller at numba's IR level instead of compiled on its own: for the steps a
#: driver or an integrator is split into, so that the split costs neither compile time (numba optimises
#: and compiles a callee's code again inside every caller) nor a call
jit_inline = _njit(inline="always")
