"""The settings record every kernel reads: one float array whose slots are named by the settings themselves.

A float array (not a NamedTuple) so that a new knob never changes a kernel's signature or its cached
compilation, and so that a driver can give each point a start of its own by writing two slots of a copy.
The slot of a setting is its position in SETTING_FIELDS, the names the specs, the methods and the
defaults use; the SET_* constants below are read off that one tuple, so they cannot drift from it.
"""

from __future__ import annotations

import numpy as np

#: the settings, in slot order
SETTING_FIELDS = (
    "steady_tol",  # |P^k(x) - x| <= steady_tol * |x| on the stroboscopic map
    "stop_tol",  # a stop is declared when |v| <= stop_tol * max(A, |(q, v)|) (event kernel)
    "max_periods",  # forcing periods marched at most
    "max_orbit_period",  # period-k orbits are detected up to this k
    "work_budget",  # stop-search steps, RK4 steps and events per point
    "shoot_after",  # periods marched before the first shooting attempt (0: from the guess, before marching)
    "shoot_every",  # periods between shooting attempts after a miss
    "kernel",  # which period integrator the driver marches: KERNEL_EVENT or KERNEL_RK4
    "steps_per_period",  # RK4 steps per forcing period (rk4 kernel only)
    "initial_displacement",  # the march starts here at forcing phase 0 ...
    "initial_velocity",  # ... with this velocity
    "stability",  # 1: measure the orbit's largest Floquet multiplier (output group `stability`), 0: not
)
SET = {name: i for i, name in enumerate(SETTING_FIELDS)}
SET_STEADY_TOL = SET["steady_tol"]
SET_STOP_TOL = SET["stop_tol"]
SET_MAX_PERIODS = SET["max_periods"]
SET_MAX_ORBIT_PERIOD = SET["max_orbit_period"]
SET_WORK_BUDGET = SET["work_budget"]
SET_SHOOT_AFTER = SET["shoot_after"]
SET_SHOOT_EVERY = SET["shoot_every"]
SET_KERNEL = SET["kernel"]
SET_STEPS_PER_PERIOD = SET["steps_per_period"]
SET_INITIAL_DISPLACEMENT = SET["initial_displacement"]
SET_INITIAL_VELOCITY = SET["initial_velocity"]
SET_STABILITY = SET["stability"]

#: values of the `kernel` setting
KERNEL_EVENT, KERNEL_RK4 = 0, 1


def settings_record(values: dict) -> np.ndarray:
    """The kernels' settings array from a complete dict of named settings (every name of SETTING_FIELDS)."""
    missing = set(SETTING_FIELDS) - set(values)
    unknown = set(values) - set(SETTING_FIELDS)
    if missing or unknown:
        raise KeyError(f"kernel settings: missing {sorted(missing)}, unknown {sorted(unknown)}")
    return np.array([float(values[name]) for name in SETTING_FIELDS])
