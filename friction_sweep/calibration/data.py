"""The measurements a calibration fits, read from the spec's data file into arrays (friction_sweep.measured).

Every row becomes a point of the scene: its frequency ratio against the spec's reference natural
frequency (the column itself, or the drive frequency over f_n), its force ratio (the column, or the
friction force over F_k), its series (the series column, or the force column's value), the measured
first-harmonic phase (degrees) and/or transmissibility, and their per-row uncertainties. A row the scene
cannot produce is refused with its line: a frequency ratio outside the sweep's range, a force ratio at
which the mass never leaves rest (no phase to measure), a phase outside [-180, 360], a transmissibility
that is not positive, a negative frequency or force, an uncertainty that is not positive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from friction_sweep import ties
from friction_sweep.measured import MEASURED_PHASE_RANGE_DEG, DataError, read_table
from friction_sweep.spec import grid
from friction_sweep.spec.quantities import FORCE, FREQUENCY, to_si
from friction_sweep.theory import scenes

from .spec import CalibrationSpec, data_path


@dataclass(frozen=True)
class Observations:
    """The measured rows, as arrays of one entry per row."""

    path: str
    lines: np.ndarray  # each row's line in the file
    frequency_ratio: np.ndarray  # r against the spec's reference natural frequency (or the data's own)
    force_ratio: np.ndarray  # beta from the data
    series: np.ndarray  # index into series_labels
    series_labels: tuple[str, ...]
    phase: np.ndarray | None  # degrees
    transmissibility: np.ndarray | None
    phase_sd: np.ndarray | None  # degrees, per row
    transmissibility_sd: np.ndarray | None  # of log T, per row
    fitted: np.ndarray  # bool: the row enters the likelihood (not held out)

    @property
    def size(self) -> int:
        return int(self.frequency_ratio.size)

    @property
    def measured(self) -> tuple[str, ...]:
        return tuple(name for name in ("phase", "transmissibility") if getattr(self, name) is not None)


def read_observations(spec: CalibrationSpec) -> Observations:
    """The spec's data file as Observations (DataError: `FILE[:LINE]: reason`)."""
    cols = spec.data.columns
    frequency_col = cols.frequency_ratio or cols.drive_frequency.column  # type: ignore[union-attr]
    force_col = cols.force_ratio or cols.friction_force.column  # type: ignore[union-attr]
    wanted = {frequency_col: "frequency", force_col: "force"}
    for name in ("phase", "transmissibility", "phase_uncertainty", "transmissibility_uncertainty"):
        column = getattr(cols, name)
        if column is not None:
            wanted[column] = name
    path = data_path(spec)

    def check(column: str, x: float, text: str) -> str | None:
        role = wanted[column]
        if role in ("frequency", "force") and x < 0:
            return f"must not be negative (got {text})"
        if role == "frequency" and x == 0:
            return f"must be positive (got {text})"
        if role == "phase" and not MEASURED_PHASE_RANGE_DEG[0] <= x <= MEASURED_PHASE_RANGE_DEG[1]:
            low, high = MEASURED_PHASE_RANGE_DEG
            return f"must be a phase lag in degrees within [{low:g}, {high:g}] (got {text})"
        if role == "transmissibility" and x <= 0:
            return f"must be positive: a measured amplitude ratio (got {text})"
        if role.endswith("_uncertainty") and x <= 0:
            return f"must be positive (got {text})"
        return None

    table, lines = read_table(path, tuple(wanted), check, text=(cols.series,) if cols.series is not None else ())
    lines_arr = np.asarray(lines)
    f_ref = spec.reference_frequency
    if cols.drive_frequency is not None:
        hz = table[frequency_col].to_numpy(float) * to_si(f"1 {cols.drive_frequency.unit}", FREQUENCY)
        r = hz / f_ref  # the spec requires f_n with drive frequencies
    else:
        r = table[frequency_col].to_numpy(float)
    if cols.friction_force is not None:
        newtons = table[force_col].to_numpy(float) * to_si(f"1 {cols.friction_force.unit}", FORCE)
        beta = newtons / spec.reference_force
    else:
        beta = table[force_col].to_numpy(float)
    _refuse(path, lines_arr, ~np.vectorize(grid.frequency_ratio_ok)(r), frequency_col, r,
            f"is frequency ratio {{}} there: it must be {grid.FREQUENCY_RATIO_SPAN}")
    _refuse(path, lines_arr, ~np.vectorize(grid.force_ratio_ok)(beta), force_col, beta,
            f"is force ratio {{}} there: it must be {grid.FORCE_RATIO_SPAN}")
    never = ties.never_moves(scenes.forcing_amplitude(spec.excitation, r), beta)
    _refuse(path, lines_arr, never, force_col, beta, f"is force ratio {{}}: under {spec.excitation} excitation the "
            "mass never leaves rest there (no phase or amplitude to measure): a point outside the scene")
    if cols.series is not None:
        keys = table[cols.series].to_numpy(str)
    else:
        keys = np.array([f"{b:.6g}" for b in table[force_col].to_numpy(float)])
    labels = tuple(dict.fromkeys(keys.tolist()))
    series = np.array([labels.index(k) for k in keys])
    fitted = np.ones(r.size, dtype=bool)
    if spec.data.holdout is not None:
        held = [f"{h:.6g}" if isinstance(h, float) and cols.series is None else str(h) for h in spec.data.holdout]
        unknown = [h for h in held if h not in labels]
        if unknown:
            raise DataError(f"{path}: holdout {', '.join(unknown)} names no series of the data "
                            f"(series: {', '.join(labels)})")
        fitted = ~np.isin(keys, held)
        if not fitted.any():
            raise DataError(f"{path}: the holdout leaves no row to fit")

    def values(name: str) -> np.ndarray | None:
        given = getattr(cols, name)
        return None if given is None else table[given].to_numpy(float)

    return Observations(str(path), lines_arr, r, beta, series, labels, values("phase"), values("transmissibility"),
                        values("phase_uncertainty"), values("transmissibility_uncertainty"), fitted)


def _refuse(path, lines: np.ndarray, bad: np.ndarray, column: str, values: np.ndarray, reason: str) -> None:
    if bad.any():
        i = int(np.argmax(bad))
        more = f" ({int(bad.sum()) - 1} more rows)" if bad.sum() > 1 else ""
        raise DataError(f"{path}:{lines[i]}: {column} {reason.format(f'{values[i]:.6g}')}{more}")
