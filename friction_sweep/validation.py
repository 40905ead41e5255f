"""Validation against measured data: the phase lags of a fixed-wall base-excitation rig.

The data (`shared/data/experiment_phase_fixed_wall.csv`, Marino & Cicirello 2020) hold 36 measured
phase lags between the base and the mass displacement: 4 force ratios x 9 frequency ratios. For each
point, at its measured frequency ratio (not the nominal one), this module predicts the lag with

* the theory (`friction_sweep.methods.theory.compute_tile`, excitation `base`), and
* the exact event-driven simulation (`friction_sweep.methods.event.compute_tile`),

each in both phase definitions of the cube: `phase` (first harmonic, what an FFT or a lock-in
measures) and `peak_phase` (between the maxima of excitation and response, Den Hartog's phi), and
summarises |predicted - measured| by its maximum and RMS for each method and definition.

    fsweep validate-data [--data PATH] [-o DIR] [--overwrite]   (or: python -m friction_sweep.validation)

writes `table.csv`, `table.md` and `phase_measured_vs_predicted.png` into DIR (default
results/validation), all three or none; files already there only with --overwrite, and never the
data. The PNG needs matplotlib (the `figures` extra): without it the command refuses before
computing anything.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import click
import numpy as np
import pandas as pd

from friction_sweep import codes
from friction_sweep.codes import Regime
from friction_sweep.exits import EXIT_RUNTIME, fail
from friction_sweep.measured import MEASURED_PHASE_RANGE_DEG, DataError, read_table
from friction_sweep.packaged import InputPath
from friction_sweep.spec import grid
from friction_sweep.storage import outputs
from friction_sweep.storage.atomic import save_figure, write_text

#: the rig's 36 measured phases, shipped with the package (source in the file's header); a copy of
#: the project's shared/data/experiment_phase_fixed_wall.csv, kept equal by tests/test_validation.py
DEFAULT_DATA = Path(__file__).with_name("data") / "experiment_phase_fixed_wall.csv"
DEFAULT_OUTPUT_DIR = Path("results/validation")
EXCITATION = "base"  # fixed wall, base motion

#: columns the CSV must have (others are kept as they are)
REQUIRED = ("force_ratio", "frequency_ratio", "phase_deg")
METHODS = ("theory", "event")
DEFINITIONS = ("phase", "peak_phase")  # first harmonic; between maxima
DEFINITION_NAMES = {"phase": "first-harmonic phase", "peak_phase": "peak (between maxima) phase"}
OUTPUT_FILES = ("table.csv", "table.md", "phase_measured_vs_predicted.png")
FIGURE_DPI = 150


# --- reading ----------------------------------------------------------------------------------------


def read_measurements(path: str | os.PathLike[str] | None = None) -> pd.DataFrame:
    """The measured points as a DataFrame, one row per point, in file order (friction_sweep.measured:
    comments, header, finite numbers; DataError `FILE[:LINE]: reason` otherwise), with frequency ratios
    and force ratios inside the spec's ranges (spec.grid)."""
    return read_table(Path(path) if path is not None else DEFAULT_DATA, REQUIRED, _in_range)[0]


def _in_range(column: str, x: float, value: str) -> str | None:
    """Why a required value is outside the spec's ranges (a phase: outside MEASURED_PHASE_RANGE_DEG), or None."""
    if column == "frequency_ratio" and not grid.frequency_ratio_ok(x):
        return f"must be {grid.FREQUENCY_RATIO_SPAN} (got {value}): {grid.FREQUENCY_RATIO_NOTE}"
    if column == "force_ratio" and not grid.force_ratio_ok(x):
        return f"must be {grid.FORCE_RATIO_SPAN} (got {value})"
    low, high = MEASURED_PHASE_RANGE_DEG
    if column == "phase_deg" and not low <= x <= high:
        return f"must be a phase lag in degrees within [{low:g}, {high:g}] (got {value})"
    return None


# --- predicting -------------------------------------------------------------------------------------


def _wrap_difference(predicted, measured):
    """predicted - measured in degrees, wrapped into [-180, 180)."""
    d = np.asarray(predicted, dtype=float) - np.asarray(measured, dtype=float)
    return np.mod(d + 180.0, 360.0) - 180.0


def predict_point(method: str, r: float, beta: float) -> dict:
    """Regime, first-harmonic and peak phase lag (degrees) at one (r, beta), base excitation."""
    from friction_sweep import methods  # here, so that loading the CLI loads no numba kernels

    out = methods.get(method).compute_tile(EXCITATION, np.array([r]), np.array([beta]), ("phase", "regime"))
    return {
        "regime": codes.name_of(Regime, out["regime"][0, 0]),
        "phase": float(out["phase"][0, 0]),
        "peak_phase": float(out["peak_phase"][0, 0]),
    }


