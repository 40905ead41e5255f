"""fsweep: the command line. A thin layer: parse, call the library, report; exit 2 on bad input."""

from __future__ import annotations

import importlib
import json
import os
import shlex
import signal
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click
import numpy as np

import friction_sweep
from friction_sweep import codes, posix
from friction_sweep.batch.executors import DEFAULT_EXECUTOR, EXECUTORS, MAX_JOBS
from friction_sweep.errors import FsweepError
from friction_sweep.exits import (
    EXIT_FINDINGS,
    EXIT_INTERRUPTED,
    EXIT_RUNTIME,
    EXIT_TERMINATED,
    fail,
)
from friction_sweep.packaged import InputPath
from friction_sweep.printable import escape
from friction_sweep.progress import ProgressBar, Step
from friction_sweep.quicklook import KINDS, WIDE_RANGE, YSCALES
from friction_sweep.spec import SpecError, load_spec


class _Terminated(KeyboardInterrupt):
    """SIGTERM, turned into an interruption so that every clean-up that Ctrl-C runs also runs."""


def _on_sigterm(signum, frame):
    raise _Terminated


def _load(path: Path):
    try:
        return load_spec(path)
    except SpecError as err:
        fail(f"invalid spec\n{err}")


#: a cube's default extension: CF section 2.1 asks netCDF files to end in .nc (the CF checker and other
#: netCDF tools go by it); fsweep reads and writes .h5 alike, the same HDF5/netCDF4 file
CUBE_SUFFIX = ".nc"


def _output_path(spec_path: Path, spec, override: str | None) -> Path:
    """Where the result goes; exit 2 for a name that cannot be a file (checked as written: a Path
    would drop the trailing slash of `out/`)."""
    from friction_sweep.storage.outputs import refuse_name, refuse_special_output

    reason = refuse_name(str(spec_path), "spec")  # its path is recorded in the cube, and may name it
    if reason is not None:
        fail(reason)
    raw = override if override is not None else spec.output
    if raw is None:
        raw = str(Path("results") / f"{spec_path.stem}{CUBE_SUFFIX}")
    reason = refuse_special_output(raw)
    if reason is not None:
        fail(f"output: {reason}")
    return Path(raw)


class _Group(click.Group):
    #: commands whose module loads heavy libraries (pandas): imported only when asked for
    lazy = {"validate-data": ("friction_sweep.validation", "validate_data"),
            "calibrate": ("friction_sweep.calibration.command", "calibrate")}

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        """As click's, but a usage error is one line like every other refusal (exit 2)."""
        unsupported = posix.missing()
        if unsupported:
            fail(unsupported, EXIT_RUNTIME)
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        try:
            rv = super().main(args, prog_name, complete_var, False, **extra)
        except click.exceptions.Abort:
            click.echo("fsweep: interrupted", err=True)
            sys.exit(EXIT_INTERRUPTED)
        except click.exceptions.NoArgsIsHelpError as err:  # `fsweep` alone: the help, as click prints it
            err.show()
            sys.exit(err.exit_code)
        except click.ClickException as err:
            where = f"fsweep {err.ctx.info_name}" if getattr(err, "ctx", None) and err.ctx.parent else "fsweep"
            click.echo(f"fsweep: error: {' '.join(err.format_message().split())} (see {where} --help)", err=True)
            sys.exit(err.exit_code)
        sys.exit(rv if isinstance(rv, int) else 0)

    def list_commands(self, ctx):
        return sorted([*super().list_commands(ctx), *self.lazy])

    def get_command(self, ctx, name):
        if name in self.lazy:
            module, attr = self.lazy[name]
            return getattr(importlib.import_module(module), attr)
        return super().get_command(ctx, name)

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt as err:
            # nothing half-written: results are only ever renamed into place when complete (a run
            # says more: it catches this itself, to name the finished tiles it keeps)
            how = "terminated" if isinstance(err, _Terminated) else "interrupted"
            click.echo(f"fsweep: {how}; no result was written or changed", err=True)
            sys.exit(EXIT_TERMINATED if isinstance(err, _Terminated) else EXIT_INTERRUPTED)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(friction_sweep.__version__, prog_name="fsweep")
def main():
    """Sweep a 1-DoF oscillator with Coulomb friction over frequency ratio r and force ratio beta."""


#: the options `run` and `validate` share: validate takes them all, so that it gives every refusal run would
_RUN_OPTIONS = [
    click.option("-o", "--output", type=click.Path(), help="Result file (overrides the spec's `output`)."),
    click.option("--overwrite", is_flag=True, help="Replace an existing result (atomically)."),
    click.option("-j", "--jobs", type=click.IntRange(min=1, max=MAX_JOBS), default=1, show_default=True,
                 help="Workers."),
    click.option("--yes", is_flag=True, help="Run even a huge grid (one estimated to take over 30 min or 4 GiB)."),
    click.option("--executor", type=click.Choice(EXECUTORS), default=DEFAULT_EXECUTOR, show_default=True,
                 help="Where tiles run (dask: a LocalCluster of -j workers, or --scheduler)."),
    click.option("--scheduler", metavar="ADDRESS", help="A Dask scheduler to run on (implies --executor dask)."),
    click.option("--resume", is_flag=True, help="Continue an interrupted run from its finished tiles."),
]


def _run_options(command):
    for option in reversed(_RUN_OPTIONS):
        command = option(command)
    return command


