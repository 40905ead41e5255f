"""Where and how a command writes its outputs: checked before it computes, written all or nothing.

The atomic writers (friction_sweep.storage.atomic, cube.write_atomic) rename a finished temporary
file over the target. That is right for a regular file, but renaming over a symlink replaces the
link (not the file it points to), and a directory, FIFO or device in the target's place fails only
after the computation. So a command asks `refuse_special_output` (and, if it draws,
`missing_figures_extra`) first and stops with the reason, and `refuse_replacing` for files already
there (replaced only with --overwrite, and never an input of the same command); then computes
everything; then writes its files with `write_all`, so that a full disk leaves the previous outputs
as they were.
"""

from __future__ import annotations

import importlib
import os
import stat
from collections.abc import Callable, Iterable
from pathlib import Path

from friction_sweep.printable import name_problem
from friction_sweep.storage import atomic

#: what a non-regular file is, by its st_mode type, in refusals
_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a named pipe (FIFO)"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
)

#: the extra that brings matplotlib, as the refusal names it
FIGURES_EXTRA = "pip install 'friction_sweep[figures]'"

#: bytes a file name may have (Linux's NAME_MAX), less what fsweep's hidden files beside an output add
#: to its name (the longest: the temporary of a staged copy, `..NAME.PID-staged.tmp.PID-XXXXXXXX.tmp`)
NAME_MAX = 255
HIDDEN_NAME_EXTRA = 40
MAX_NAME_BYTES = NAME_MAX - HIDDEN_NAME_EXTRA

#: what a command line means by an output named "-": standard output, which fsweep never writes (a cube, a
#: figure, a folder of results is a file renamed into place when complete, never a stream)
STDOUT = "-"


def refuse_stdout(path: str | os.PathLike[str]) -> str | None:
    """Why `path` cannot be an output (file or folder) when it is "-" (None otherwise)."""
    if os.fspath(path) != STDOUT:
        return None
    return ("'-' would be standard output, which fsweep does not write (a result is a file, renamed into place "
            "when complete): name a file, ./- for one called '-'")

def refuse_name(text: str, what: str = "name") -> str | None:
    """Why `text` cannot be a file name fsweep records and writes (None if it can): name_problem, said of
    `what` (the spec, the data, the file name). Shared by every command, and by `validate` and `run` for the
    spec's own path, before anything is computed."""
    problem = name_problem(text)
    if problem is None:
        return None
    return f"{what} {ascii(text)} {problem}: rename it"


