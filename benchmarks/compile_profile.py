"""Where a cold compile's time goes: `fsweep run SPEC` with an empty numba cache, in a fresh process, with
numba's compile events (numba.core.event: `numba:compile`, `numba:run_pass`) recorded in CPU seconds.

    python benchmarks/compile_profile.py [SPEC] [--top N]      (default SPEC: configs/demo.yaml)

Writes results/bench/compile_profile.md, and prints it: the process's CPU (user, sys) and minor page
faults before the run and over it; each kernel's own compile CPU (exclusive of the kernels it calls,
which numba compiles while it types the caller) and inclusive; numba's passes summed over the kernels
(exclusive likewise); and the LLVM stages inside native lowering (lowering to LLVM IR, function and
module optimisation, machine code), timed by wrapping numba's CodeLibrary methods for this process only.

Why these three views: numba compiles every kernel called from compiled code as a library of its own and
links the libraries of its callees into it, optimising and emitting the callees' code again at every level
of the call tree; inlining (kernels/jit.py: jit_inline) trades that for typing and lowering the callee again
at every call site. The per-kernel view shows which subtree costs, the pass and LLVM views which side of
that trade it is on.
"""

from __future__ import annotations

import argparse
import collections
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from numba.core import event

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "bench"


class _Recorder(event.Listener):
    """numba event listener: CPU seconds per kernel and per pass, each exclusive of nested compiles."""

    def __init__(self):
        self.kernels: list[list] = []  # stack of [name, start, nested seconds]
        self.passes: list[list] = []
        self.exclusive: collections.Counter = collections.Counter()
        self.inclusive: collections.Counter = collections.Counter()
        self.by_pass: collections.Counter = collections.Counter()

    def on_start(self, ev):
        if ev.kind == "numba:compile":
            func = ev.data["dispatcher"].py_func
            self.kernels.append([f"{func.__module__.removeprefix('friction_sweep.kernels.')}.{func.__qualname__}",
                                 time.process_time(), 0.0])
        else:
            self.passes.append([ev.data["name"].split(" ")[0], time.process_time(), 0.0])

    def on_end(self, ev):
        stack = self.kernels if ev.kind == "numba:compile" else self.passes
        name, start, nested = stack.pop()
        spent = time.process_time() - start
        if ev.kind == "numba:compile":
            self.exclusive[name] += spent - nested
            self.inclusive[name] += spent
        else:
            self.by_pass[name] += spent - nested
        if stack:
            stack[-1][2] += spent


def _time_llvm() -> collections.Counter:
    """Wrap numba's code-generation steps to sum their CPU seconds (exclusive of one another)."""
    from numba.core import codegen, lowering

    spent: collections.Counter = collections.Counter()
    nested: list[float] = []

    def wrap(cls, method, label):
        original = getattr(cls, method)

        def timed(*args, **kwargs):
            start = time.process_time()
            nested.append(0.0)
            try:
                return original(*args, **kwargs)
            finally:
                total = time.process_time() - start
                spent[label] += total - nested.pop()
                if nested:
                    nested[-1] += total

        setattr(cls, method, timed)

    wrap(lowering.Lower, "lower", "numba IR to LLVM IR")
    wrap(codegen.CPUCodeLibrary, "add_ir_module", "LLVM IR parsed and verified")
    wrap(codegen.CPUCodeLibrary, "_optimize_functions", "LLVM function passes")
    wrap(codegen.CPUCodeLibrary, "_optimize_final_module", "LLVM module passes (callees linked in)")
    wrap(codegen.CPUCodeLibrary, "_finalize_final_module", "machine code (MCJIT)")
    wrap(codegen.CPUCodeLibrary, "serialize_using_object_code", "cache: object code serialised")
    return spent


def child(spec: str, top: int) -> list[str]:
    recorder = _Recorder()
    event.register("numba:compile", recorder)
    event.register("numba:run_pass", recorder)
    llvm = _time_llvm()
    from friction_sweep.cli import main

    before = resource.getrusage(resource.RUSAGE_SELF)
    try:
        main(["run", spec, "-o", os.path.join(os.environ["NUMBA_CACHE_DIR"], "cube.nc"), "--overwrite", "-q",
              "-j", "1"])
    except SystemExit as done:
        if done.code:
            raise
    after = resource.getrusage(resource.RUSAGE_SELF)
    compiled = sum(recorder.exclusive.values())
    rows = [f"# Cold compile of `{spec}` (numba cache empty, one process, -j 1)", "",
            "| | user s | sys s | minor page faults |", "|---|---|---|---|",
            f"| imports (before the run) | {before.ru_utime:.2f} | {before.ru_stime:.2f} | {before.ru_minflt} |",
            f"| the run | {after.ru_utime - before.ru_utime:.2f} | {after.ru_stime - before.ru_stime:.2f} | "
            f"{after.ru_minflt - before.ru_minflt} |", "",
            f"numba's compile events: {compiled:.2f} CPU s over {len(recorder.exclusive)} kernels; "
            f"load average {os.getloadavg()[0]:.1f} at the end.", "",
            "| kernel | own CPU s | with what it compiled s |", "|---|---|---|"]
    rows += [f"| {name} | {s:.2f} | {recorder.inclusive[name]:.2f} |"
             for name, s in recorder.exclusive.most_common(top)]
    rows += ["", "| numba pass (all kernels) | CPU s |", "|---|---|"]
    rows += [f"| {name} | {s:.2f} |" for name, s in recorder.by_pass.most_common(top) if s >= 0.01]
    rows += ["", "| inside native_lowering | CPU s |", "|---|---|"]
    rows += [f"| {name} | {s:.2f} |" for name, s in llvm.most_common()]
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("spec", nargs="?", default=str(ROOT / "configs" / "demo.yaml"))
    parser.add_argument("--top", type=int, default=25, help="rows per table (default 25)")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    report = OUT / "compile_profile.md"
    if args.child:
        report.write_text("\n".join(child(args.spec, args.top)) + "\n")
        return
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as cache:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_DISABLE_JIT"}
        subprocess.run([sys.executable, __file__, args.spec, "--top", str(args.top), "--child"], check=True,
                       capture_output=True, env={**env, "NUMBA_CACHE_DIR": cache})
    print(report.read_text(), end="")


if __name__ == "__main__":
    main()
