"""The one phase convention every output shares."""

from __future__ import annotations

import numpy as np

#: Phases are lags of the response behind the excitation, in degrees, wrapped into [-90, 270):
#: physical lags lie in [0, 180], so neither the linear 0 (r < 1) nor the linear 180 (r > 1)
#: sits on a wrap point, while small leads stay small negative numbers.
PHASE_RANGE_DEG = (-90.0, 270.0)


def wrap_degrees(degrees):
    """A lag in degrees wrapped into [-90, 270): the convention itself, plain arithmetic for floats and
    arrays alike, so that the kernels jit this same function (kernels/steady.py)."""
    return (degrees + 90.0) % 360.0 - 90.0


def wrap_lag_degrees(radians):
    """Convert a lag in radians (anything array-like) to degrees in [-90, 270)."""
    return wrap_degrees(np.degrees(np.asarray(radians, dtype=float)))


def complex_amplitude(amplitude, phase_degrees):
    """X, with x = Re(X e^{i w t}), of a first harmonic given as its amplitude and its lag in degrees:
    |X| e^{-i lag}; 0 where the amplitude is 0, whose lag is NaN (a mass standing still, structures.solve)."""
    amp = np.asarray(amplitude, dtype=float)
    return np.where(amp == 0.0, 0.0, amp * np.exp(-1j * np.radians(np.asarray(phase_degrees, dtype=float))))