def predict(table: pd.DataFrame) -> pd.DataFrame:
    """The measured table with, per method, the regime, both predicted phases and their errors
    (predicted - measured, degrees; NaN where a method gives no phase, e.g. theory off its range)."""
    out = table.copy()
    for method in METHODS:
        points = zip(table["frequency_ratio"], table["force_ratio"], strict=True)
        preds = [predict_point(method, float(r), float(b)) for r, b in points]
        out[f"{method}_regime"] = [p["regime"] for p in preds]
        for definition in DEFINITIONS:
            values = np.array([p[definition] for p in preds])
            out[f"{method}_{definition}_deg"] = values
            out[f"{method}_{definition}_error_deg"] = _wrap_difference(values, table["phase_deg"])
    return out


def summarize(table: pd.DataFrame) -> pd.DataFrame:
    """Max and RMS of |predicted - measured| per method and phase definition (over the points where
    the method gives a phase; `points` counts them)."""
    rows = []
    for method in METHODS:
        for definition in DEFINITIONS:
            signed = table[f"{method}_{definition}_error_deg"].to_numpy(dtype=float)
            signed = signed[np.isfinite(signed)]
            err = np.abs(signed)
            rows.append({
                "method": method,
                "definition": definition,
                "points": int(err.size),
                "max_abs_deg": float(err.max()) if err.size else math.nan,
                "rms_deg": float(np.sqrt(np.mean(err**2))) if err.size else math.nan,
                "mean_signed_deg": float(signed.mean()) if err.size else math.nan,
            })
    return pd.DataFrame(rows)


def validate(data: str | os.PathLike[str] | None = None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Read the data, predict every point with both methods; return (table, summary)."""
    table = predict(read_measurements(data))
    return table, summarize(table)


# --- reporting --------------------------------------------------------------------------------------

_MD_COLUMNS = (
    ("force_ratio", "F_mu/F_k", "{:.4f}"),
    ("frequency_ratio", "r (measured)", "{:.4f}"),
    ("phase_deg", "measured (deg)", "{:.2f}"),
    ("theory_regime", "theory regime", "{}"),
    ("theory_phase_deg", "theory 1st harm.", "{:.2f}"),
    ("theory_peak_phase_deg", "theory peak", "{:.2f}"),
    ("event_regime", "event regime", "{}"),
    ("event_phase_deg", "event 1st harm.", "{:.2f}"),
    ("event_peak_phase_deg", "event peak", "{:.2f}"),
    ("theory_phase_error_deg", "Δ theory 1st harm.", "{:+.2f}"),
    ("theory_peak_phase_error_deg", "Δ theory peak", "{:+.2f}"),
    ("event_phase_error_deg", "Δ event 1st harm.", "{:+.2f}"),
    ("event_peak_phase_error_deg", "Δ event peak", "{:+.2f}"),
)


def _cell(fmt: str, value) -> str:
    if isinstance(value, float) and not math.isfinite(value):
        return "—"
    return fmt.format(value)


def markdown_table(table: pd.DataFrame) -> str:
    head = "| " + " | ".join(title for _, title, _ in _MD_COLUMNS) + " |"
    rule = "|" + "|".join("---" if fmt == "{}" else "---:" for _, _, fmt in _MD_COLUMNS) + "|"
    body = ["| " + " | ".join(_cell(fmt, row[col]) for col, _, fmt in _MD_COLUMNS) + " |"
            for _, row in table.iterrows()]
    return "\n".join([head, rule, *body])


def markdown_summary(summary: pd.DataFrame) -> str:
    lines = ["| method | phase definition | points | max \\|Δ\\| (deg) | RMS Δ (deg) | mean Δ (deg) |",
             "|---|---|---:|---:|---:|---:|"]
    for _, s in summary.iterrows():
        lines.append(f"| {s['method']} | {DEFINITION_NAMES[s['definition']]} | {s['points']} | "
                     f"{_cell('{:.2f}', s['max_abs_deg'])} | {_cell('{:.2f}', s['rms_deg'])} | "
                     f"{_cell('{:+.2f}', s['mean_signed_deg'])} |")
    return "\n".join(lines)


def markdown_report(table: pd.DataFrame, summary: pd.DataFrame, data_path) -> str:
    return (
        "# Phase lag: measured against predicted (fixed-wall base excitation)\n\n"
        f"Data: `{data_path}` ({len(table)} points). Predictions at the measured frequency ratio. "
        "Δ = predicted − measured, degrees.\n\n"
        "## Summary\n\n" + markdown_summary(summary) + "\n\n## Points\n\n" + markdown_table(table) + "\n"
    )


def plot(table: pd.DataFrame, path: str | os.PathLike[str]) -> Path:
    """Draw `figure(table)` into the PNG `path` (atomically)."""
    return save_figure(figure(table), Path(path), dpi=FIGURE_DPI)


def figure(table: pd.DataFrame):
    """Measured against predicted phase, one panel per phase definition, one marker per force ratio
    (theory filled, event simulation as black crosses on top), with the identity line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    markers = "osD^vP*X"
    betas = sorted(table["force_ratio"].unique())
    colours = [plt.get_cmap("viridis")(x) for x in np.linspace(0.0, 0.85, max(len(betas), 1))]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.8), constrained_layout=True)
    lo = min(-5.0, float(np.nanmin(table["phase_deg"])) - 5)
    hi = max(185.0, float(np.nanmax(table["phase_deg"])) + 5)
    for ax, definition in zip(axes, DEFINITIONS, strict=False):
        ax.plot([lo, hi], [lo, hi], color="0.4", lw=1, label="predicted = measured")
        for k, (beta, colour) in enumerate(zip(betas, colours, strict=False)):
            sel = table["force_ratio"] == beta
            ax.plot(table.loc[sel, "phase_deg"], table.loc[sel, f"theory_{definition}_deg"], markers[k % len(markers)],
                    color=colour, ms=7, label=rf"theory, $F_\mu/F_k = {beta:g}$")
        ax.plot(table["phase_deg"], table[f"event_{definition}_deg"], "x", color="k", ms=5, label="event simulation")
        ax.set(xlim=(lo, hi), ylim=(lo, hi), aspect="equal", xlabel="measured phase lag (deg)",
               ylabel=f"predicted {DEFINITION_NAMES[definition]} lag (deg)",
               title=f"{DEFINITION_NAMES[definition]}".capitalize())
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=7.5)
    fig.suptitle("Fixed-wall base excitation: measured against predicted phase lag")
    return fig


