"""What accuracy costs in time: error against a trusted reference and wall time per point, for every
method and accuracy knob, in three regions of the (r, beta) plane and both kinds of wall.

Reference: Den Hartog's closed form in the continuous region; elsewhere the event method at its
tightest setting, cross-checked against an independent integrator (SciPy's DOP853 with event
switching, friction_sweep.bench.reference). Error: the largest relative error of the first-harmonic
transmissibility over the region's points (a point a setting fails on counts as an infinite error).

The rows `event_jenkins` (and those of any other VARIANTS) measure a method on a scene with an effect, the
Jenkins contact at CONTACT_STIFFNESS: the same points (their regions named after the rigid model's
regimes), against the same method at its tightest setting with the effect (no closed form covers it;
tests/test_jenkins.py checks that reference against an independent DOP853 integrator of the contact).

The rows `event_structure` and `rk4_structure` (STRUCTURE_ROWS) measure the multi-DoF engine (issue 31) on
STRUCTURE, the issue's blade and under-platform damper with a rigid and a Jenkins contact, in the column
`structure` of the excitation dim (force on the blade): points by the platform contact's regime, against
`event` at its tightest setting (tests/test_structure_reference.py checks the engine against an independent
DOP853 integrator of structures), the error the largest over the masses of |X_i - X_ref_i| / max |X_ref|.
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

import numpy as np
import xarray as xr

from friction_sweep import catalogue
from friction_sweep.kernels import steady
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import event, paper, rk4, theory
from friction_sweep.theory import scenes

OUTPUTS = catalogue.DEFAULT_OUTPUTS
EXCITATIONS = ("base", "joined")  # the two walls: fixed (base) and moving with the base (joined)
REGIONS = {
    "continuous": {"base": [(1.5, 0.3), (2.5, 0.4), (0.8, 0.2)], "joined": [(2.0, 0.8), (1.5, 0.4), (3.0, 1.0)]},
    "two_stops": {"base": [(0.7, 0.8), (1.5, 0.7), (3.0, 0.6)], "joined": [(0.95, 0.8), (1.2, 1.1), (2.0, 2.5)]},
    "many_stops": {"base": [(0.1, 0.3), (0.05, 0.3)], "joined": [(0.15, 0.01), (0.1, 0.005)]},
}
SETTINGS: dict[str, list[dict[str, float]]] = {
    # both knobs together, then each alone against a tight other: which one limits the accuracy
    "event": [{"stop_tol": a, "steady_tol": b} for a, b in ((1e-4, 1e-3), (1e-6, 1e-5), (1e-8, 1e-7), (1e-10, 1e-9),
                                                            (1e-12, 1e-10), (1e-12, 1e-5), (1e-6, 1e-10))],
    "rk4": [{"steps_per_period": n} for n in (16, 32, 64, 128, 256, 512, 1024)],
    # the paper's ode45 defaults, then tighter, then a finer output step; its chatter makes stuck
    # phases very slow, so a budget
    "paper": [{"rtol": a, "atol": b, "samples_per_period": n, "max_evaluations": 300_000}
              for a, b, n in ((1e-3, 1e-6, 64), (1e-5, 1e-8, 64), (1e-7, 1e-10, 64), (1e-7, 1e-10, 256))],
}
#: the contact stiffness of the Jenkins rows: stiff enough to keep the rigid model's regimes at most points,
#: soft enough that the contact's own swings (sqrt(1 + kappa) per natural period) show in the cost
CONTACT_STIFFNESS = 100.0
#: rows of a method on a scene with an effect: name -> (method, effects)
VARIANTS = {"event_jenkins": ("event", {"contact_stiffness": CONTACT_STIFFNESS}),
            "rk4_jenkins": ("rk4", {"contact_stiffness": CONTACT_STIFFNESS})}
#: rows of a method on STRUCTURE (the multi-DoF engine): name -> method
STRUCTURE_ROWS = {"event_structure": "event", "rk4_structure": "rk4"}
#: their column of the excitation dim (a force on the structure's blade)
STRUCTURE_COLUMN = "structure"
#: the structure those rows measure: the issue's blade (1) and under-platform damper (0.1) on springs
#: ground-blade 1 and blade-damper 2, a dashpot ground-blade 0.004, a rigid contact damper-ground (friction
#: 0.3) and a Jenkins one blade-base (0.2, k_t 20), the force on the blade (structures.StructureDef's fields)
STRUCTURE = {"excitation": "force", "masses": {"blade": 1.0, "damper": 0.1},
             "springs": (("ground", "blade", 1.0), ("blade", "damper", 2.0)), "dampers": (("ground", "blade", 0.004),),
             "contacts": ({"name": "platform", "between": ("damper", "ground"), "friction": 0.3},
                          {"name": "root", "between": ("blade", "base"), "friction": 0.2, "stiffness": 20.0}),
             "forcing": {"blade": 1.0}}
#: its points (angular frequency, friction_scale) by the platform contact's regime: continuous; stick-slip with
#: two stops a period; many stops (6 and 4 a period at low frequency, and the root's 4 with the platform stuck)
STRUCTURE_REGIONS = {"continuous": [(0.8, 0.3), (2.5, 0.3), (1.2, 0.1)],
                     "two_stops": [(0.8, 1.0), (2.0, 1.0), (1.6, 3.0)],
                     "many_stops": [(0.1, 1.0), (0.3, 0.1), (0.2, 3.0)]}
QUICK_SETTINGS = {"event": SETTINGS["event"][:5:2], "rk4": SETTINGS["rk4"][1::2], "paper": SETTINGS["paper"][:1]}
for _name, _method in (*((n, m) for n, (m, _) in VARIANTS.items()), *STRUCTURE_ROWS.items()):
    SETTINGS[_name] = SETTINGS[_method]
    QUICK_SETTINGS[_name] = QUICK_SETTINGS[_method]
# rk4 on the structure from 128 steps a period: at 32 and 64 its many-stops orbit at frequency 0.1 never settles
# (16 and 6 s a point to the work budget, the error infinite)
SETTINGS["rk4_structure"] = [row for row in SETTINGS["rk4"] if row["steps_per_period"] >= 128]
QUICK_SETTINGS["rk4_structure"] = [row for row in QUICK_SETTINGS["rk4"] if row["steps_per_period"] >= 128]
REFERENCE_SETTINGS = {"stop_tol": 1e-13, "steady_tol": 1e-12}
#: the compiled kernels the rows call (module, entry point): each family compiles on its first call where
#: numba's cache does not hold it (batch.kernel_cache; batch.estimate.COMPILE_SECONDS says how long)
KERNELS = (("steady", "solve_points"), ("jenkins_steady", "solve_points_jenkins"), ("structure.steady", "solve_batch"))
#: CPU seconds (user + sys) of `fsweep bench [--quick]` with those kernels cached, on the 2-core reference
#: machine (/usr/bin/time: 8.8 and 94.8 s, measured while other users loaded it, so that the wall times were
#: 29 and 1490 s). The bench measures in one thread, so alone on a core its wall time is about this. Most of
#: --quick is the DOP853 cross-check (bench/reference.py, one point per region; cProfile).
CACHED_SECONDS = {"quick": 9.0 + 4.5, "full": 95.0 + 12.4}  # + the structure rows (4.5 and 12.4 s, measured alone)
METHODS = {"event": event, "rk4": rk4, "paper": paper}
ALL_ROWS = ("event", "rk4", "paper", *VARIANTS, *STRUCTURE_ROWS)


def method_and_effects(name: str) -> tuple[str, dict]:
    """The method a row runs and the scene effects it runs with."""
    if name in STRUCTURE_ROWS:
        return STRUCTURE_ROWS[name], {}
    return VARIANTS.get(name, (name, {}))


def calibrated_rows(method: str, effects=None, structure: bool = False) -> str:
    """Whose rows `accuracy:` reads for a method on a scene: a structure's those measured on STRUCTURE;
    those measured with the scene's costly effect (a VARIANTS entry: the Jenkins contact, at
    CONTACT_STIFFNESS), else the method's own."""
    if structure:
        return next(name for name, of in STRUCTURE_ROWS.items() if of == method)
    for name, (of, measured_with) in VARIANTS.items():
        if of == method and set(measured_with) <= set(effects or {}):
            return name
    return method


