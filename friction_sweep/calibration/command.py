"""`fsweep calibrate SPEC`: infer the friction, the natural frequency and the scene's effects from a rig's
measurements, in two stages (MAP by least squares; posterior samples by emcee), with honest diagnostics.

Every refusal comes before any computation (the spec, the extra, the data, the output folder), as one
line, exit 2; a prior under which no draw explains the data is refused the same way, after the few model
evaluations that tell. Nothing is written until everything is computed, and then all files or none.
"""

from __future__ import annotations

import importlib.util
import math
import shlex
import time
from pathlib import Path

import click
import numpy as np

from friction_sweep.batch.executors import MAX_JOBS
from friction_sweep.exits import EXIT_RUNTIME, fail
from friction_sweep.measured import DataError
from friction_sweep.packaged import InputPath
from friction_sweep.progress import ProgressBar
from friction_sweep.spec import SpecError
from friction_sweep.storage import outputs, provenance
from friction_sweep.storage.schema import CONVENTIONS

from . import report
from .data import read_observations
from .fit import fit_map
from .model import ForwardModel
from .posterior import Posterior
from .sampler import NoLikelihood, Targets, sample, start_from_prior
from .spec import MAX_SEED, load_calibration_spec

CALIBRATE_EXTRA = "pip install 'friction_sweep[calibrate]' (emcee and ArviZ)"
#: a run estimated to take longer than this is refused without --yes
MAX_SECONDS = 30 * 60
#: steps per autocorrelation time guessed for the estimate (emcee's DE moves in a handful of dimensions)
TAU_GUESS = 25.0


def missing_extra() -> str | None:
    missing = [name for name in ("emcee", "arviz") if importlib.util.find_spec(name) is None]
    if missing:
        return f"fsweep calibrate needs {' and '.join(missing)}: {CALIBRATE_EXTRA}"
    return outputs.missing_figures_extra()


@click.command("calibrate")
@click.argument("spec_path", metavar="SPEC", type=InputPath())
@click.option("-o", "--output", type=click.Path(path_type=Path), help="Folder for the results (overrides the "
              "spec's `output`; default results/<spec name>).")
@click.option("-j", "--jobs", type=click.IntRange(min=1, max=MAX_JOBS), default=1, show_default=True,
              help="Threads for the model evaluations.")
@click.option("--seed", type=click.IntRange(min=0, max=MAX_SEED), default=None,
              help="Random seed (overrides sampler.seed).")
@click.option("-q", "--quiet", is_flag=True, help="No progress bar.")
@click.option("--yes", is_flag=True, help="Run even when estimated to take over 30 minutes.")
@click.option("--overwrite", is_flag=True, help="Replace the results of an earlier calibration in the folder "
              "(all together; never the spec or the data).")
