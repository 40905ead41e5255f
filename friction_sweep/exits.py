"""How every fsweep command ends when it cannot do its job: one line on stderr and an exit code."""

from __future__ import annotations

import sys
from typing import NoReturn

import click

from friction_sweep.printable import escape

EXIT_BAD_INPUT = 2  # the input (spec, data, output path, arguments) is refused; nothing was done
EXIT_RUNTIME = 1  # the work failed (a full disk, a lost cluster); nothing half-written
EXIT_FINDINGS = 1  # fsweep check: a rule failed
EXIT_INTERRUPTED = 130  # Ctrl-C, as a shell reports it
EXIT_TERMINATED = 143  # 128 + SIGTERM, as a shell reports a process it ended


def fail(message: str, code: int = EXIT_BAD_INPUT) -> NoReturn:
    """`fsweep: error: message` on stderr, and exit with `code`. Each line of the message is escaped
    (friction_sweep.printable): it can quote a file name or a value read from a file, which must not
    reach the terminal as control sequences."""
    message = "\n".join(map(escape, message.split("\n")))
    click.echo(f"fsweep: error: {message}", err=True)
    sys.exit(code)