def label(settings: dict) -> str:
    return ", ".join(f"{k}={v:g}" for k, v in settings.items() if k != "max_evaluations")


def _points(region, excitation, quick):
    pts = REGIONS[region][excitation]
    return pts[:1] if quick else pts


def reference(region, excitation, quick, effects=None):
    """Reference transmissibilities of a region's points, and the cross-check discrepancy (NaN: none here)."""
    pts = np.array(_points(region, excitation, quick))
    r, b = pts[:, 0], pts[:, 1]
    if effects:
        return event.solve_flat(excitation, r, b, effects, **REFERENCE_SETTINGS)[:, steady.OUT_TRANSMISSIBILITY], \
            math.nan
    if region == "continuous":
        th = theory.compute_tile(excitation, r, b, OUTPUTS)["transmissibility"].diagonal() if r.size > 1 else \
            theory.compute_tile(excitation, r, b, OUTPUTS)["transmissibility"][0]
        return np.asarray(th), 0.0
    raw = event.solve_flat(excitation, r, b, **REFERENCE_SETTINGS)
    ref = raw[:, steady.OUT_TRANSMISSIBILITY]
    # DOP853 marches from rest as long as the kernel's own march (shooting off) needs to settle
    marched = event.solve_flat(excitation, r, b, **{**REFERENCE_SETTINGS, "shoot_after": 10**9})
    from friction_sweep.bench.reference import measure

    worst = 0.0
    for i, (rr, bb) in enumerate(pts[:1] if quick else pts):  # DOP853 is slow: one point per region in quick
        A, c = scenes.forcing_amplitude(excitation, rr), scenes.response_offset(excitation)
        t_dop, _ = measure(A, rr, bb, bb, int(marched[i, steady.OUT_PERIODS]) + 20, c)
        worst = max(worst, abs(t_dop / ref[i] - 1))
    return ref, worst


