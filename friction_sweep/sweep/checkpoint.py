"""Finished tiles survive an interrupted run; one run at a time per output.

Beside the output `out.h5` a run keeps `.out.h5.partial/`: `manifest.json` (a fingerprint of
everything that decides the numbers: spec content, method, settings, tile layout, versions) and one
`tile-NNNNN.npz` per finished tile, each written to a temporary name and renamed, so a kill -9 leaves
only whole tiles. `fsweep run --resume` reloads them and computes the rest; the folder is removed once
the cube is written. `.out.h5.lock` is held with flock for the whole run: the kernel releases it
when the process ends, however it ends.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
from pathlib import Path

import numpy as np


class Busy(RuntimeError):
    """Another run holds the output's lock."""


class Mismatch(RuntimeError):
    """The checkpoint on disk belongs to a different sweep."""


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
    def __init__(self, out: Path):
        self.path = out.parent / f".{out.name}.lock"
        self.fd = None

    def __enter__(self):
        self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(self.fd)
            self.fd = None
            raise Busy(f"another fsweep run is writing {self.path.parent / self.path.name[1:-5]} "
                       f"(it holds {self.path}); wait for it to finish") from None
        os.ftruncate(self.fd, 0)
        os.write(self.fd, str(os.getpid()).encode())
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            fcntl.flock(self.fd, fcntl.LOCK_UN)
            os.close(self.fd)
        return False


class Checkpoint:
    def __init__(self, out: Path, key: str, n_tiles: int):
        self.dir = out.parent / f".{out.name}.partial"
        self.key = key
        self.n_tiles = n_tiles

    def exists(self) -> bool:
        return (self.dir / "manifest.json").exists()

    def finished(self) -> int:
        return len(list(self.dir.glob("tile-*.npz"))) if self.dir.exists() else 0

    def start(self, resume: bool) -> dict[int, dict]:
        """Open for writing; with resume, return the finished tiles (checked against the key)."""
        done: dict[int, dict] = {}
        if self.exists():
            manifest = json.loads((self.dir / "manifest.json").read_text())
            if manifest.get("key") != self.key:
                raise Mismatch(f"{self.dir} holds tiles of a different sweep (spec, method, settings or version "
                               f"changed); delete it to start afresh")
            if resume:
                for path in sorted(self.dir.glob("tile-*.npz")):
                    with np.load(path) as data:
                        done[int(path.stem.split("-")[1])] = {k: data[k] for k in data.files}
        self.dir.mkdir(parents=True, exist_ok=True)
        _atomic_write(self.dir / "manifest.json", json.dumps({"key": self.key, "tiles": self.n_tiles}).encode())
        return done

    def save(self, index: int, tile: dict) -> None:
        path = self.dir / f"tile-{index:05d}.npz"
        tmp = self.dir / f".tile-{index:05d}.npz.tmp"
        with open(tmp, "wb") as fh:
            np.savez(fh, **tile)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)

    def remove(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)


def _atomic_write(path: Path, data: bytes) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)
