"""The progress bar of long commands: rich on stderr (done of total, rate, time left, a note); silent when
quiet or not a terminal, and rich then not even imported (20 ms of a one-point run)."""

from __future__ import annotations

import sys
import time


class ProgressBar:
    """`with ProgressBar(quiet, total, "sweep", "points") as advance: advance(n, note)`."""

    def __init__(self, quiet: bool, total: int, label: str = "sweep", unit: str = "points"):
        self.enabled = not quiet and sys.stderr.isatty()
        self.total = total
        self.label = label
        self.unit = unit

    def __enter__(self):
        if not self.enabled:
            return lambda n, note="": None
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        self.bar = Progress(
            TextColumn(self.label), BarColumn(), MofNCompleteColumn(), TextColumn(self.unit),
            TextColumn("{task.fields[rate]}"), TimeRemainingColumn(), TextColumn("{task.fields[note]}"),
            console=Console(stderr=True), transient=True,
        )
        self.bar.start()
        task = self.bar.add_task(self.label, total=self.total, rate="", note="")
        start = time.perf_counter()
        done = [0]

        def advance(n: int, note: str = "") -> None:
            done[0] += n
            rate = done[0] / max(time.perf_counter() - start, 1e-9)
            self.bar.update(task, advance=n, rate=f"{rate:,.0f} {self.unit}/s", note=note)

        return advance

    def __exit__(self, *exc):
        if self.enabled:
            self.bar.stop()
        return False


class Step:
    """`with Step(quiet, label, seconds):` a step whose progress cannot be counted (numba compiling the
    kernels): the label on stderr, on a line of its own, and on a terminal below it a live line (a spinner,
    the time spent of the `seconds` expected), gone when the step ends; nothing when quiet."""

    def __init__(self, quiet: bool, label: str, seconds: float):
        self.quiet = quiet
        self.live = not quiet and sys.stderr.isatty()
        self.label = label
        self.seconds = seconds

    def __enter__(self):
        if self.quiet:
            return self
        print(self.label, file=sys.stderr, flush=True)
        if self.live:
            from rich.console import Console
            from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

            self.bar = Progress(SpinnerColumn(), TimeElapsedColumn(), TextColumn(f"of about {self.seconds:.0f} s"),
                                console=Console(stderr=True), transient=True)
            self.bar.start()
            self.bar.add_task(self.label, total=None)
        return self

    def __exit__(self, *exc):
        if self.live:
            self.bar.stop()
        return False
