"""The one way fsweep writes a file: whole or not at all, readable as the user's umask says.

The content goes to a temporary file beside the target, is flushed to disk (fsync), and is renamed
into place; the folder is then fsynced so the rename itself survives a crash. A failed or
interrupted write (a full disk, Ctrl-C, an exception in the writer) removes the temporary file and
leaves any earlier file at the target untouched.

Writers get a Python file object, never a path: a library that writes by path (h5py) crashes the
process on a full disk, while a file object turns it into an ordinary OSError.

A kill -9 leaves the temporary file behind. Its name carries the writer's process id,
`.NAME.PID-XXXXXXXX.tmp`, so the next write of the same target removes the ones whose writer is gone
(`remove_stale`) and never one of a live writer (a reused id only keeps a stale file longer).
"""

from __future__ import annotations

import errno
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

Writer = Callable[[BinaryIO], object]


def umask() -> int:
    """The process's umask, read without changing it where Linux shows it (thread-safe)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    old = os.umask(0o022)  # elsewhere: the classic read-by-setting, restored at once
    os.umask(old)
    return old


def write(path: str | os.PathLike[str], writer: Writer, *, overwrite: bool = True, sweep: bool = True) -> Path:
    """Write `path` through `writer(file)`. Without `overwrite`, an existing `path` is never replaced
    (FileExistsError, checked at the final link, so a file that appeared meanwhile is kept). `sweep`:
    first remove the temporaries killed writers left of `path` (a caller writing many files into one
    folder sweeps it once instead, remove_stale_in)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if sweep:
        remove_stale(path)
    fd, name = tempfile.mkstemp(prefix=temporary_prefix(path), suffix=".tmp", dir=path.parent)
    tmp = Path(name)
    try:
        # mkstemp creates 0600; a result is for colleagues too: the mode a new file would get
        os.fchmod(fd, 0o666 & ~umask())
        with os.fdopen(fd, "wb") as fh:
            writer(fh)
            fh.flush()
            os.fsync(fh.fileno())
        if overwrite:
            os.replace(tmp, path)
        else:
            publish_new(tmp, path)
        fsync_folder(path.parent)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


#: what os.link raises where a file system has no hard links (FAT, exFAT, some CIFS and sshfs mounts)
_NO_HARD_LINKS = frozenset({errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK, errno.EXDEV, errno.ENOSYS})


def publish_new(tmp: Path, target: Path) -> None:
    """Move the finished file `tmp` to `target`, never replacing a file there (FileExistsError, `tmp` kept
    for the caller to remove). A hard link does it in one step; where the file system has none, the name
    is claimed by an exclusive create (O_EXCL fails on any file there, even one that appeared a moment
    ago) and `tmp` renamed over that empty claim, which is ours alone (a reader may see it empty first)."""
    try:
        os.link(tmp, target)
    except OSError as err:
        if err.errno not in _NO_HARD_LINKS:
            raise
    else:
        tmp.unlink()
        return
    fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    claim = os.fstat(fd)
    os.close(fd)
    try:
        os.replace(tmp, target)
    except BaseException:
        try:  # our empty claim, unless something replaced it meanwhile
            here = os.stat(target, follow_symlinks=False)
            if (here.st_dev, here.st_ino) == (claim.st_dev, claim.st_ino):
                os.unlink(target)
        except OSError:
            pass
        raise


def temporary_prefix(path: Path, tag: str = "") -> str:
    """The start of the name of a temporary file that becomes `path`: hidden, the target's name, the
    writer's process id (what `remove_stale` reads). `tag` names a staged copy (storage.outputs)."""
    return f".{path.name}.{os.getpid()}-{tag}"


#: the temporaries of a target NAME: `.NAME.PID-XXXXXXXX.tmp` (mkstemp's 8 random characters) or a
#: staged copy `.NAME.PID-staged.tmp`, and the temporary of a staged copy, `..NAME.PID-staged.tmp.PID-XXXXXXXX.tmp`
_TEMPORARY = r"\.\.?{name}\.(\d+)-(?:staged|[a-z0-9_]{{8}})(?:\.tmp\.\d+-[a-z0-9_]{{8}})?\.tmp"


def temporary_pattern(name: str) -> re.Pattern[str]:
    """The names of the temporaries of targets whose names match the regular expression `name`."""
    return re.compile(_TEMPORARY.format(name=f"(?:{name})"))


def remove_stale(path: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files of `path` left by writers that are gone (killed mid-write); returns
    them. Only regular files of fsweep's own naming whose process id names no running process."""
    path = Path(path)
    return _remove_stale(path.parent, re.escape(path.name))


def remove_stale_in(folder: str | os.PathLike[str]) -> list[Path]:
    """remove_stale for every target in `folder` (a checkpoint's tiles: one listing, not one per tile)."""
    return _remove_stale(Path(folder), r"[^/]+?")


def _remove_stale(folder: Path, name: str) -> list[Path]:
    pattern = temporary_pattern(name)
    removed: list[Path] = []
    try:
        names = os.listdir(folder)
    except OSError:
        return removed
    for name in names:
        match = pattern.fullmatch(name)
        if match is None or _alive(int(match.group(1))):
            continue
        stale = folder / name
        try:
            if os.path.isfile(stale) and not os.path.islink(stale):
                stale.unlink()
                removed.append(stale)
        except OSError:
            pass  # another run removed it first, or the folder is read-only: nothing to do
    return removed


def _alive(pid: int) -> bool:
    """Whether a process with this id runs (another user's counts: it may be writing)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True
    return True


def write_bytes(path: str | os.PathLike[str], data: bytes | memoryview, *, overwrite: bool = True) -> Path:
    return write(path, lambda fh: fh.write(data), overwrite=overwrite)


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    return write_bytes(path, text.encode("utf-8"))


def save_figure(fig, path: str | os.PathLike[str], **savefig_kwargs) -> Path:
    """Save a matplotlib figure as PNG atomically, and close it."""
    import matplotlib.pyplot as plt

    try:
        return write(path, lambda fh: fig.savefig(fh, format="png", **savefig_kwargs))
    finally:
        plt.close(fig)


def fsync_folder(folder: Path) -> None:
    """Make renames in `folder` durable. Best effort: the file is in place by then, and not every
    file system lets a folder be synced, so a failure here must not report the write as failed."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