def refuse_special_output(path: str | os.PathLike[str]) -> str | None:
    """Why `path` must not be written as an output file, or None when it may be; said without a prefix
    (the caller adds "output: ", or the option that named it).

    May be: a path that does not exist yet (its folders are created when written), or an existing
    regular file (replaced atomically). Refused: a symlink (even to a regular file: fsweep never
    replaces links), anything else that exists there (directory, FIFO, socket, device), and a path
    one of whose parents exists as something other than a folder.
    """
    text = os.fspath(path)
    reason = refuse_name(text, "the file name") or refuse_stdout(text)
    if reason is not None:
        return reason
    if text.endswith(os.sep) or not text or os.path.basename(text) in (".", ".."):
        return f"{text!r} names a folder: name the file to write"
    size = len(os.path.basename(text).encode("utf-8"))
    if size > MAX_NAME_BYTES:
        return (f"the file name is {size} bytes long; fsweep takes at most {MAX_NAME_BYTES}, as it "
                f"writes hidden files beside it whose names are longer (a name has at most {NAME_MAX})")
    path = Path(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except NotADirectoryError:  # a parent is a file: said below, naming that parent
        st = None
    except OSError as err:
        return f"cannot check the output {path}: {err.strerror or err}"
    if st is not None:
        if stat.S_ISLNK(st.st_mode):
            return (f"{path} is a symbolic link to {os.readlink(path)}; fsweep never replaces links: "
                    "name the file itself, or remove the link")
        if not stat.S_ISREG(st.st_mode):
            return f"{path} is {file_kind(st.st_mode)}, not a regular file"
        return None
    return _refuse_parent(path)


def _refuse_parent(path: Path) -> str | None:
    """The reason the nearest existing ancestor of `path` cannot hold it (None if it is a folder)."""
    for parent in path.parents:  # as written: relative ones end at ".", which exists
        try:
            st = os.stat(parent)  # followed: a link to a folder is a fine place to write
        except FileNotFoundError:
            if os.path.islink(parent):
                return f"parent {parent} is a broken symbolic link to {os.readlink(parent)}"
            continue  # created when the output is written
        except NotADirectoryError:
            continue  # an ancestor further up is a file: reported when the loop reaches it
        except OSError as err:
            return f"cannot check the folder {parent}: {err.strerror or err}"
        if stat.S_ISDIR(st.st_mode):
            return _refuse_unwritable(parent)
        what = "a file" if stat.S_ISREG(st.st_mode) else file_kind(st.st_mode)
        return f"parent {parent} is {what}, not a folder"
    return None


def _refuse_unwritable(folder: Path) -> str | None:
    """Why nothing can be written in `folder` (checked without writing: `validate` writes nothing)."""
    try:
        if os.statvfs(folder).f_flag & os.ST_RDONLY:
            return f"{folder} is on a read-only file system"
    except OSError:
        pass
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"{folder} is not writable"
    return None


def missing_figures_extra() -> str | None:
    """Why figures cannot be drawn (matplotlib missing or broken), or None when they can.

    Commands that end with a figure ask this before they compute, so that a missing optional
    dependency costs nothing and leaves no partial set of outputs.
    """
    try:
        # both imports, explicitly: pyplot is what draws, and a broken install (a missing backend
        # dependency) fails only there; `import matplotlib` first so that a matplotlib blocked in
        # sys.modules is noticed even when pyplot was imported earlier
        for module in ("matplotlib", "matplotlib.pyplot"):
            importlib.import_module(module)
    except ImportError as err:
        return f"this command draws figures, which need matplotlib ({err}): {FIGURES_EXTRA}"
    return None


def file_kind(mode: int) -> str:
    """What a non-regular file is ("a directory", "a named pipe (FIFO)", ...), for messages."""
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")



def refuse_replacing(targets: Iterable[str | os.PathLike[str]], overwrite: bool,
                     inputs: Iterable[str | os.PathLike[str]] = ()) -> str | None:
    """Why a command must not write `targets` (None if it may), asked before it computes: one of them is
    an input of the same command (never written over, even with --overwrite), or exists already and
    --overwrite was not given. A command's files are published together (write_all), so one refusal
    stops them all."""
    sources = [Path(p) for p in inputs]
    for target in map(Path, targets):
        for source in sources:
            if _same_file(target, source):
                return (f"output: {target} is {source}, an input of this command; fsweep never writes over "
                        "its own input (not even with --overwrite): name another output")
        if os.path.lexists(target) and not overwrite:
            return f"output: {target} exists; pass --overwrite to replace it"
    return None


def _same_file(a: Path, b: Path) -> bool:
    """Whether two paths name one file (hard links included), or would once written (one path)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


class Appeared(FileExistsError):
    """A target that did not exist when the command started exists when its result is published."""


def write_all(writers: Iterable[tuple[str | os.PathLike[str], Callable[[Path], object]]], *,
              overwrite: bool = True) -> list[Path]:
    """Write a command's outputs all or nothing; returns their paths.

    `writers` pairs each target with a function that writes a given path (atomically, through
    friction_sweep.storage.atomic or cube.write_atomic). Each first writes a hidden staged file next
    to its target; only when every one has succeeded are they renamed into place. A failure while
    writing (a full disk, a read-only folder) thus changes none of the targets and leaves no staged
    file: the error is re-raised for the command to report. Renames need no space, so the second
    phase fails only in exotic cases (the folder removed meanwhile), which re-raise likewise.
    Without `overwrite` no existing file is replaced: each staged file is published with
    atomic.publish_new (a hard link, or where there are none an exclusive create then a rename), which
    fails where one appeared meanwhile (Appeared), and the targets already published by this call are
    removed again, so none or all of them appear.
    """
    staged: list[tuple[Path, Path]] = []
    published: list[Path] = []
    try:
        for target, write in writers:
            target = Path(target)
            target.parent.mkdir(parents=True, exist_ok=True)
            atomic.remove_stale(target)
            tmp = target.with_name(atomic.temporary_prefix(target, "staged") + ".tmp")
            staged.append((tmp, target))
            write(tmp)
        for tmp, target in staged:
            if overwrite:
                os.replace(tmp, target)
                continue
            try:
                atomic.publish_new(tmp, target)
            except FileExistsError:
                raise Appeared(f"{target} appeared while the command ran; nothing was replaced "
                               "(pass --overwrite)") from None
            published.append(target)
    except BaseException:
        for target in published:  # ours alone: linked from our staged file just now
            target.unlink(missing_ok=True)
        for tmp, _ in staged:
            if os.path.lexists(tmp):
                os.unlink(tmp)
        raise
    for tmp, _ in staged:
        if os.path.lexists(tmp):
            os.unlink(tmp)
    for folder in {target.parent for _, target in staged}:
        atomic.fsync_folder(folder)
    return [target for _, target in staged]