@main.command()
@click.argument("spec", type=InputPath())
@_run_options
def validate(spec: Path, output: str | None, overwrite: bool, jobs: int, yes: bool, executor: str,
             scheduler: str | None, resume: bool):
    """Check SPEC, and where its result would go, without computing or writing anything: every refusal
    `fsweep run` with the same options would give, and the settings `accuracy:` chooses."""
    plan = _plan(spec, output, overwrite, resume, jobs, executor, scheduler, yes, for_run=False)
    s, out = plan.spec, plan.out
    if _is_structure(s):
        n_s, n_f = s.friction_scale.size, s.frequency.size
        click.echo(f"{escape(spec)}: ok: structure of {len(s.structure.dofs)} masses and "
                   f"{len(s.structure.contacts)} contacts, excitation {s.scene.excitation}, method {s.method}, "
                   f"{n_s} friction scales x {n_f} frequencies = {n_s * n_f} points, outputs {', '.join(s.outputs)}, "
                   f"output {escape(out)}")
        for line in s.describe():
            click.echo(f"  {escape(line)}")
        click.echo(f"  settings: {json.dumps(plan.recorded)}")
        click.echo(f"  estimate: {plan.cost.describe()}")
        return
    n_r, n_b = s.frequency_ratio.size, s.force_count
    click.echo(
        f"{escape(spec)}: ok: excitation {s.scene.excitation}, method {s.method}, "
        f"{n_b} force ratios x {n_r} frequency ratios = {n_b * n_r} points, "
        f"outputs {', '.join(s.outputs)}, output {escape(out)}"
    )
    from friction_sweep.catalogue import effect_lines

    for line in effect_lines(s.scene.excitation, s.scene.effects):
        click.echo(f"  effect {line}")
    click.echo(f"  settings: {json.dumps(plan.recorded)}")
    click.echo(f"  estimate: {plan.cost.describe()}")
    if s.physical is not None:
        for line in s.physical.describe(s.scene.excitation):
            click.echo(f"  {line}")


@main.command("settings")
@click.argument("method", required=False)
def settings_(method: str | None):
    """List each method's settings: default, meaningful range (values outside are refused), and why; and
    the effects it models, as a spec writes them."""
    from friction_sweep.catalogue import EFFECTS, METHODS

    if method is not None and method not in METHODS:
        fail(f"unknown method {method!r} (available: {', '.join(METHODS)})")
    for record in [METHODS[method]] if method else METHODS.values():
        click.echo(f"{record.name}:" + ("" if record.settings else " no settings"))
        for key, setting in record.settings.items():
            default = record.defaults[key]
            click.echo(f"  {key:<28} default {default!s:<10} range {setting.describe():<22} {setting.why}")
        for name in record.effects:
            click.echo(f"  effect {name}: {EFFECTS[name].shape()}")


def _methods_table() -> None:
    """What each method can do, from the catalogue: the table of `fsweep info --methods`."""
    from friction_sweep.catalogue import EFFECTS, METHODS

    def cell(names) -> str:
        return ", ".join(names) or "-"

    rows = [("method", "excitations", "effects", "outputs", "accuracy:", "sweep:", "settings")]
    for m in METHODS.values():
        accuracy = f"sets {cell(m.accuracy_knobs)}" if m.accuracy_knobs else "-"
        rows.append((m.name, cell(m.excitations), cell(m.effects), cell(m.outputs), accuracy,
                     "yes" if m.sweep else "-", str(len(m.settings))))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    for row in rows:
        click.echo("  ".join(text.ljust(w) for text, w in zip(row, widths, strict=True)).rstrip())
    click.echo("")
    for m in METHODS.values():
        click.echo(f"{m.name}: {m.summary}")
    click.echo("")
    for name, effect in EFFECTS.items():
        click.echo(f"effect {name}: {effect.meaning}; {effect.shape()}")
        for excitation, places in effect.places.items():
            for place, where in places.items():
                click.echo(f"  {excitation}, to: {place}: {where}")
    click.echo("settings of a method, their defaults and ranges: fsweep settings METHOD")


@main.command()
@click.argument("spec", type=InputPath())
@_run_options
@click.option("-q", "--quiet", is_flag=True, help="No progress bar.")
@click.option("-v", "--verbose", count=True, help="Log what happens (-vv: more).")
def run(spec: Path, output: str | None, overwrite: bool, jobs: int, quiet: bool, yes: bool, executor: str,
        scheduler: str | None, resume: bool, verbose: int):
    """Run the sweep described by SPEC and write the result cube (HDF5/netCDF4).

    SPEC is a spec file, or an example shipped with the package: package:examples/demo.yaml."""
    # imported here so that `fsweep validate` and `--help` stay fast (no numba kernels loaded)
    from friction_sweep.batch import checkpoint

    _logging(verbose)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _on_sigterm)
    plan = _plan(spec, output, overwrite, resume, jobs, executor, scheduler, yes, for_run=True)
    if not quiet:
        click.echo(f"estimate: {plan.cost.describe()}", err=True)
    try:
        with checkpoint.Lock(plan.out):
            _run_locked(plan.spec, spec, plan.out, overwrite, resume, jobs, quiet, plan.executor, scheduler,
                        plan.store, plan.settings, plan.extra, plan.cost.compile)
    except (checkpoint.Busy, checkpoint.Mismatch) as err:
        fail(str(err))


@dataclass(frozen=True)
class _Plan:
    """What `run` and `validate` decide before anything is computed."""

    spec: Any
    out: Path
    executor: str
    settings: dict
    extra: dict
    recorded: dict  # the method settings the cube will record (what `accuracy:` chose included)
    cost: Any
    store: Any


def _is_structure(s) -> bool:
    """Whether a validated spec is a structure spec (spec.structure: several masses and contacts)."""
    from friction_sweep.spec.structure import StructureSpec

    return isinstance(s, StructureSpec)


def _flow(s):
    """The pipeline of a validated spec: batch.pipeline for a 1-DoF spec, batch.structure_sweep for a
    structure (the same functions, by name)."""
    from friction_sweep.batch import pipeline, structure_sweep

    return structure_sweep if _is_structure(s) else pipeline


