"""The physical side of a cube whose spec has a `system:` (spec/system.py): coordinates in Hz and N beside
(r, beta), and each dimensionless length or time that the run wrote, again in m and s.

Lengths are ratios times the length scale L (Y; F0/k for force), forces times F_k, energies times F_k L,
time in forcing periods over the frequency f = r f_n. Variables need what they are scaled by: without a
length scale (a system given by its natural frequency and forces alone) no length or energy is written in SI.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from friction_sweep.spec.system import PhysicalMap
from friction_sweep.storage.schema import MOVING_SUFFIX

#: physical variable -> (the dimensionless variable it scales, by what: length L, force F_k, energy F_k L)
SCALED = {
    "displacement_amplitude": ("transmissibility", "length"),
    "peak_displacement": ("peak_transmissibility", "length"),
    "dissipated_energy": ("friction_energy", "energy"),
    "force_amplitude": ("transmitted_force", "force"),
    "history_physical_displacement": ("history_displacement", "length"),
}
#: the cube attribute that records the map, as JSON (`fsweep info` prints it)
ATTRIBUTE = "physical_system"


def coordinates(physical: PhysicalMap) -> dict[str, np.ndarray]:
    """The physical coordinates that the map knows: frequency (Hz), friction_force (N)."""
    coords = {"frequency": physical.frequency, "friction_force": physical.friction_force}
    return {name: np.asarray(values, dtype=np.float64) for name, values in coords.items() if values is not None}


def constants(physical: PhysicalMap) -> dict[str, float]:
    """The system's constants that the map knows, by their scalar coordinate's name (schema.SCALAR_COORDS):
    natural frequency (Hz), mass (kg), stiffness (N/m), length scale and excitation force (where constant),
    base acceleration (where held)."""
    values = {"natural_frequency": physical.natural_frequency, "mass": physical.mass, "stiffness": physical.stiffness,
              "length_scale": physical.length_scale, "excitation_force": physical.reference_force,
              "base_acceleration": physical.acceleration}
    return {name: float(value) for name, value in values.items() if value is not None}


def variables(physical: PhysicalMap, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The physical variables of a run's arrays: lengths in m, forces in N, energies in J, history time in s.
    At constant acceleration the scales depend on the frequency: along the grid's last axis, and at each
    history point's own frequency."""

    def scales(frequency) -> dict[str, Any]:
        force, length = physical.scales_at(frequency)
        return {"length": length, "force": force,
                "energy": force * length if force is not None and length is not None else None}

    out: dict[str, np.ndarray] = {}
    history_frequency = None
    if physical.natural_frequency is not None and "history_frequency_ratio" in arrays:
        history_frequency = np.asarray(arrays["history_frequency_ratio"], dtype=np.float64) * physical.natural_frequency
    grid = scales(physical.frequency)
    at_history = scales(history_frequency[:, None]) if history_frequency is not None else \
        (grid if physical.acceleration is None else {})
    for name, (source, kind) in SCALED.items():
        history = name.startswith("history_")
        scale = (at_history if history else grid).get(kind)
        if scale is None:
            continue
        # a grid variable's twin from the moving start (schema.STATE_VARIABLES) scales alike
        for suffix in ("",) if history else ("", MOVING_SUFFIX):
            if source + suffix in arrays:
                out[name + suffix] = np.asarray(arrays[source + suffix], dtype=np.float64) * scale
    if history_frequency is not None and "history_time" in arrays:
        out["history_physical_time"] = np.asarray(arrays["history_time"], dtype=np.float64) / history_frequency[:, None]
    return out


def from_attribute(text: str) -> PhysicalMap:
    """The map a cube recorded (its coordinates left out); ValueError where the text is not one (read by the
    one bounded reader of a cube's JSON, storage.attributes)."""
    from friction_sweep.storage import attributes

    record = attributes.read_json({ATTRIBUTE: text}, ATTRIBUTE)

    def value(key: str) -> float | None:
        x = record.get(key)
        return float(x) if isinstance(x, (int, float)) and not isinstance(x, bool) else None

    return PhysicalMap(natural_frequency=value("natural_frequency_Hz"), reference_force=value("excitation_force_N"),
                       length_scale=value("length_scale_m"), stiffness=value("stiffness_N_per_m"),
                       frequency=None, friction_force=None, acceleration=value("base_acceleration_m_per_s2"))


def attribute(physical: PhysicalMap) -> str:
    """The map as the JSON a cube records (SI values; null where the spec leaves one open)."""
    record: dict[str, Any] = {
        "natural_frequency_Hz": physical.natural_frequency,
        "excitation_force_N": physical.reference_force,
        "length_scale_m": physical.length_scale,
        "stiffness_N_per_m": physical.stiffness,
        "base_acceleration_m_per_s2": physical.acceleration,
    }
    return json.dumps(record)