def _structure():
    from friction_sweep.structures import ContactDef, StructureDef, assemble

    contacts = tuple(ContactDef(**c) for c in STRUCTURE["contacts"])
    return assemble(StructureDef(**{**STRUCTURE, "contacts": contacts}))


def _structure_solve(pts, settings, method, repeat=1):
    """STRUCTURE's first-harmonic amplitudes (points, masses) at `pts` by `method`, and seconds per point."""
    from friction_sweep.structures import solve_points

    a = _structure()
    w, s = pts[:, 0], pts[:, 1]
    solve_points(a, w[:1], s[:1], settings, method=method)  # compiled before timing
    t = time.perf_counter()
    for _ in range(repeat):
        amplitude = solve_points(a, w, s, settings, method=method)["amplitude"]
    return amplitude, (time.perf_counter() - t) / (repeat * w.size)


def _structure_error(values, ref) -> float:
    """The largest over the points of max_i |X_i - X_ref_i| / max_i |X_ref_i| (inf where one failed)."""
    rel = np.abs(values - ref).max(axis=1) / np.abs(ref).max(axis=1)
    return float(rel.max()) if np.all(np.isfinite(rel)) else np.inf


def _time_points(row, excitation, pts, settings, repeat):
    """(transmissibility per point, seconds per point)."""
    method_name, effects = method_and_effects(row)
    r, b = pts[:, 0], pts[:, 1]
    if method_name == "paper":
        values, t = [], time.perf_counter()
        for rr, bb in pts:
            values.append(paper.solve_point(excitation, rr, bb, settings)["transmissibility"])
        return np.array(values), (time.perf_counter() - t) / len(pts)
    full = {**settings, "kernel": KERNEL_RK4} if method_name == "rk4" else dict(settings)
    event.solve_flat(excitation, r[:1], b[:1], effects, **full)  # compiled before timing
    rr, bb = np.tile(r, repeat), np.tile(b, repeat)
    t = time.perf_counter()
    raw = event.solve_flat(excitation, rr, bb, effects, **full)
    return raw[: r.size, steady.OUT_TRANSMISSIBILITY], (time.perf_counter() - t) / rr.size