def _plan(spec: Path, output: str | None, overwrite: bool, resume: bool, jobs: int, executor: str,
          scheduler: str | None, yes: bool, *, for_run: bool) -> _Plan:
    """Every refusal `run` gives, in run's order. For run (`for_run`), what runs killed while writing this
    output left is removed first, whatever this one does next, and the checkpoint's state is left to run,
    which judges it holding the output's lock (a live run's checkpoint is that run's, not an interrupted
    one); `validate` writes nothing and reads the checkpoint's state as it is."""
    from friction_sweep.batch import checkpoint
    from friction_sweep.batch import estimate as cost_model

    if scheduler is not None:  # even "": refused below as no scheduler address, not ignored
        executor = "dask"
    s = _load(spec)
    flow = _flow(s)
    out = _output_path(spec, s, output)
    if resume and overwrite:
        fail("give --resume (finish an interrupted run) or --overwrite (compute afresh), not both")
    _refuse_destroying_spec(out, spec)
    _refuse_replacing_calibration(s, out)
    if for_run:
        from friction_sweep.storage import atomic

        atomic.remove_stale(out)
    if out.exists() and not overwrite and not resume:
        fail(f"{out} exists; pass --overwrite to replace it")
    if executor == "dask":
        _check_dask(scheduler)
    settings, extra = _accuracy_settings(s, spec, quiet=False)
    cost = cost_model.estimate(s, settings, jobs=jobs, executor=executor, scheduler=scheduler)
    if (cost.seconds > cost_model.HUGE_SECONDS or cost.bytes > cost_model.HUGE_BYTES) and not yes:
        fail(f"{spec}: grid: {cost.points} points with method {s.method} would take {cost.describe()}; "
              f"pass --yes to run it")
    _check_writable(out)
    store = checkpoint.Checkpoint(out, flow.checkpoint_key(s, settings, extra), flow.tile_grids(s))
    reason = None if for_run else _checkpoint_refusal(store, out, resume)
    if reason is not None:
        fail(reason)
    return _Plan(s, out, executor, settings, extra, flow.recorded_settings(s, settings), cost, store)


def _checkpoint_refusal(store, out: Path, resume: bool) -> str | None:
    """Why the output's checkpoint state forbids this run (None: it does not); reads, never changes it. An
    empty checkpoint (a run that failed before finishing a tile) forbids nothing: run removes it; a folder
    holding anything fsweep did not write forbids the run, which would otherwise use or remove it."""
    from friction_sweep.batch.checkpoint import Mismatch

    try:
        return _checkpoint_state(store, out, resume)
    except Mismatch as err:  # a .partial that is not a checkpoint folder
        return str(err)


def _checkpoint_state(store, out: Path, resume: bool) -> str | None:
    strangers = store.refuse_strangers()  # a folder holding anything not fsweep's is neither used nor removed
    if strangers is not None:
        return strangers
    if not store.exists() or store.empty():
        if resume and out.exists():
            return (f"{out} is complete: there is nothing to resume (to compute it again, pass --overwrite "
                    f"instead of --resume)")
        return None
    if not resume:
        if not store.belongs():
            return store.foreign()
        return (f"an interrupted run left {store.finished()} finished tiles in {store.dir}: pass --resume to "
                f"continue it, or clear them with: {store.clear_command}")
    return None


def _accuracy_settings(s, spec: Path, quiet: bool) -> tuple[dict, dict]:
    """The run's settings and the attributes that record what `accuracy:` chose (exit 2 if nothing can)."""
    from friction_sweep import api

    try:
        settings, extra = api.accuracy_settings(s)
    except FsweepError as err:
        fail(str(err))
    if extra and not quiet:
        row = json.loads(extra["accuracy_choice"])
        chosen = {k: settings[k] for k in row["settings"] if k in settings}
        click.echo(f"accuracy {s.accuracy:g}: {s.method} with {chosen} (benchmark worst error "
                   f"{row['worst_error']:.1e}, {row['seconds_per_point'] * 1e3:.3g} ms per point)", err=True)
    return settings, extra


def _refuse_destroying_spec(out: Path, spec: Path) -> None:
    """Exit 2 where the run would replace the spec (as its output) or remove it (as its lock)."""
    for own in (out, out.parent / f".{out.name}.lock"):  # the run replaces the one, removes the other
        try:
            if own.exists() and os.path.samefile(own, spec):
                fail(f"output: {own} is the spec {spec} itself; a run would destroy it")
        except OSError:
            pass


def _refuse_replacing_calibration(s, out: Path) -> None:
    """Exit 2 where the run would replace the calibration its `accuracy:` reads (an input, like the spec)."""
    if s.accuracy is None:
        return
    from friction_sweep.bench.workprecision import calibration_path
    from friction_sweep.storage.outputs import refuse_replacing

    reason = refuse_replacing([out], True, inputs=[calibration_path()])
    if reason is not None:
        fail(reason)


def _check_dask(scheduler: str | None) -> None:
    """Fail in a second, not after a 30 s connection timeout, where Dask cannot run the tiles."""
    from friction_sweep.batch.executors import DaskUnavailable, check_dask

    try:
        check_dask(scheduler)
    except DaskUnavailable as err:
        fail(str(err))


