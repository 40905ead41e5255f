"""make calibrate: calibrate the model to the rig's measured phases, in sample and out of sample, and put
the summary into the README between its markers.

1. `fsweep calibrate configs/calibration/rig.yaml`: every series' friction force, the natural frequency,
   the phase noise and a constant phase offset, from all 36 rows.
2. Four folds out of sample (configs/calibration/rig_holdout.yaml with data.holdout set to each series in
   turn): one factor on the rig's measured friction forces (friction_scale) instead of a force per series,
   so that the held-out series is predicted from its own measured friction, fitted on the other three.
3. Beside each, the plain model (the rig's stated values, no offset: what validate-data compares) on the
   same rows.

Writes results/calibration/summary.md only: a user's `make calibrate` never edits a tracked file. The
maintainers' `make refresh-readme` copies that summary into the README's <!-- calibrate --> section
(benchmarks/readme_tables.py).
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from friction_sweep.calibration.report import SAMPLER_TITLE

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "calibration"
RIG = ROOT / "configs" / "calibration" / "rig.yaml"
HOLDOUT = ROOT / "configs" / "calibration" / "rig_holdout.yaml"
FSWEEP = Path(sys.executable).with_name("fsweep")


def run(spec: Path, out: Path) -> float:
    began = time.perf_counter()
    subprocess.run([str(FSWEEP), "calibrate", str(spec), "-j", "2", "-q", "--overwrite", "-o", str(out)], check=True,
                   cwd=ROOT)
    return time.perf_counter() - began


def plain_residuals() -> pd.Series:
    """The plain model's phase misfit per row (degrees, wrapped): event at the rig's stated f_n and
    friction forces, no offset, at the (r, beta) the calibration reads from rig.yaml (drive frequencies
    over its f_n, friction forces over its F_k)."""
    from friction_sweep import validation
    from friction_sweep.calibration.data import read_observations
    from friction_sweep.calibration.spec import load_calibration_spec

    obs = read_observations(load_calibration_spec(RIG))
    table = validation.read_measurements()
    table["frequency_ratio"] = obs.frequency_ratio
    table["force_ratio"] = obs.force_ratio
    predicted = validation.predict(table)
    return -predicted["event_phase_error_deg"]  # measured - predicted, as the calibration's table


def stats(d) -> str:
    d = np.asarray(d, dtype=float)
    return f"{np.sqrt(np.mean(d**2)):.2f}° RMS, {np.max(np.abs(d)):.2f}° max"


def section(text: str, title: str) -> str:
    """A '## title' section of a report, without its heading."""
    body = text.split(f"## {title}\n", 1)[1]
    return body.split("\n## ", 1)[0].strip()


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    seconds = run(RIG, OUT / "rig")
    rig_report = (OUT / "rig" / "report.md").read_text()
    rig_table = pd.read_csv(OUT / "rig" / "map.csv")
    plain = plain_residuals()
    series = list(dict.fromkeys(rig_table["series"].astype(str)))
    folds = []
    template = HOLDOUT.read_text()
    for label in series:
        spec = OUT / f"holdout_{label}.yaml"
        # its data is named package:data/..., so the copy finds it from here
        spec.write_text(template.replace("holdout: [0.2175]", f"holdout: [{label}]"))
        run(spec, OUT / f"holdout_{label}")
        table = pd.read_csv(OUT / f"holdout_{label}" / "map.csv")
        held = table["fitted"] == False  # noqa: E712 - a column of booleans read from CSV
        folds.append((label, table.loc[held, "phase_residual_deg"], plain[held.to_numpy()]))
    lines = [
        "`make calibrate` (written to results/calibration/summary.md; the maintainers' `make refresh-readme` "
        "publishes it here): `fsweep calibrate configs/calibration/rig.yaml -j 2` on the rig's 36 measured "
        "first-harmonic phases, event model.",
        "",
        section(rig_report, "Parameters"),
        "",
        section(rig_report, SAMPLER_TITLE),
        "",
        f"Whole command {seconds:.0f} s on 2 cores; " + section(rig_report, "Fit").split("Time: ", 1)[1].split("\n")[0],
        "",
        "| phase residuals | plain model (stated f_n and friction, no offset) | calibrated (MAP) |",
        "|---|---|---|",
        f"| all 36 rows, in sample | {stats(plain)} | {stats(rig_table['phase_residual_deg'])} |",
    ]
    for label, calibrated, baseline in folds:
        lines.append(f"| series {label} N held out: fitted on the other three (one factor on the measured friction "
                     f"forces, f_n, noise, offset), predicted | {stats(baseline)} | {stats(calibrated)} |")
    text = "\n".join(lines) + "\n"
    (OUT / "summary.md").write_text(text)
    print(text)
    print(f"wrote {OUT / 'summary.md'} (make refresh-readme puts it into the README)")

if __name__ == "__main__":
    main()