def write_outputs(table: pd.DataFrame, summary: pd.DataFrame, output_dir, data_path, *,
                  overwrite: bool = True) -> list[Path]:
    """Write table.csv, table.md and the figure into `output_dir`, all or nothing: everything is
    rendered first, then written (outputs.write_all), so a failure changes none of the three; without
    `overwrite`, none replaces a file."""
    import matplotlib.pyplot as plt

    csv_path, md_path, png_path = (Path(output_dir) / name for name in OUTPUT_FILES)
    csv_text = table.to_csv(index=False, float_format="%.10g")
    md_text = markdown_report(table, summary, data_path)
    fig = figure(table)
    try:
        return outputs.write_all([
            (csv_path, lambda tmp: write_text(tmp, csv_text)),
            (md_path, lambda tmp: write_text(tmp, md_text)),
            (png_path, lambda tmp: save_figure(fig, tmp, dpi=FIGURE_DPI)),
        ], overwrite=overwrite)
    finally:
        plt.close(fig)  # save_figure closes it too, but not when an earlier write failed


# --- command ----------------------------------------------------------------------------------------


@click.command("validate-data")
# no click.Path checks (dir_okay, file_okay): their refusals are multi-line usage errors; ours
# below are one line each
@click.option("--data", type=InputPath(), default=None,
              help=f"Measured data CSV (default: {DEFAULT_DATA}).")
@click.option("-o", "--output-dir", type=click.Path(path_type=Path), default=DEFAULT_OUTPUT_DIR,
              show_default=True, help="Folder for table.csv, table.md and phase_measured_vs_predicted.png.")
@click.option("--overwrite", is_flag=True, help="Replace the three files of an earlier run (never the data).")
def validate_data(data: Path | None, output_dir: Path, overwrite: bool):
    """Compare the measured phase lags of the fixed-wall rig with the theory and the simulation."""
    # Every refusal comes before the predictions (seconds; more where numba compiles first), and
    # nothing is written until everything is computed.
    if data is None and not DEFAULT_DATA.exists():
        fail(f"no measured data at {DEFAULT_DATA} (the default, shipped with the package): "
              "pass --data FILE")
    data_path = data if data is not None else DEFAULT_DATA
    refusal = outputs.refuse_name(str(data_path), "data")  # its path is written into table.md
    if refusal:
        fail(refusal)
    try:
        measured = read_measurements(data_path)
    except DataError as err:
        fail(str(err))
    refusal = outputs.refuse_stdout(output_dir)
    if refusal:
        fail(f"output: {refusal}")
    targets = [output_dir / name for name in OUTPUT_FILES]
    for target in targets:
        refusal = outputs.refuse_special_output(target)
        if refusal:
            fail(f"output: {refusal}")
    refusal = outputs.refuse_replacing(targets, overwrite, inputs=[data_path])
    if refusal:
        fail(refusal)
    missing = outputs.missing_figures_extra()
    if missing:
        fail(missing)

    table = predict(measured)
    summary = summarize(table)
    click.echo(f"measured data: {data_path} ({len(table)} points, force ratios "
               f"{', '.join(f'{b:g}' for b in sorted(table['force_ratio'].unique()))})")
    click.echo("phase lags in degrees; predictions at the measured frequency ratio; Δ = predicted − measured\n")
    click.echo(markdown_table(table))
    click.echo("\nsummary of |Δ|:\n")
    click.echo(markdown_summary(summary))
    try:
        paths = write_outputs(table, summary, output_dir, data_path, overwrite=overwrite)
    except FileExistsError as err:
        fail(str(err))
    except OSError as err:
        fail(f"could not write into {output_dir}: {err.strerror or err}; no output was changed", EXIT_RUNTIME)
    click.echo("\nwrote " + ", ".join(str(p) for p in paths))


if __name__ == "__main__":
    validate_data()