def run(quick: bool = False, methods=ALL_ROWS, log=print) -> xr.Dataset:
    table = QUICK_SETTINGS if quick else SETTINGS
    methods = list(methods)
    n_set = max(len(table[m]) for m in methods)
    columns = [*EXCITATIONS, *([STRUCTURE_COLUMN] if set(methods) & set(STRUCTURE_ROWS) else [])]
    shape = (len(methods), n_set, len(REGIONS), len(columns))
    error = np.full(shape, np.nan)
    seconds = np.full(shape, np.nan)
    labels = np.full((len(methods), n_set), "", dtype=object)
    crosscheck = {}
    k = len(EXCITATIONS)  # the structure's column, where its rows are asked for: those rows only
    structure_rows = [(i, m) for i, m in enumerate(methods) if m in STRUCTURE_ROWS]
    for j, region in enumerate(REGIONS if structure_rows else ()):
        pts = np.array(STRUCTURE_REGIONS[region][:1] if quick else STRUCTURE_REGIONS[region])
        ref = _structure_solve(pts, REFERENCE_SETTINGS, "event")[0]
        for i, m in structure_rows:
            for s, settings in enumerate(table[m]):
                labels[i, s] = label(settings)
                values, sec = _structure_solve(pts, settings, STRUCTURE_ROWS[m], repeat=3)
                error[i, s, j, k] = _structure_error(values, ref)
                seconds[i, s, j, k] = sec
                log(f"{STRUCTURE_COLUMN} {region:10s} {m:15s} {labels[i, s]:32s} error {error[i, s, j, k]:.2e} "
                    f"{sec * 1e3:.3f} ms/point")
    for k, exc in enumerate(EXCITATIONS):
        for j, region in enumerate(REGIONS):
            pts = np.array(_points(region, exc, quick))
            ref, disc = reference(region, exc, quick)
            crosscheck[f"{exc}/{region}"] = disc
            refs = {name: reference(region, exc, quick, effects)[0] for name, (_, effects) in VARIANTS.items()
                    if name in methods}
            for i, m in enumerate(methods):
                if m in STRUCTURE_ROWS:
                    continue  # measured in their own column above
                if m == "paper" and (quick and region != "continuous"):
                    continue  # the chattering baseline is slow off the continuous region; full runs only
                for s, settings in enumerate(table[m]):
                    labels[i, s] = label(settings)
                    values, sec = _time_points(m, exc, pts, settings, repeat=1 if m == "paper" else 20)
                    rel = np.abs(values / refs.get(m, ref) - 1)
                    error[i, s, j, k] = np.inf if not np.all(np.isfinite(rel)) else rel.max()
                    seconds[i, s, j, k] = sec
                    log(f"{exc:6s} {region:10s} {m:5s} {labels[i, s]:32s} error {error[i, s, j, k]:.2e} "
                        f"{sec * 1e3:.3f} ms/point")
    ds = xr.Dataset(
        {
            "error": (("method", "setting", "region", "excitation"), error,
                      {"long_name": "largest relative error of the first-harmonic transmissibility", "units": "1"}),
            "seconds_per_point": (("method", "setting", "region", "excitation"), seconds,
                                  {"long_name": "wall time per grid point, one core", "units": "s"}),
            "setting_label": (("method", "setting"), labels.astype(str), {"long_name": "accuracy knobs"}),
        },
        coords={"method": methods, "setting": np.arange(n_set), "region": list(REGIONS), "excitation": columns},
        attrs={"reference": "theory (continuous); event at " + json.dumps(REFERENCE_SETTINGS) + " elsewhere; "
               "rows with effects: their method at that setting with the effects, everywhere; structure rows "
               "(column structure): event at that setting on the structure",
               "structure": json.dumps(STRUCTURE), "structure_points": json.dumps(STRUCTURE_REGIONS),
               "effects": json.dumps({name: effects for name, (_, effects) in VARIANTS.items() if name in methods}),
               "reference_crosscheck_dop853_max_rel": json.dumps(crosscheck),
               "settings": json.dumps({m: table[m] for m in methods}), "quick": int(quick)},
    )
    return ds


def cheapest(ds: xr.Dataset, accuracy: float, method: str, excitation: str | None = None):
    """The cheapest setting of `method` whose error meets `accuracy` in every region (and excitation)."""
    sub = ds.sel({"method": method})
    err = sub["error"] if excitation is None else sub["error"].sel({"excitation": excitation})
    sec = sub["seconds_per_point"] if excitation is None else sub["seconds_per_point"].sel({"excitation": excitation})
    worst = err.max([d for d in err.dims if d != "setting"])
    cost = sec.mean([d for d in sec.dims if d != "setting"])
    ok = (worst <= accuracy).values & np.isfinite(cost.values)
    if not ok.any():
        return None
    best = int(np.argmin(np.where(ok, cost.values, np.inf)))
    return best, str(sub["setting_label"].values[best]), float(cost.values[best]), float(worst.values[best])


def _columns(row: str) -> list[str]:
    """The excitation columns a row is measured in: the structure's, or the 1-DoF walls."""
    return [STRUCTURE_COLUMN] if row in STRUCTURE_ROWS else list(EXCITATIONS)