def _run_locked(s, spec, out, overwrite, resume, jobs, quiet, executor, scheduler, store, settings,
                extra_attrs, compile_seconds):
    """The part of `run` that holds the output's lock: checkpoint, compute, write, clean up. Kernels that
    numba's cache does not hold (the estimate's `compile_seconds`) are compiled first, on a line of their
    own, unless a remote Dask cluster's workers compute (they compile for themselves)."""
    from friction_sweep.batch import checkpoint
    from friction_sweep.batch.estimate import COMPILING
    from friction_sweep.storage import cube

    flow = _flow(s)
    reason = _checkpoint_refusal(store, out, resume)  # first: it refuses a folder that is not provably fsweep's
    if reason is not None:
        fail(reason)
    if store.empty():
        store.remove()  # a run that failed before finishing a tile: nothing to keep, nothing to block
    try:
        done, dropped = store.start(resume)
    except checkpoint.SaveFailed as err:
        fail(str(err), EXIT_RUNTIME)
    for name, why in dropped:
        click.echo(f"fsweep: warning: {store.dir / name} {why}; its tile is computed again", err=True)
    total = s.frequency.size * s.friction_scale.size if _is_structure(s) else s.frequency_ratio.size * s.force_count
    start = time.perf_counter()
    try:
        if compile_seconds > 0 and scheduler is None:
            with Step(quiet, COMPILING, compile_seconds):
                flow.compile_kernels(s, settings)
        with ProgressBar(quiet, total) as advance:
            arrays = flow.compute(s, settings, jobs=jobs, executor=executor, scheduler=scheduler, done=done,
                                      on_done=store.save, on_tile=advance)
    except _Terminated:
        _stopped(store, "terminated", EXIT_TERMINATED)
    except KeyboardInterrupt:
        _stopped(store, "interrupted", EXIT_INTERRUPTED)
    except checkpoint.SaveFailed as err:
        fail(str(err), EXIT_RUNTIME)
    except Exception as err:  # a lost scheduler, a bug: one line, and the finished tiles stay usable
        _stopped(store, f"the run failed: {type(err).__name__}: {' '.join(str(err).split())[:300]}", EXIT_RUNTIME)
    elapsed = time.perf_counter() - start

    command = "fsweep run " + " ".join(shlex.quote(a) for a in [str(spec), "-o", str(out)])
    parts = flow.cube(s, arrays, settings, command, extra_attrs)
    if done:  # tiles read back from disk: a tampered or damaged one must not reach the result
        from friction_sweep.storage import audit

        problems = audit.audit(cube.as_dataset(parts))
        if problems:
            fail(f"the finished tiles in {store.dir} hold values no run writes ({problems[0]}); nothing was "
                  f"written: clear them with {store.clear_command} and run again", EXIT_RUNTIME)
    try:
        cube.write_atomic(parts, out, overwrite=overwrite or resume)
    except FileExistsError:
        fail(f"{out} appeared while the sweep ran; nothing was replaced (pass --overwrite)")
    except OSError as err:
        kept = f"; its {store.finished()} finished tiles are kept in {store.dir}: rerun with --resume" \
            if store.finished() else ""
        fail(f"could not write {out}: {err.strerror or err}; nothing was written{kept}", EXIT_RUNTIME)

    store.remove()
    click.echo(f"wrote {escape(out)}")
    if _is_structure(s):
        n_s, n_f = s.friction_scale.size, s.frequency.size
        click.echo(f"  structure of {len(s.structure.dofs)} masses and {len(s.structure.contacts)} contacts, "
                   f"{s.scene.excitation} excitation, method {s.method}: {n_s} friction scales x {n_f} frequencies "
                   f"= {n_s * n_f} points in {elapsed:.2f} s")
        _echo_contact_regimes({name: (dims, values) for name, (dims, values, _) in parts.data_vars.items()},
                              parts.coords["contact"][1].tolist())
        return
    r = s.frequency_ratio
    click.echo(
        f"  {s.scene.excitation} excitation, method {s.method}: {s.force_count} force ratios x "
        f"{r.size} frequency ratios = {s.force_count * r.size} points in {elapsed:.2f} s"
    )
    _echo_regimes({name: values for name, (_, values, _) in parts.data_vars.items()})


def _stopped(store, why: str, code: int):
    """End a run that stopped early: keep finished tiles for --resume, and say so; else leave nothing."""
    n = store.finished()
    if n:
        fail(f"{why}; no result was written; {n} finished tiles are kept in {store.dir}: rerun with --resume "
              f"to continue", code)
    store.remove()
    fail(f"{why}; nothing was written", code)


def _logging(verbose: int) -> None:
    import logging

    level = logging.WARNING if verbose == 0 else logging.INFO if verbose == 1 else logging.DEBUG
    logging.basicConfig(level=level, format="fsweep: %(levelname)s: %(message)s", stream=sys.stderr)
    logging.getLogger("friction_sweep").setLevel(level)


def _check_writable(out: Path) -> None:
    """Fail before computing, not after, if the result could not be written there."""
    import tempfile

    from friction_sweep.storage import atomic

    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        # named as atomic's temporaries: one a kill -9 leaves here is removed by the next write
        with tempfile.NamedTemporaryFile(dir=out.parent, prefix=atomic.temporary_prefix(out), suffix=".tmp"):
            pass
    except OSError as err:
        fail(f"cannot write the output {out}: {err.strerror or err}")


def _echo_regimes(arrays) -> None:
    """Regime counts; where static friction gave points two steady states, how many, and the regimes
    from the moving start. arrays: the cube's variables by name."""
    if "regime" in arrays:
        click.echo("  regimes: " + _regime_summary(arrays["regime"]))
    if "steady_states" in arrays:
        _echo_steady_states(arrays["steady_states"])
    if "regime_moving" in arrays:
        click.echo("  regimes from a moving start: " + _regime_summary(arrays["regime_moving"]))


def _echo_steady_states(n) -> None:
    click.echo(f"  two steady states (from rest and from a moving start): {int((n >= 2).sum())} of {n.size} "
               "points (a lower bound)")


def _echo_contact_regimes(arrays, contacts) -> None:
    """A structure cube's regime counts, one line per contact; where static friction gave it two starts, how
    many points hold two states and each contact's regimes from the moving start. arrays: name -> (dims,
    values); contacts: the contact names."""
    from friction_sweep.storage.schema import MOVING_SUFFIX

    for name, what in (("regime", "regimes"), ("regime" + MOVING_SUFFIX, "regimes from a moving start")):
        if name not in arrays:
            continue
        dims, values = arrays[name]
        axis = list(dims).index("contact")
        for j, contact in enumerate(contacts):
            click.echo(f"  {what} at contact {escape(contact)}: " + _regime_summary(np.take(values, j, axis=axis)))
        if name == "regime" and "steady_states" in arrays:
            _echo_steady_states(arrays["steady_states"][1])


def _regime_summary(values) -> str:
    return ", ".join(f"{name} {n}" for name, n in codes.counts(values).items())


