"""The one place that holds numba options for every kernel.

`NUMBA_DISABLE_JIT=1` runs the same code as plain Python (debugging, coverage).

A kernel calling another compiles the callee for the types of the call's arguments; numba types a
constant argument (True, 0, a module constant) as a literal, so every distinct constant makes a
callee, and everything it calls, compile again: on main 09f00cb the first run compiled stick_phase
12 times, advance 4, shoot 5, half the compile time of the demo's kernels. Kernels here compile
once per argument type: a call from compiled code asks for the arguments' plain (non-literal) types.
"""

from __future__ import annotations

import numba
from numba.core import types
from numba.core.registry import CPUDispatcher


class _OncePerType(CPUDispatcher):
    """numba's CPU dispatcher, except that a call from compiled code compiles the callee for the plain
    types of its arguments: no specialisation per constant value."""

    def get_call_template(self, args, kws):
        return super().get_call_template(tuple(types.unliteral(a) for a in args),
                                         {k: types.unliteral(v) for k, v in kws.items()})


def _once_per_type(options: dict):
    """numba.njit with `options`, its dispatcher a _OncePerType (the plain function where the JIT is
    off)."""
    def decorate(func):
        disp = numba.njit(**options)(func)
        if isinstance(disp, CPUDispatcher):
            disp.__class__ = _OncePerType  # the same object, one method more (no state of its own)
        return disp
    return decorate


#: cache=True: compile once per machine, not per process; nogil: tiles may run in threads
_OPTIONS = {"cache": True, "nogil": True, "error_model": "numpy"}
jit = _once_per_type(_OPTIONS)

#: the same, inlined into each caller at numba's IR level instead of compiled on its own: for the steps a
#: driver or an integrator is split into, so that the split costs neither compile time (numba optimises
#: and compiles a callee's code again inside every caller) nor a call
jit_inline = _once_per_type({**_OPTIONS, "inline": "always"})