def markdown(ds: xr.Dataset) -> str:
    """The table of every row (the 1-DoF rows, then the structure's in a table of their own) and the cheapest
    setting of each for three accuracies."""
    lines: list[str] = []
    for structure in (False, True):
        rows = [str(m) for m in ds.method.values if (str(m) in STRUCTURE_ROWS) is structure]
        if rows:
            lines += [*([""] if lines else []), *_table(ds, rows, _columns(rows[0]))]
    lines += ["", "Each cell: largest relative error of the first-harmonic transmissibility (structure: of the masses' "
              "first-harmonic amplitudes, over the largest) / wall time per point.", ""]
    for target in (1e-3, 1e-6, 1e-9):
        for m in ds.method.values:
            pick = cheapest(ds, target, str(m))
            if pick is not None:
                lines.append(f"- for {target:.0e} in transmissibility, method {m} at {pick[1]} costs "
                             f"{pick[2] * 1e3:.3g} ms per point (worst error measured {pick[3]:.1e})")
    return "\n".join(lines)


def _table(ds: xr.Dataset, rows: list[str], excitations: list[str]) -> list[str]:
    cols = [(r, e) for e in excitations for r in ds.region.values]
    lines = ["| method | setting | " + " | ".join(f"{e} {r}" for r, e in cols) + " |",
             "|---|---|" + "---|" * len(cols)]
    for m in rows:
        for s in ds.setting.values:
            lab = str(ds["setting_label"].sel({"method": m, "setting": s}).values)
            if not lab:
                continue
            cells = []
            for r, e in cols:
                err = float(ds["error"].sel({"method": m, "setting": s, "region": r, "excitation": e}))
                sec = float(ds["seconds_per_point"].sel({"method": m, "setting": s, "region": r, "excitation": e}))
                cells.append("–" if np.isnan(sec) else f"{err:.0e} / {sec * 1e3:.2g} ms")
            lines.append(f"| {m} | {lab} | " + " | ".join(cells) + " |")
    return lines


def figure(ds: xr.Dataset, path) -> None:
    """Draw `draw(ds)` into the PNG `path` (atomically)."""
    from friction_sweep.storage.atomic import save_figure

    save_figure(draw(ds), path, dpi=FIGURE_DPI)


def draw(ds: xr.Dataset):
    """The work-precision figure: error against time per point, one panel per region and wall."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(ds.excitation), len(ds.region), figsize=(12, 7), sharex=True, sharey=True)
    for k, e in enumerate(ds.excitation.values):
        for j, r in enumerate(ds.region.values):
            ax = axes[k, j]
            for m in ds.method.values:
                sec = ds["seconds_per_point"].sel({"method": m, "region": r, "excitation": e}).values
                err = ds["error"].sel({"method": m, "region": r, "excitation": e}).values
                ok = np.isfinite(sec) & np.isfinite(err)
                if ok.any():
                    ax.loglog(sec[ok], np.maximum(err[ok], 1e-16), "o-", label=str(m))
            ax.set_title(f"{e}, {r}")
            if k == len(ds.excitation) - 1:
                ax.set_xlabel("wall time per point (s)")
            if j == 0:
                ax.set_ylabel("relative error of |X|/|Y|")
            ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend()
    fig.suptitle("Work-precision: what accuracy costs in time")
    fig.tight_layout()
    return fig


#: the calibration shipped with the package (package data; `make bench` regenerates it in a checkout)
PACKAGED_CALIBRATION = Path(__file__).with_name("calibration.json")
FIGURE_DPI = 110


def user_calibration() -> Path:
    """Where `fsweep bench --calibrate` writes by default, and where `accuracy:` looks first: the
    user's data folder ($XDG_DATA_HOME, else ~/.local/share), never the installed package."""
    base = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(base) / "friction_sweep" / "calibration.json"


def calibration_path() -> Path:
    """The calibration `accuracy:` reads: the user's re-calibration where one exists, else the packaged."""
    user = user_calibration()
    return user if user.is_file() else PACKAGED_CALIBRATION


def output_paths(output, calibrate: bool = False, calibration: Path | None = None) -> list[Path]:
    """What `fsweep bench -o OUTPUT` writes: the dataset, its figure and table beside it, and with
    --calibrate the calibration that `accuracy:` in specs reads (`calibration`, default the user's)."""
    output = Path(output)
    paths = [output, output.with_suffix(".png"), output.with_suffix(".md")]
    return paths + [calibration or user_calibration()] if calibrate else paths


