"""Reading a rig's measurements: a small CSV file of numbers, refused with `FILE[:LINE]: reason`.

Shared by `fsweep validate-data` (friction_sweep.validation) and `fsweep calibrate`
(friction_sweep.calibration): lines starting with `#` are comments, the first other line is the header,
every required column must hold a finite number on every row, and the caller adds its own checks of
each value with the row's line number.
"""

from __future__ import annotations

import codecs
import csv
import math
import os
import re
import stat
from collections.abc import Callable, Sequence
from pathlib import Path

import pandas as pd

from friction_sweep.storage.outputs import file_kind

#: a rig's file is kilobytes; a file past this is not measured data, and would take hours to predict
MAX_DATA_BYTES = 16 * 2**20
#: rows a data file may hold: a rig's sweep has tens to hundreds; each costs a simulation
MAX_ROWS = 2000

#: a number as a rig's software writes it: ASCII digits, an optional sign, point and exponent. Python's
#: float() also reads other scripts' digits (Arabic-Indic "١.٤") and underscores ("1_4353"), which no CSV
#: writer produces: a file holding them was edited by hand or by another tool, and is refused, not guessed
PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: a measured phase lag in degrees, in any of the conventions rigs use (lag or lead, wrapped or not)
MEASURED_PHASE_RANGE_DEG = (-180.0, 360.0)

#: a value check: the reason a required column's value is refused, or None
Check = Callable[[str, float, str], "str | None"]


class DataError(ValueError):
    """The measured-data file is missing or malformed."""


def read_table(path: str | os.PathLike[str], required: Sequence[str], check: Check | None = None,
               text: Sequence[str] = ()) -> tuple[pd.DataFrame, list[int]]:
    """The data rows as a DataFrame, in file order, and each row's line number in the file.

    Every required column becomes float64, each value a finite number that `check(column, value, text)`
    does not refuse; the `text` columns must be there too and stay as written (labels); other columns
    that parse as numbers become float64. Raises DataError, its
    message `FILE[:LINE]: reason`, on a file that cannot be read or is not UTF-8 CSV text, missing or
    repeated columns, a row with the wrong number of fields, a refused value, more than MAX_ROWS rows,
    or no data rows.
    """
    path = Path(path)
    header, header_line, rows = None, 0, []
    for number, line in enumerate(_read_text(path).split("\n"), start=1):
        line = line.rstrip("\r")
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            fields = next(csv.reader([line]))
        except csv.Error as err:
            raise DataError(f"{path}:{number}: not a CSV line ({err})") from None
        if header is None:
            header, header_line = [name.strip() for name in fields], number
            _check_header(path, number, header, [*required, *text])
            continue
        if len(fields) != len(header):
            raise DataError(f"{path}:{number}: {len(fields)} fields, but the header (line {header_line}) "
                            f"has {len(header)}")
        rows.append((number, fields))
    if not rows or header is None:  # a header comes before any row
        raise DataError(f"{path}: no data rows")
    if len(rows) > MAX_ROWS:  # each row is simulated (up to ~0.5 s at the lowest frequency ratios)
        raise DataError(f"{path}:{rows[MAX_ROWS][0]}: more than {MAX_ROWS} data rows")
    columns = {name: [fields[i].strip() for _, fields in rows] for i, name in enumerate(header)}
    table = pd.DataFrame(columns)
    for column in header:
        if column in required:
            table[column] = [_required_number(path, number, column, value, check)
                             for (number, _), value in zip(rows, columns[column], strict=True)]
            continue
        if column in text:
            continue
        converted = pd.to_numeric(table[column], errors="coerce")
        if converted.notna().all():
            table[column] = converted.astype(float)
    return table, [number for number, _ in rows]


def _read_text(path: Path) -> str:
    """The file's text, refusing what is not a readable, reasonably small UTF-8 text file."""
    try:
        st = os.stat(path)
    except OSError as err:
        raise DataError(f"{path}: cannot read the measured data: {err.strerror or err}") from None
    # a FIFO or device would block or never end, and a directory is a common slip
    if not stat.S_ISREG(st.st_mode):
        raise DataError(f"{path}: is {file_kind(st.st_mode)}, not a CSV file")
    if st.st_size > MAX_DATA_BYTES:
        raise DataError(f"{path}: {st.st_size} bytes, too large for a measured-data CSV "
                        f"(at most {MAX_DATA_BYTES // 2**20} MiB)")
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_DATA_BYTES + 1)
    except OSError as err:
        raise DataError(f"{path}: cannot read the measured data: {err.strerror or err}") from None
    if not data.strip():
        raise DataError(f"{path}: empty file")
    if b"\0" in data:
        line = data[: data.index(b"\0")].count(b"\n") + 1
        raise DataError(f"{path}:{line}: binary data (a NUL byte), not a CSV text file")
    if data.startswith(codecs.BOM_UTF8):  # as spreadsheets save "UTF-8 CSV"
        data = data[len(codecs.BOM_UTF8):]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data[: err.start].count(b"\n") + 1
        raise DataError(f"{path}:{line}: not UTF-8 text (byte 0x{data[err.start]:02x}); "
                        "save the file as UTF-8 CSV") from None


def _check_header(path: Path, number: int, header: list[str], required: Sequence[str]) -> None:
    repeated = sorted({name for name in header if header.count(name) > 1})
    if repeated:
        raise DataError(f"{path}:{number}: column(s) {', '.join(repeated)} appear more than once")
    missing = [c for c in required if c not in header]
    if missing:
        raise DataError(f"{path}:{number}: missing column(s) {', '.join(missing)} (have: {', '.join(header)})")


def _required_number(path: Path, number: int, column: str, value: str, check: Check | None) -> float:
    """A required column's value on line `number`: a finite number that `check` does not refuse."""
    try:
        x = float(value)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise DataError(f"{path}:{number}: {column} must be a finite number (got {value!r})")
    if not PLAIN_NUMBER.fullmatch(value):
        raise DataError(f"{path}:{number}: {column} must be a number in plain ASCII digits, such as 1.4353 or "
                        f"-2.5e-3 (got {value!r})")
    reason = check(column, x, value) if check is not None else None
    if reason is not None:
        raise DataError(f"{path}:{number}: {column} {reason}")
    return x
