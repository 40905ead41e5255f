"""Finished tiles survive an interrupted run; one run at a time per output.

Beside the output `out.h5` a run keeps `.out.h5.partial/`: `manifest.json` (a fingerprint of
everything that decides the numbers: spec content, method, settings, tile layout, versions) and one
`tile-NNNNN.npz` per finished tile, each written to a temporary name and renamed, so a kill -9 leaves
only whole tiles. `fsweep run --resume` reloads them and computes the rest; the folder is removed once
the cube is written. `.out.h5.lock` is held with flock for the whole run: the kernel releases it
when the process ends, however it ends; a run that ends normally also removes the file.
"""

from __future__ import annotations

import errno
import fcntl
import hashlib
import json
import os
import shlex
import shutil
import stat
from pathlib import Path

import numpy as np

from friction_sweep.storage import atomic


class Busy(RuntimeError):
    """Another run holds the output's lock, or the lock cannot be taken at all."""


class Mismatch(RuntimeError):
    """The checkpoint on disk belongs to a different sweep, or cannot be trusted."""


class SaveFailed(RuntimeError):
    """A finished tile or the manifest could not be written (a full disk, an I/O error)."""


def fingerprint(**parts) -> str:
    """Stable hash of JSON-able parts (arrays by their bytes)."""
    h = hashlib.sha256()
    for key in sorted(parts):
        value = parts[key]
        h.update(key.encode())
        if isinstance(value, np.ndarray):
            h.update(np.ascontiguousarray(value, dtype=np.float64).tobytes())
        else:
            h.update(json.dumps(value, sort_keys=True, default=str).encode())
    return h.hexdigest()


class Lock:
    """flock on `.out.lock` for the whole run; the file is removed when the run ends."""

    def __init__(self, out: Path):
        self.path = out.parent / f".{out.name}.lock"
        self.out = out
        self.fd: int | None = None

    def __enter__(self):
        while True:
            try:
                # never through a link (a link to another file would have it truncated), never
                # waiting on a FIFO
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK, 0o644)
                kind = os.fstat(fd).st_mode
                if not stat.S_ISREG(kind):
                    os.close(fd)
                    raise IsADirectoryError(errno.EINVAL, "not a regular file")
            except OSError as err:
                if self.path.is_symlink():
                    what = "is a symbolic link, which fsweep never writes through"
                elif self.path.is_dir():
                    what = "is a folder, not a lock file"
                elif os.path.lexists(self.path) and not self.path.is_file():
                    what = "is not a regular file"
                else:
                    what = f"cannot be opened ({err.strerror})"
                raise Busy(f"{self.path}, where fsweep locks {self.out}, {what}: remove it if no run is "
                           f"writing {self.out}") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise Busy(f"another fsweep run is writing {self.out} (it holds {self.path}); wait for it "
                           f"to finish") from None
            # the run before us may have removed the file between our open and our lock: then we
            # hold a lock on a file nobody else can see, so take the one now at the path
            try:
                same = os.stat(self.path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        self.fd = fd
        try:  # who holds it, for a person looking; the flock is what counts, so a full disk is no matter
            os.ftruncate(fd, 0)
            os.write(fd, str(os.getpid()).encode())
        except OSError:
            pass
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            self.path.unlink(missing_ok=True)  # while still held: no one can take the old file
            fcntl.flock(self.fd, fcntl.LOCK_UN)
            os.close(self.fd)
            self.fd = None
        return False


class Checkpoint:
    def __init__(self, out: Path, key: str, n_tiles: int):
        self.dir = out.parent / f".{out.name}.partial"
        self.key = key
        self.n_tiles = n_tiles

    @property
    def clear_command(self) -> str:
        return f"rm -r {shlex.quote(str(self.dir))}"

    def exists(self) -> bool:
        return os.path.lexists(self.dir)

    def finished(self) -> int:
        return len(list(self.dir.glob("tile-*.npz"))) if self.dir.is_dir() else 0

    def belongs(self) -> bool:
        """Whether the checkpoint on disk is this sweep's (Mismatch if it cannot be read)."""
        if self.dir.is_symlink() or not self.dir.is_dir():
            raise Mismatch(f"{self.dir} is not a folder, so it holds no checkpoint; remove it with: "
                           f"{self.clear_command}")
        try:
            manifest = json.loads((self.dir / "manifest.json").read_text(encoding="utf-8"))
            return manifest["key"] == self.key
        except FileNotFoundError:
            return False  # killed before its manifest was written: it holds nothing of any sweep
        except (OSError, ValueError, KeyError, TypeError) as err:
            raise Mismatch(f"{self.dir}/manifest.json cannot be read ({_why(err)}), so its tiles cannot be "
                           f"trusted; clear them with: {self.clear_command}") from None

    def foreign(self) -> str:
        """What to say of a checkpoint that `belongs()` to another sweep."""
        return (f"{self.dir} holds {self.finished()} finished tiles of a different sweep (spec, method, settings "
                f"or version changed); clear them with: {self.clear_command}")

    def start(self, resume: bool) -> tuple[dict[int, dict], list[str]]:
        """Open for writing; with resume, return the finished tiles, and the names of damaged tiles
        that were dropped (to be computed again)."""
        done: dict[int, dict] = {}
        dropped: list[str] = []
        if self.exists():
            if not self.belongs():
                raise Mismatch(self.foreign())
            if resume:
                for path in sorted(self.dir.glob("tile-*.npz")):
                    try:
                        index = int(path.stem.split("-")[1])
                        with np.load(path) as data:
                            tile = {k: data[k] for k in data.files}
                        if not 0 <= index < self.n_tiles or not tile:
                            raise ValueError("not a tile of this sweep")
                    except Exception:  # any damage (truncated, not a zip, bad index): compute it again
                        _discard(path)
                        dropped.append(path.name)
                        continue
                    done[index] = tile
        try:
            self.dir.mkdir(parents=True, exist_ok=True)
            manifest = {"key": self.key, "tiles": self.n_tiles}
            atomic.write_bytes(self.dir / "manifest.json", json.dumps(manifest).encode())
        except OSError as err:
            raise SaveFailed(f"could not start a checkpoint in {self.dir}: {_why(err)}") from None
        return done, dropped

    def save(self, index: int, tile: dict) -> None:
        try:
            atomic.write(self.dir / f"tile-{index:05d}.npz", lambda fh: np.savez(fh, **tile))
        except OSError as err:
            raise SaveFailed(f"could not save a finished tile in {self.dir}: {_why(err)}; its "
                             f"{self.finished()} finished tiles are kept: rerun with --resume once it can be "
                             f"written") from None

    def remove(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)


def _discard(path: Path) -> None:
    """Remove a damaged entry of the checkpoint, whatever it is (a file, a link, a folder)."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def _why(err: BaseException) -> str:
    return (getattr(err, "strerror", None) or " ".join(str(err).split()) or type(err).__name__).rstrip(".")