def refuse_outputs(output, calibrate: bool = False, calibration: Path | None = None) -> str | None:
    """Why the benchmark must not write where `output` says (None if it may), asked before the
    minutes of computing: a path that is a link, folder, FIFO or device, or a dataset named so that
    its own figure or table would replace it (`-o x.png`)."""
    from friction_sweep.storage.outputs import refuse_special_output

    paths = output_paths(output, calibrate, calibration)
    if len(set(paths)) < len(paths):
        if calibrate and paths[3] in paths[:3]:
            return f"--calibration {paths[3]}: the benchmark's own dataset, figure or table goes there"
        return (f"{output}: the figure and the table are written beside the dataset with the suffixes .png "
                "and .md, so the dataset cannot have either: name it .nc (or .h5)")
    return next((f"output: {reason}" for reason in map(refuse_special_output, paths) if reason), None)


def write(ds: xr.Dataset, output, calibrate: bool = False, calibration: Path | None = None, *,
          overwrite: bool = True) -> list[Path]:
    """Write the dataset, figure, table (and calibration) of `output_paths`, all or nothing:
    everything is rendered first, then written (storage.outputs.write_all), so a failure (a full
    disk) changes none of them; without `overwrite`, none replaces a file. Returns the paths written."""
    import matplotlib.pyplot as plt

    from friction_sweep.storage import atomic, cube, outputs

    paths = output_paths(output, calibrate, calibration)
    table = markdown(ds) + "\n"
    calibration_text = json.dumps(calibration_table(ds), indent=1) + "\n" if calibrate else ""
    fig = draw(ds)
    writers = [
        (paths[0], lambda tmp: cube.write_atomic(ds, tmp, overwrite=True)),
        (paths[1], lambda tmp: atomic.save_figure(fig, tmp, dpi=FIGURE_DPI)),
        (paths[2], lambda tmp: atomic.write_text(tmp, table)),
    ]
    if calibrate:
        writers.append((paths[3], lambda tmp: atomic.write_text(tmp, calibration_text)))
    try:
        return outputs.write_all(writers, overwrite=overwrite)
    finally:
        plt.close(fig)  # save_figure closes it too, but not when an earlier write failed


def calibration_table(ds: xr.Dataset) -> dict:
    """Per method and setting: the worst error over every region and excitation, and the mean cost."""
    table = {}
    settings = json.loads(ds.attrs["settings"])
    for m in ds.method.values:
        rows = []
        own = {"excitation": _columns(str(m))}  # the cells the row is measured in
        for s, st in enumerate(settings[str(m)]):
            err = ds["error"].sel({"method": m, "setting": s, **own}).values
            sec = ds["seconds_per_point"].sel({"method": m, "setting": s, **own}).values
            complete = np.all(np.isfinite(sec))
            rows.append({"settings": st, "worst_error": float(np.max(err)) if complete else None,
                         "seconds_per_point": float(np.nanmean(sec))})
        table[str(m)] = rows
    return table


#: a calibration is a few kilobytes (one row per method and setting); a file past this is something else
MAX_CALIBRATION_BYTES = 2**20
#: the keys of a calibration row (calibration_table)
ROW_KEYS = ("settings", "worst_error", "seconds_per_point")


class CalibrationError(LookupError):
    """The calibration file `accuracy:` reads is not one `fsweep bench --calibrate` writes: `FILE: key: reason`.
    A LookupError, as `accuracy:` finding no setting is: the spec's accuracy cannot be honoured."""