@main.command()
@click.argument("result", type=click.Path(path_type=Path), required=False)
@click.option("--methods", "show_methods", is_flag=True, help="Instead: what each method can do (no RESULT).")
def info(result: Path | None, show_methods: bool):
    """Describe a result cube: dims, method, provenance, regime counts; exit 2 if it holds values
    no run writes (outside a variable's valid range, or codes outside its flags). With --methods,
    tabulate the methods instead."""
    if show_methods:
        if result is not None:
            fail("give either RESULT or --methods, not both")
        _methods_table()
        return
    if result is None:
        fail("give a RESULT to describe, or --methods")
    ds = _open_result(result, every_problem=True)
    a = {str(k): escape(v) for k, v in ds.attrs.items()}  # a cube's text is data: nothing a terminal acts on
    if _structure_cube(ds):
        _info_structure(result, ds, a)
        return
    click.echo(escape(result))
    click.echo("  dims: " + ", ".join(f"{escape(k)} {v}" for k, v in ds.sizes.items()))
    for name in ("frequency_ratio", "force_ratio", "frequency", "friction_force"):
        if name in ds.coords and ds[name].size:
            v = ds[name].values
            units = escape(ds[name].attrs.get("units", "1"))
            click.echo(f"  {name}: {v.min():g} .. {v.max():g}" + (f" {units}" if units != "1" else ""))
    click.echo(f"  excitation: {a.get('excitation')}, method: {a.get('method')}")
    if a.get("effects"):
        click.echo(f"  effects: {a['effects']}")
    _echo_physical(ds.attrs)
    click.echo(f"  variables: {', '.join(map(escape, ds.data_vars))}")
    click.echo(f"  history: {a.get('history')}")
    versions = ", ".join(
        f"{k[: -len('_version')]} {v}" for k, v in a.items() if k.endswith("_version")
    )
    click.echo(f"  versions: {versions}")
    click.echo(f"  spec: {a.get('spec_path')}")
    _echo_regimes({name: ds[name].values for name in ds.data_vars})
    for name in ("transmissibility", "peak_transmissibility"):
        if name in ds:
            v = ds[name].values
            finite = np.isfinite(v)
            if finite.any():
                click.echo(f"  {name}: {v[finite].min():.6g} .. {v[finite].max():.6g} "
                           f"({finite.sum()} finite of {v.size})")


def _structure_cube(ds) -> bool:
    from friction_sweep.storage.schema import is_structure

    return is_structure(ds.attrs)


def _info_structure(result: Path, ds, a: dict) -> None:
    """`fsweep info` of a structure cube: its plane, the structure it solved, its variables, the regimes
    per contact. `a`: its attributes, escaped."""
    from friction_sweep.storage import attributes

    click.echo(escape(result))
    click.echo("  dims: " + ", ".join(f"{escape(k)} {v}" for k, v in ds.sizes.items()))
    for name in ("friction_scale", "frequency"):
        v = ds[name].values
        click.echo(f"  {name}: {v.min():g} .. {v.max():g}{_units_note(ds[name])}")
    click.echo(f"  excitation: {a.get('excitation')}, method: {a.get('method')}")
    _echo_natural_frequencies(ds)
    try:
        st = attributes.read_json(ds.attrs, "structure")
    except attributes.BadAttribute as err:  # open_cube refuses such a cube; a Dataset from elsewhere not
        st = None
        click.echo(f"  structure: unreadable ({escape(err)})")
    if isinstance(st, dict):
        masses = st.get("masses")
        if isinstance(masses, dict):
            click.echo("  masses: " + ", ".join(f"{escape(k)} {escape(v)}" for k, v in masses.items()))
        for form in ("matrices", "modes"):  # a reduced model: where it came from, its dofs
            source = st.get(form)
            if isinstance(source, dict):
                where = f" from {escape(source.get('file'))} (sha256 {escape(source.get('sha256'))})" \
                    if form == "matrices" else ""
                click.echo(f"  reduced model ({form}){where}, dofs: {', '.join(map(escape, st.get('dofs') or ()))}")
        for key in ("springs", "dampers"):
            if st.get(key):
                click.echo(f"  {key}: " + ", ".join(escape(" ".join(map(str, e))) for e in st[key]))
        for c in st.get("contacts") or []:
            if isinstance(c, dict):
                kind = "rigid" if c.get("stiffness") is None else f"Jenkins, stiffness {c.get('stiffness')}"
                ends = " and ".join(map(str, c.get("between") or ()))
                click.echo(f"  contact {escape(c.get('name'))}: between {escape(ends)}, friction "
                           f"{escape(c.get('friction'))}, {escape(kind)}, static friction ratio "
                           f"{escape(c.get('static_friction_ratio'))}")
        forcing = st.get("forcing")
        if isinstance(forcing, dict) and forcing:
            click.echo("  forcing: " + ", ".join(f"{escape(k)} {escape(v)}" for k, v in forcing.items()))
        if "base_amplitude" in st:
            click.echo(f"  base amplitude: {escape(st['base_amplitude'])}")
    click.echo(f"  variables: {', '.join(map(escape, ds.data_vars))}")
    click.echo(f"  history: {a.get('history')}")
    click.echo("  versions: " + ", ".join(f"{k[: -len('_version')]} {v}" for k, v in a.items()
                                          if k.endswith("_version")))
    click.echo(f"  spec: {a.get('spec_path')}")
    _echo_contact_regimes({name: (ds[name].dims, ds[name].values) for name in ds.data_vars},
                          ds["contact"].values.tolist())
    if "history_frequency" in ds.coords:  # outputs: time_history
        where = ds["history_frequency"].values.tolist()
        periods = (ds["history_orbit_period"].values.tolist() if "history_orbit_period" in ds
                   else [float("nan")] * len(where))
        points = zip(where, ds["history_friction_scale"].values.tolist(), periods, strict=True)
        click.echo("  time histories (frequency, friction_scale: orbit periods): " + ", ".join(
            f"{w:g}, {s:g}: {k:g}" for w, s, k in points))
    for name in ("amplitude", "peak_amplitude"):
        if name in ds:
            click.echo(f"  {name}:{_units_note(ds[name]) or ' dimensionless'}")
            for dof in ds["dof"].values.tolist():
                v = ds[name].sel(dof=dof).values
                finite = np.isfinite(v)
                if finite.any():
                    click.echo(f"  {name} of {escape(dof)}: {v[finite].min():.6g} .. {v[finite].max():.6g} "
                               f"({finite.sum()} finite of {v.size})")