def calibrate(spec_path: Path, output: Path | None, jobs: int, seed: int | None, quiet: bool, yes: bool,
              overwrite: bool):
    """Calibrate the model to a rig's measurements (MAP, then posterior samples).

    SPEC is a calibration spec file, or one shipped with the package named package:PATH, from any folder:
    `fsweep calibrate package:examples/calibration/rig.yaml` calibrates to the rig's measured phases, which
    that spec names as `data: {file: package:data/experiment_phase_fixed_wall.csv}`. Results go to the
    spec's `output`, relative to the working directory."""
    began = time.perf_counter()
    refusal = outputs.refuse_name(str(spec_path), "spec")  # paths are written into the report
    if refusal:
        fail(refusal)
    try:
        spec = load_calibration_spec(spec_path)
    except SpecError as err:
        fail(f"invalid calibration spec\n{err}")
    missing = missing_extra()
    if missing:
        fail(missing)
    try:
        obs = read_observations(spec)
    except DataError as err:
        fail(str(err))
    refusal = outputs.refuse_name(obs.path, "data")
    if refusal:
        fail(refusal)
    folder = output if output is not None else Path(spec.output or Path("results") / spec_path.stem)
    refusal = outputs.refuse_stdout(folder)
    if refusal:
        fail(f"output: {refusal}")
    targets = [folder / name for name in report.OUTPUT_FILES]
    for target in targets:
        refusal = outputs.refuse_special_output(target)
        if refusal:
            fail(f"output: {refusal}")
    refusal = outputs.refuse_replacing(targets, overwrite, inputs=[spec_path, obs.path])
    if refusal:
        fail(refusal)
    settings = spec.sampler
    seed = settings.seed if seed is None else seed
    model = ForwardModel(spec, obs, jobs=jobs)
    short = model.too_few_rows()
    if short:
        fail(short)
    post = Posterior(model)
    rng = np.random.default_rng(seed)
    try:
        start = start_from_prior(post, settings.walkers, rng)  # refuses a prior that explains no data (exit 2)
    except NoLikelihood as err:
        fail(f"{spec.locate('parameters')}: {err}")
    t0 = time.perf_counter()  # the start's evaluations loaded the kernels: time a step now
    post(np.column_stack([p.prior.sample(rng, settings.walkers) for p in model.parameters]))
    per_step = time.perf_counter() - t0
    steps = max(settings.autocorr_times * TAU_GUESS, settings.min_ess * TAU_GUESS / (0.75 * settings.walkers))
    estimate = per_step * min(steps, settings.max_steps)
    click.echo(f"calibrating {', '.join(model.names)} from {obs.size} rows of {obs.path} "
               f"({spec.method} model, {settings.walkers} walkers, seed {seed})")
    click.echo(f"estimate: {per_step * 1e3:.1f} ms a step of the sampler, about {estimate:.0f} s for "
               f"{min(steps, settings.max_steps):.0f} steps (tau guessed {TAU_GUESS:g}; the run stops when its own "
               "diagnostics are met)")
    if estimate > MAX_SECONDS and not yes:
        fail(f"estimated {estimate / 60:.0f} min, over {MAX_SECONDS // 60} min: pass --yes to run it anyway, or "
             "fewer walkers, rows or a cheaper method")

    t0 = time.perf_counter()
    fit = fit_map(post)
    map_seconds = time.perf_counter() - t0
    if math.isfinite(fit.log_posterior):
        click.echo(f"MAP ({fit.intervals} natural-frequency interval(s) searched, {map_seconds:.1f} s): "
                   + ", ".join(f"{n} = {v:.5g}" for n, v in zip(model.names, fit.theta, strict=True)))
    else:
        click.echo(f"MAP not found: every least-squares search ({fit.intervals}) ended where the model has no "
                   "value at some row; its table shows the prior's median. The sampler goes on from the prior.",
                   err=True)

    before = model.evaluations
    with ProgressBar(quiet, settings.max_steps, "sampling", "steps") as advance:
        chains = sample(post, start, seed=seed, targets=Targets(settings.autocorr_times, settings.min_ess),
                        max_steps=settings.max_steps, check_every=settings.check_every, progress=advance)
    points = model.evaluations - before
    theta, replicated = report.predictive(post, chains, settings.predictive_draws, seed)
    params = report.summary(model, fit, chains)
    timing = {"map": map_seconds, "sampling": chains.seconds, "total": time.perf_counter() - began,
              "rate": chains.evaluations / chains.seconds}
    run = {"seed": seed, "walkers": settings.walkers, "steps": chains.steps, "burn_in": chains.burn,
           "acceptance_fraction": chains.acceptance, "converged": int(chains.converged),
           "length_in_autocorr_times": chains.length_in_tau, "model_points_evaluated": points}
    command = "fsweep calibrate " + " ".join(shlex.quote(a) for a in [str(spec_path), "-o", str(folder)])
    attrs = {"title": f"friction_sweep calibration: {spec.excitation} excitation, {spec.method} model, "
                      f"{obs.size} rows of {obs.path}",
             "Conventions": CONVENTIONS, "history": provenance.history_line(command),
             **provenance.attributes(spec_text=spec.text, spec_path=str(spec_path), excitation=spec.excitation,
                                     method=spec.method, settings=dict(spec.settings)),
             "data_path": obs.path, "emcee_version": provenance.version("emcee"),
             "arviz_version": provenance.version("arviz")}
    idata = report.inference_data(post, chains, replicated, fit.theta, seed=seed, run=run, provenance=attrs)
    md = report.markdown(model, chains, params, fit.table, timing, obs.path)
    figures = (report.predictive_figure(post, theta), report.corner_figure(model, chains, fit))
    try:
        paths = report.write(folder, idata, fit.table, md, figures, overwrite=overwrite)
    except FileExistsError as err:
        fail(str(err))
    except OSError as err:
        fail(f"could not write into {folder}: {err.strerror or err}; no output was changed", EXIT_RUNTIME)
    click.echo(params[["parameter", "unit", "map", "median", "ci95_low", "ci95_high", "identification", "tau",
                       "ess"]].to_string(index=False, float_format=lambda x: f"{x:.5g}"))
    fitted = report.residual_stats(fit.table, True)
    if fitted:
        click.echo(f"MAP phase residuals (fitted rows): RMS {fitted['rms_deg']:.2f} deg, max {fitted['max_deg']:.2f} "
                   "deg")
    held = report.residual_stats(fit.table, False)
    if held:
        click.echo(f"held-out rows: RMS {held['rms_deg']:.2f} deg, max {held['max_deg']:.2f} deg")
    click.echo(f"sampler: {chains.steps} steps, largest tau {np.max(chains.tau):.1f} (kept run "
               f"{chains.length_in_tau:.0f} tau), smallest ESS {np.min(chains.ess):.0f}, walkers' R-hat "
               f"{np.max(chains.rhat):.3f}, acceptance {chains.acceptance:.2f}, "
               f"{'converged' if chains.converged else 'NOT converged (max_steps reached)'}; "
               f"{timing['rate']:.0f} model evaluations/s; whole run {timing['total']:.1f} s")
    click.echo("wrote " + ", ".join(str(p) for p in paths))