def read_calibration(path: Path) -> dict:
    """The calibration at `path`, its structure checked whole (CalibrationError otherwise): a JSON object
    of rows by ALL_ROWS name, each a list of objects of exactly ROW_KEYS, whose settings are the row's
    method's (catalogue) with numbers for values, worst_error a number >= 0 (inf: never met) or null (the
    setting failed somewhere), seconds_per_point a finite number >= 0 (any number where worst_error is null)."""

    def refuse(key: str, reason: str) -> CalibrationError:
        return CalibrationError(f"{path}: {key}{': ' if key else ''}{reason}")

    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_CALIBRATION_BYTES + 1)
    except OSError as err:
        raise refuse("", f"cannot be read: {err.strerror or err}") from None
    if len(data) > MAX_CALIBRATION_BYTES:
        raise refuse("", f"over {MAX_CALIBRATION_BYTES // 2**20} MiB: not a calibration (fsweep bench --calibrate)")
    try:
        table = json.loads(data.decode("utf-8"))
    except UnicodeDecodeError as err:
        raise refuse("", f"not UTF-8 text (byte {err.start})") from None
    except ValueError as err:  # json.JSONDecodeError: with its line and column
        raise refuse("", f"not JSON ({err})") from None
    except RecursionError:
        raise refuse("", "not a calibration: nested too deeply") from None
    if not isinstance(table, dict):
        raise refuse("", f"must be a JSON object of rows by method (got {_json_kind(table)})")
    for name, rows in table.items():
        if name not in ALL_ROWS:
            raise refuse(_shown(name), f"unknown row name (known: {', '.join(ALL_ROWS)})")
        if not isinstance(rows, list):
            raise refuse(name, f"must be a list of rows (got {_json_kind(rows)})")
        known = catalogue.method(method_and_effects(name)[0]).settings
        for i, row in enumerate(rows):
            where = f"{name}[{i}]"
            if not isinstance(row, dict):
                raise refuse(where, f"must be an object with keys {', '.join(ROW_KEYS)} (got {_json_kind(row)})")
            if set(row) != set(ROW_KEYS):
                has = ", ".join(map(_shown, row))
                raise refuse(where, f"must have exactly the keys {', '.join(ROW_KEYS)} (has {has})")
            settings = row["settings"]
            if not isinstance(settings, dict):
                raise refuse(f"{where}.settings", f"must be an object of settings (got {_json_kind(settings)})")
            for key, value in settings.items():
                if key not in known:
                    raise refuse(f"{where}.settings.{_shown(key)}", f"not a setting of {method_and_effects(name)[0]} "
                                 f"(its settings: {', '.join(known)})")
                if not _finite(value):
                    raise refuse(f"{where}.settings.{key}", f"must be a finite number (got {_shown(value)})")
            error, seconds = row["worst_error"], row["seconds_per_point"]
            if error is not None and (not _number(error) or not error >= 0):
                raise refuse(f"{where}.worst_error", f"must be a number >= 0, or null (got {_shown(error)})")
            if not _number(seconds) or (error is not None and not (_finite(seconds) and seconds >= 0)):
                raise refuse(f"{where}.seconds_per_point", f"must be a finite number >= 0 (got {_shown(seconds)})")
    return table


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _finite(value) -> bool:
    try:
        return _number(value) and math.isfinite(value)
    except OverflowError:  # an int beyond any float
        return False


def _json_kind(value) -> str:
    kinds = {dict: "an object", list: "a list", str: "a string", bool: "true/false", type(None): "null"}
    return kinds.get(type(value), "a number")


def _shown(value) -> str:
    text = json.dumps(value, ensure_ascii=True) if not isinstance(value, float) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def choose(method: str, accuracy: float, table: dict | None = None, effects=None,
           structure: bool = False) -> tuple[dict, dict]:
    """The cheapest calibrated setting of `method`, within the catalogue's ranges, whose worst measured
    error meets `accuracy`, on a scene with `effects` or on a structure (calibrated_rows).

    Returns (settings, the calibration row). Raises LookupError when none does, CalibrationError where the
    calibration file is not one (read_calibration)."""
    table = table if table is not None else read_calibration(calibration_path())
    rows_of = calibrated_rows(method, effects, structure)
    # only settings that a spec could give itself: the benchmark also measures looser ones, to show
    # the whole curve, but outside the catalogue's ranges a point may be mislabelled
    known = catalogue.method(method).settings
    measured = [row for row in table.get(rows_of, []) if row["worst_error"] is not None
                and all(known[k].contains(v) for k, v in row["settings"].items() if k in known)]
    rows = [row for row in measured if row["worst_error"] <= accuracy]
    if not rows:
        best = min((row["worst_error"] for row in measured), default=None)
        measured_as = ("" if rows_of == method else " (as measured on the benchmark's structure)" if structure
                       else f" (as measured with {', '.join(VARIANTS[rows_of][1])})")
        raise LookupError(f"no calibrated setting of method {method!r}{measured_as} reaches {accuracy:g} "
                          f"(the best measured is {best:.1e})" if best is not None else
                          f"method {method!r}{measured_as} has no calibration")
    row = min(rows, key=lambda row: row["seconds_per_point"])
    settings = {k: v for k, v in row["settings"].items() if k != "max_evaluations"}
    return settings, {**row, "measured_as": rows_of}