def _units_note(da) -> str:
    """A coordinate's or variable's units as info shows them: " [units] (comment)", "" where it has none."""
    units = str(da.attrs.get("units", "1")).strip()
    comment = str(da.attrs.get("comment", "")).strip()
    text = f" [{escape(units)}]" if units not in ("", "1") else ""
    return text + (f" ({escape(comment)})" if comment else "")


def _echo_natural_frequencies(ds) -> None:
    """The linear natural angular frequencies of a structure cube's structure, every contact stuck (rigid
    contacts as constraints, Jenkins contacts as their springs) and every contact free (no friction)."""
    from friction_sweep.structures import recorded

    try:
        found = recorded.frequencies(recorded.assembled(ds))
    except recorded.UnreadableStructure as err:
        click.echo(f"  natural frequencies: unknown ({escape(err)})")
        return
    for contacts, values in found.items():
        click.echo(f"  natural frequencies, every contact {contacts}: "
                   + (", ".join(f"{w:.6g}" for w in values) or "none (every mass held by a rigid contact)"))


def _echo_physical(attrs) -> None:
    """The physical meaning of (r, beta) that a cube of a spec with `system:` recorded."""
    from friction_sweep.storage import physical

    text = attrs.get(physical.ATTRIBUTE)
    if text is None:
        return
    try:
        mapping = physical.from_attribute(str(text))
    except ValueError as err:
        click.echo(f"  physical system: unreadable ({escape(err)})")
        return
    for line in mapping.describe(str(attrs.get("excitation"))):
        click.echo(f"  {escape(line)}")


@main.command()
@click.argument("result", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the findings as JSON.")
def check(result: Path, as_json: bool):
    """Audit a result cube with whole-plane consistency rules (exit 1 when any rule fails)."""
    import json

    from friction_sweep import consistency

    ds = _open_result(result, every_problem=True)  # rules on values no run writes would say nothing true
    if _structure_cube(ds):  # the rules that carry over to several masses and contacts
        from friction_sweep import consistency_structure

        rules = consistency_structure.check
    else:
        rules = consistency.check
    try:
        findings = rules(ds)
    except consistency.CubeError as err:
        fail(f"{escape(result)} is not a friction_sweep result cube: {escape(err)}")
    if as_json:
        click.echo(json.dumps([f.to_dict() for f in findings], indent=1))
    else:
        for f in findings:
            click.echo(_finding_line(f))
        n = {s: sum(f.status == s for f in findings) for s in ("failed", "ok", "partial", "skipped", "info")}
        verdict = "FAILED" if n["failed"] else "ok"
        click.echo(f"{escape(result)}: {verdict}: " + ", ".join(f"{v} {k}" for k, v in n.items() if v))
    sys.exit(EXIT_FINDINGS if consistency.failed(findings) else 0)


@main.command()
@click.argument("result", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(), help="PNG to write (default: RESULT with suffix .png, beside it).")
@click.option("--kind", type=click.Choice(KINDS), help="What to draw (default: map for a plane with regimes; "
              "curves otherwise, or with --sel; orbit with --sel history_point=K).")
@click.option("--sel", "selections", multiple=True, metavar="NAME=VALUE",
              help="Choose what is drawn, nearest value (repeatable): force_ratio=0.3 for curves and phase; "
                   "history_point=K, frequency_ratio=R, force_ratio=B for orbit; or a physical coordinate on those "
                   "dims. A structure cube: friction_scale=S, dof=NAME (curves, phase), contact=NAME.")
@click.option("--yscale", type=click.Choice(YSCALES), default="auto", show_default=True,
              help="The curves' y axis: log, linear, or auto (log where the values span more than "
                   f"{WIDE_RANGE:g} times their median, e.g. a frictionless peak beside damped curves).")
@click.option("--overwrite", is_flag=True, help="Replace an existing PNG (atomically).")
def plot(result: Path, output: str | None, kind: str | None, selections: tuple[str, ...], yscale: str,
         overwrite: bool):
    """Draw a quick look at a result cube as PNG: the regime map, transmissibility or phase curves, or
    a stored orbit; of a structure cube, a regime map per contact, or each mass's amplitude or phase with a
    regime strip per contact."""
    from friction_sweep.storage.outputs import missing_figures_extra, refuse_replacing, refuse_special_output, write_all

    problem = missing_figures_extra()  # first: a missing extra costs nothing, not even reading the cube
    if problem:
        fail(problem)
    from friction_sweep import quicklook

    out = Path(output) if output is not None else quicklook.default_output(result)
    reason = refuse_special_output(output if output is not None else out)  # as written: keeps a trailing /
    if reason is not None:
        fail(f"output: {reason}")
    if out.suffix.lower() != ".png":
        fail(f"output: {out} does not end in .png; fsweep plot writes PNG")
    reason = refuse_replacing([out], overwrite, inputs=[result])
    if reason is not None:
        fail(reason)
    ds = _open_result(result)
    if _structure_cube(ds):  # a panel per mass, a regime strip or map per contact
        from friction_sweep import quicklook_structure

        draw = quicklook_structure.draw
    else:
        draw = quicklook.draw
    try:
        fig = draw(ds, kind, selections, yscale)
    except quicklook.PlotError as err:
        fail(f"{escape(result)}: {escape(err)}")
    try:
        write_all([(out, lambda tmp: quicklook.save(fig, tmp))], overwrite=overwrite)
    except FileExistsError as err:  # appeared while it drew
        fail(str(err))
    except OSError as err:
        fail(f"could not write {out}: {err.strerror or err}; nothing was written", EXIT_RUNTIME)
    click.echo(f"wrote {escape(out)}")


def _bench_estimate(quick: bool) -> str:
    """The bench's time: its measured CPU time with the kernels cached (bench.workprecision), plus the
    compile of each kernel family numba's cache does not hold, as `fsweep run`'s estimate counts it."""
    from friction_sweep.batch import estimate, kernel_cache
    from friction_sweep.bench import workprecision as wp

    cold = {module for module, name in wp.KERNELS if not kernel_cache.warm(module, name)}
    compiling = sum(estimate.COMPILE_SECONDS[module] for module in cold)
    seconds = wp.CACHED_SECONDS["quick" if quick else "full"] + compiling
    text = f"about {estimate.duration(seconds)} of CPU time on one core"
    if compiling:
        text += (f", {estimate.duration(compiling)} of it compiling the simulation kernels (first run on this "
                 "machine; cached afterwards)")
    return text


def _open_result(path: Path, every_problem: bool = False):
    """The cube at `path`, read and audited (friction_sweep.storage.cube.open_cube), or exit 2 with the
    reason: one line, or with `every_problem` one line for each value problem the audit found."""
    from friction_sweep.storage import cube

    try:
        return cube.open_cube(path)
    except cube.UnsoundCube as err:
        if every_problem:
            for p in err.problems[:-1]:
                click.echo(f"fsweep: error: {escape(path)}: {p}", err=True)
            fail(f"{escape(path)}: {err.problems[-1]}")
        fail(str(err))
    except FsweepError as err:
        fail(str(err))


def _finding_line(f) -> str:
    head = f"{f.rule:<12}" if len(f.rule) < 12 else f"{f.rule} "
    if f.status == "skipped":
        return f"{head}skipped ({f.note})"
    if f.status == "info":
        return f"{head}{'info':<9}{f.note} ({f.checked} checked)"
    if f.status == "ok":
        return f"{head}{'ok':<9}{f.checked} checked"
    if f.status == "partial":  # no violation, but not every point judged in full: the note says which and why
        return f"{head}{'partial':<9}{f.checked} checked; {f.note}"
    more_note = f" [{f.note}]" if f.note else ""
    # an example's place: (r, beta) in a 1-DoF cube; (frequency, friction_scale, the mass or contact) in a
    # structure cube
    shown = " ".join("(" + ", ".join(f"{k}={v!r}" for k, v in e.items() if k not in ("found", "expected"))
                     + f": {_shown(e['found'])}, expected {_shown(e['expected'])})" for e in f.examples)
    more = " ..." if f.violations > len(f.examples) else ""
    return f"{head}{'FAILED':<9}{f.violations} of {f.checked}: {shown}{more}{more_note}"


def _shown(v) -> str:
    return f"{v:.10g}" if isinstance(v, float) else str(v)


_DESIGN_OPTIONS = [
    click.option("-o", "--output", type=click.Path(), help="Also write the Dataset (netCDF4/HDF5) here."),
    click.option("--overwrite", is_flag=True, help="Replace an existing file at --output (atomically)."),
    click.option("--variable", type=click.Choice(["transmissibility", "peak_transmissibility"]),
                 default="transmissibility", show_default=True,
                 help="The response whose peak is taken (first harmonic, or max|x| over the orbit)."),
]


def _design_options(command):
    for option in reversed(_DESIGN_OPTIONS):
        command = option(command)
    return command


@main.command()
@click.argument("spec", type=click.Path(path_type=Path))
@_design_options
def peak(spec: Path, output: str | None, overwrite: bool, variable: str):
    """The resonance peak of SPEC's scene for each force ratio of its grid: the largest response over
    frequency, refined on the exact solver to 1e-10 in r (fs.peak). One line per force ratio. A structure
    spec: one mass's (settings: {peak_dof: NAME}; the forced mass by default) for each friction_scale, with
    each contact's regime there."""
    from friction_sweep import api

    ds = _design(lambda: api.peak(str(spec), variable=variable), spec, output, overwrite)
    level = _level(ds)
    for j, beta in enumerate(ds[level].values):
        click.echo(f"{level} {beta:.10g}: {_peak_line(ds, j)}")


@main.command()
@click.argument("spec", type=click.Path(path_type=Path))
@_design_options
@click.option("--plot", type=click.Path(), help="Also draw the performance curve (PNG), in the spec's physical "
              "units where it has a system: the peak against friction, the optimum, Den Hartog's prediction.")
def optimize(spec: Path, output: str | None, overwrite: bool, variable: str, plot: str | None):
    """The force ratio that minimises the resonance peak, to 1e-8, searched from SPEC's force-ratio grid
    (fs.optimize); -o writes the performance curve (the peak at every force ratio) with it. A structure
    spec: the friction_scale that minimises its mass's peak (as fsweep peak)."""
    from friction_sweep import api

    if plot is not None:  # every refusal before the computing
        from friction_sweep.storage.outputs import missing_figures_extra, refuse_replacing, refuse_special_output

        special = refuse_special_output(plot)
        reason = ((f"plot: {special}" if special else None) or missing_figures_extra()
                  or refuse_replacing([plot], overwrite, [spec, *([output] if output else [])]))
        if reason is not None:
            fail(reason)
    ds = _design(lambda: api.optimize(str(spec), variable=variable), spec, output, overwrite)
    level, frequency, regime = _level(ds), _frequency_name(ds), _regime_words(ds.optimum_regime)
    click.echo(f"optimum ({ds.attrs['optimum_kind']}): {level} {float(ds[f'optimum_{level}']):.10g}, "
               f"peak {float(ds.optimum_peak):.10g} at {frequency} = {float(ds[f'optimum_{frequency}']):.12g} "
               f"({regime})")
    if plot is not None:
        from friction_sweep.design import performance_figure

        try:
            performance_figure.save(ds, plot)
        except OSError as err:
            fail(f"plot: {plot}: {err.strerror or err}", EXIT_RUNTIME)
        click.echo(f"wrote {plot}")


@main.command()
@click.argument("spec", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(), help="Also write the Dataset (netCDF4/HDF5) here.")
@click.option("--overwrite", is_flag=True, help="Replace an existing file at --output (atomically).")
def backbone(spec: Path, output: str | None, overwrite: bool):
    """The backbone of SPEC's scene (force, or base): at every phase resonance (90-degree lag, bisected on
    the exact solver to 1e-10 in r) of each force ratio, the amplitude and the equivalent damping ratio
    zeta_eq = E_dissipated / (4 pi E_potential) per period (fs.backbone). One line per phase resonance. A
    structure spec (force excitation): along its mass's phase resonance (as fsweep peak)."""
    from friction_sweep import api

    ds = _design(lambda: api.backbone(str(spec)), spec, output, overwrite)
    level, frequency = _level(ds), _frequency_name(ds)
    short = "r" if frequency == "frequency_ratio" else "w"
    for j, beta in enumerate(ds[level].values):
        found = np.nonzero(np.isfinite(ds[f"backbone_{frequency}"].values[j]))[0]
        if not found.size:
            click.echo(f"{level} {beta:.10g}: no phase resonance")
        for k in found:
            one = ds.isel({level: j, "crossing": k})
            click.echo(f"{level} {beta:.10g}: {short} = {float(one[f'backbone_{frequency}']):.10g}, amplitude "
                       f"{float(one.backbone_amplitude):.10g}, zeta_eq {float(one.backbone_damping_ratio):.8g} "
                       f"({_regime_words(one.backbone_regime)})")


def _level(ds) -> str:
    """The friction axis of a design Dataset: force_ratio (1-DoF) or friction_scale (a structure)."""
    return "friction_scale" if "friction_scale" in ds.dims else "force_ratio"


def _frequency_name(ds) -> str:
    return "frequency" if "friction_scale" in ds.dims else "frequency_ratio"


def _regime_words(codes_at) -> str:
    """A regime code in words; a structure's, one per contact: `name: regime, ...`."""
    def word(code: float) -> str:
        return codes.Regime(int(code)).name.lower() if np.isfinite(code) else "none"

    if "contact" not in codes_at.dims:
        return word(float(codes_at))
    return ", ".join(f"{c}: {word(float(v))}" for c, v in zip(codes_at.contact.values, codes_at.values, strict=True))


def _peak_line(ds, j: int) -> str:
    value = float(ds.resonance_peak[j])
    if np.isnan(value):
        return "no peak"
    frequency = _frequency_name(ds)
    short = "r" if frequency == "frequency_ratio" else "w"
    regime = _regime_words(ds.resonance_regime[j])
    edge = " (grid edge)" if bool(ds.resonance_at_edge[j]) else ""
    return f"peak {value:.10g} at {short} = {float(ds[f'resonance_{frequency}'][j]):.12g} ({regime}){edge}"


def _design(compute, spec: Path, output: str | None, overwrite: bool):
    """Run `compute` (an fs.peak / fs.optimize / fs.backbone call), refusing as every command does; write the Dataset to
    `output` (booleans as 0/1 bytes) whole or not at all."""
    from friction_sweep.storage.outputs import refuse_replacing, refuse_special_output

    if output is not None:
        reason = refuse_special_output(output)
        if reason is not None:
            fail(f"output: {reason}")
        reason = refuse_replacing([output], overwrite, [spec])
        if reason is not None:
            fail(reason)
    try:
        ds = compute()
    except SpecError as err:
        fail(f"invalid spec\n{err}")
    except FsweepError as err:
        fail(str(err))
    if output is not None:
        from friction_sweep.storage.cube import write_atomic

        written = ds.copy()
        for name, var in ds.data_vars.items():
            if var.dtype == bool:
                written[name] = var.astype(np.int8)
        try:
            write_atomic(written, Path(output), overwrite=overwrite)
        except FileExistsError:
            fail(f"output: {output} appeared meanwhile; not replaced (--overwrite replaces it)")
        except OSError as err:
            fail(f"output: {output}: {err.strerror or err}", EXIT_RUNTIME)
    return ds


@main.command()
@click.option("--quick", is_flag=True, help="One point per region and fewer settings (it prints its estimate first).")
@click.option("-o", "--output", type=click.Path(),
              default=Path(f"results/bench/workprecision{CUBE_SUFFIX}"), show_default=True, help="Dataset to write.")
@click.option("--calibrate", is_flag=True, help="Also write the calibration that `accuracy:` in specs uses.")
@click.option("--calibration", type=click.Path(path_type=Path), default=None,
              help="Where --calibrate writes (default: the user's, ~/.local/share/friction_sweep/calibration.json, "
                   "which `accuracy:` then reads in preference to the packaged one).")
@click.option("--overwrite", is_flag=True, help="Replace existing outputs (the dataset, its .png and .md, the "
              "calibration), all together.")
def bench(quick: bool, output: str, calibrate: bool, calibration: Path | None, overwrite: bool):
    """Measure what accuracy costs in time: error and time per point of every method and setting."""
    from friction_sweep.bench import workprecision as wp
    from friction_sweep.storage.outputs import missing_figures_extra, refuse_replacing, refuse_special_output

    if calibrate and quick:
        fail("--calibrate needs the full benchmark, not --quick")
    # every refusal before the benchmark's seconds to minutes of computing
    reason = refuse_special_output(output)
    problem = ((f"output: {reason}" if reason else None) or wp.refuse_outputs(output, calibrate, calibration)
               or refuse_replacing(wp.output_paths(output, calibrate, calibration), overwrite)
               or missing_figures_extra())
    if problem:
        fail(problem)
    _check_writable(Path(output))
    click.echo(f"estimate: {_bench_estimate(quick)}", err=True)
    ds = wp.run(quick=quick, log=lambda line: click.echo(line, err=True))
    table = wp.markdown(ds)
    try:
        paths = wp.write(ds, output, calibrate, calibration, overwrite=overwrite)  # all or nothing
    except FileExistsError as err:
        fail(str(err))
    except OSError as err:
        fail(f"could not write the benchmark's results ({output}): {err.strerror or err}; "
              "no output was changed", EXIT_RUNTIME)
    click.echo(table)
    click.echo("wrote " + ", ".join(str(p) for p in paths))

