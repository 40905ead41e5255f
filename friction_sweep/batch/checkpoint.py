"""Finished tiles survive an interrupted run; one run at a time per output.

Beside the output `out.h5` a run keeps `.out.h5.partial/`: `manifest.json` (a fingerprint of
everything that decides the numbers, batch.pipeline.checkpoint_key, and the variables and dtypes of
the first tile saved) and one `tile-NNNNN.npz` per finished tile, each written to a temporary name and
renamed, so a kill -9 leaves only whole tiles. Each tile carries its proof: the fingerprint, its own
index and its grid values; `fsweep run --resume` reloads the tiles that prove they belong and hold the
manifest's variables in its dtypes, computes the rest again, and removes the folder once the cube is
written.

fsweep removes only a checkpoint folder that is provably its own: every entry a regular file of its own
naming (manifest.json, tile-NNNNN.npz, a temporary `.NAME.PID-XXXXXXXX.tmp` of one of them) or an empty
folder of such a name, and a manifest, if any, that is fsweep's; and even then it removes those entries
one by one, never the folder's tree, so a file that appeared meanwhile stays (`strangers`, `remove`).

`.out.h5.lock` is held with flock for the whole run: the kernel releases it when the process ends,
however it ends; a run that ends normally also removes the file. fsweep writes its process id into
the lock, and so writes only into a lock it created, or one left by an earlier run (empty, or a
number): never into a file of other content, nor one with more than one name (a hard link to some
other file would be written through).
"""

from __future__ import annotations

import errno
import fcntl
import hashlib
import json
import os
import re
import shlex
import stat
from pathlib import Path

import numpy as np

from friction_sweep.printable import escape
from friction_sweep.storage import atomic


class Busy(RuntimeError):
    """Another run holds the output's lock, or the lock cannot be taken at all."""


class Mismatch(RuntimeError):
    """The checkpoint on disk belongs to a different sweep, or cannot be trusted."""


class SaveFailed(RuntimeError):
    """A finished tile or the manifest could not be written (a full disk, an I/O error)."""


def fingerprint(**parts) -> str:
    """Stable hash of JSON-able parts (arrays by their shape and bytes, bytes as they are)."""
    h = hashlib.sha256()
    for key in sorted(parts):
        value = parts[key]
        h.update(key.encode())
        if isinstance(value, np.ndarray):
            h.update(repr(value.shape).encode())
            h.update(np.ascontiguousarray(value, dtype=np.float64).tobytes())
        elif isinstance(value, bytes):
            h.update(hashlib.sha256(value).digest())
        else:
            h.update(json.dumps(value, sort_keys=True, default=str).encode())
    return h.hexdigest()


#: the entries of a tile's .npz that prove where it belongs (not variables): the key, the index, and the
#: tile's grid values, `fsweep_<axis>` for each axis of the grid (these are a 1-DoF grid's; a structure's
#: are fsweep_frequency and fsweep_friction_scale)
PROOF = ("fsweep_key", "fsweep_index", "fsweep_frequency_ratio", "fsweep_force_ratio")
#: the names fsweep gives the entries of a checkpoint folder, and their temporaries (storage.atomic)
_OWN_NAME = re.compile(r"manifest\.json|tile-\d{5}\.npz")
_OWN_TEMPORARY = atomic.temporary_pattern(r"manifest\.json|tile-\d{5}\.npz")
#: a manifest holds a fingerprint, a count and a few variable names: far less than this
_MANIFEST_BYTES = 1 << 20
#: strangers a refusal names before it says how many more there are
_SHOWN = 3
#: a lock fsweep wrote holds at most a process id
_LOCK_BYTES = 20


class Lock:
    """flock on `.out.lock` for the whole run; the file is removed when the run ends."""

    def __init__(self, out: Path):
        self.path = out.parent / f".{out.name}.lock"
        self.out = out
        self.fd: int | None = None

    def __enter__(self):
        while True:
            try:
                # never through a symbolic link (a link to another file would have it truncated),
                # never waiting on a FIFO; created here, or opened as an earlier run left it
                try:
                    fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_NONBLOCK,
                                 0o644)
                    created = True
                except FileExistsError:
                    fd = os.open(self.path, os.O_RDWR | os.O_NOFOLLOW | os.O_NONBLOCK)
                    created = False
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
            foreign = self._foreign(fd, created)  # checked as late as can be, just before the write
            if foreign:
                os.close(fd)  # releases the flock, which changed nothing in the file
                raise Busy(f"{self.path}, where fsweep locks {self.out}, {foreign}, which fsweep never writes "
                           f"into: remove that name (rm {shlex.quote(str(self.path))}) if no run is writing "
                           f"{self.out}")
            # the run before us may have removed the file between our open and our lock: then we
            # hold a lock on a file nobody else can see, so take the one now at the path
            if self._at_path(fd):
                break
            os.close(fd)
        self.fd = fd
        try:  # who holds it, for a person looking; the flock is what counts, so a full disk is no matter
            os.ftruncate(fd, 0)
            os.write(fd, str(os.getpid()).encode())
        except OSError:
            pass
        atomic.remove_stale(self.out)  # temporaries of runs killed while writing this output
        return self

    @staticmethod
    def _foreign(fd: int, created: bool) -> str | None:
        """Why the open file is no lock fsweep may write (None if it is): it has other names (a hard
        link: writing would change that file too), or content no run wrote (fsweep writes a number)."""
        st = os.fstat(fd)
        if st.st_nlink > 1:
            return f"has {st.st_nlink} names (a hard link to another file)"
        if created:
            return None
        head = os.pread(fd, _LOCK_BYTES + 1, 0)
        if len(head) > _LOCK_BYTES or not head.strip().isdigit() and head.strip():
            return "holds data fsweep did not write (a lock holds a process id)"
        return None

    def _at_path(self, fd: int) -> bool:
        """Whether the path still names the open file."""
        try:
            here, held = os.stat(self.path, follow_symlinks=False), os.fstat(fd)
        except FileNotFoundError:
            return False
        return (here.st_dev, here.st_ino) == (held.st_dev, held.st_ino)

    def __exit__(self, *exc):
        if self.fd is not None:
            if self._at_path(self.fd):  # ours alone: while still held, so no one can take the old file
                self.path.unlink(missing_ok=True)
            fcntl.flock(self.fd, fcntl.LOCK_UN)
            os.close(self.fd)
            self.fd = None
        return False


class Checkpoint:
    """The finished tiles of one sweep. `grids[i]` holds the grid values of tile i by name (frequency_ratio,
    force_ratio): a tile must carry them, its index and the sweep's fingerprint `key` to be used again."""

    def __init__(self, out: Path, key: str, grids: list[dict[str, np.ndarray]]):
        self.dir = out.parent / f".{out.name}.partial"
        self.out = out
        self.key = key
        self.grids = grids
        self.n_tiles = len(grids)
        #: the variables (name: dtype) of this sweep's tiles, as the first one saved had them
        self.variables: dict[str, str] | None = None

    @property
    def clear_command(self) -> str:
        return f"rm -r {shlex.quote(str(self.dir))}"

    def exists(self) -> bool:
        return os.path.lexists(self.dir)

    def finished(self) -> int:
        return len(list(self.dir.glob("tile-*.npz"))) if self.dir.is_dir() else 0

    def empty(self) -> bool:
        """A checkpoint folder without a finished tile (a run that failed before finishing one): nothing
        to keep or resume, and nothing that should block the next run."""
        return self.dir.is_dir() and not self.dir.is_symlink() and self.finished() == 0

    def strangers(self) -> list[str]:
        """The entries of the checkpoint folder fsweep did not write (empty: the folder is provably its
        own, or there is none): a name fsweep never gives, a link, a folder that is not empty, anything not
        a regular file. Mismatch if the folder cannot be listed."""
        if not self.dir.is_dir() or self.dir.is_symlink():
            return []
        found: list[str] = []
        try:
            with os.scandir(self.dir) as entries:
                for entry in entries:
                    if not _own_entry(entry):
                        found.append(entry.name)
        except OSError as err:
            raise Mismatch(f"{self.dir} cannot be read ({_why(err)}), so fsweep cannot tell whether it is "
                           f"its checkpoint; remove it with: {self.clear_command}") from None
        return sorted(found)

    def refuse_strangers(self) -> str | None:
        """Why fsweep must neither use nor remove the checkpoint folder (None: it is its own, or absent);
        Mismatch where its manifest.json is not one fsweep wrote."""
        found = self.strangers()
        if not found:
            if os.path.lexists(self.dir / "manifest.json"):
                self._manifest()  # Mismatch, saying why, unless it is fsweep's
            return None
        shown = ", ".join(escape(name) for name in found[:_SHOWN])
        more = f" and {len(found) - _SHOWN} more" if len(found) > _SHOWN else ""
        return (f"{escape(self.dir)}, where fsweep keeps the checkpoint of {escape(self.out)}, holds {shown}{more}, "
                f"which fsweep did not write; it removes only its own files: move yours out, or remove the "
                f"folder with: {self.clear_command}")

    def _manifest(self) -> dict | None:
        """The manifest on disk (None if there is none; Mismatch if it cannot be read)."""
        if self.dir.is_symlink() or not self.dir.is_dir():
            raise Mismatch(f"{self.dir} is not a folder, so it holds no checkpoint; remove it with: "
                           f"{self.clear_command}")
        try:
            with open(self.dir / "manifest.json", "rb") as fh:
                text = fh.read(_MANIFEST_BYTES + 1)
            if len(text) > _MANIFEST_BYTES:
                raise ValueError("larger than any manifest fsweep writes")
            manifest = json.loads(text.decode("utf-8"))
            if not _manifest_shape(manifest):
                raise TypeError("not a manifest")
            return manifest
        except FileNotFoundError:
            return None  # killed before its manifest was written: it holds nothing of any sweep
        except (OSError, ValueError, KeyError, TypeError, RecursionError) as err:
            raise Mismatch(f"{self.dir}/manifest.json cannot be read ({_why(err)}), so its tiles cannot be "
                           f"trusted; clear them with: {self.clear_command}") from None

    def belongs(self) -> bool:
        """Whether the checkpoint on disk is this sweep's (Mismatch if it cannot be read)."""
        manifest = self._manifest()
        return manifest is not None and manifest["key"] == self.key

    def foreign(self) -> str:
        """What to say of a checkpoint that `belongs()` to another sweep."""
        return (f"{self.dir} holds {self.finished()} finished tiles of a different sweep (spec, method, settings, "
                f"calibration, code or version changed); clear them with: {self.clear_command}")

    def start(self, resume: bool) -> tuple[dict[int, dict], list[tuple[str, str]]]:
        """Open for writing; with resume, return the finished tiles that prove they belong, and the
        names of the others, with why, which are removed (to be computed again)."""
        done: dict[int, dict] = {}
        dropped: list[tuple[str, str]] = []
        if self.exists():
            manifest = self._manifest()
            if manifest is None or manifest["key"] != self.key:
                raise Mismatch(self.foreign())
            recorded = manifest.get("variables")
            self.variables = recorded if isinstance(recorded, dict) and recorded else None
            if resume:
                for path in sorted(self.dir.glob("tile-*.npz")):
                    try:
                        index, tile = self._load(path)
                    except Exception as err:  # any damage (truncated, not a zip, foreign): compute it again
                        _discard(path)
                        dropped.append((path.name, str(err) or "damaged"))
                        continue
                    done[index] = tile
        try:
            self.dir.mkdir(parents=True, exist_ok=True)
            atomic.remove_stale_in(self.dir)  # tiles a killed run was writing; saves then need not look
            self._write_manifest()
        except OSError as err:
            raise SaveFailed(f"could not start a checkpoint in {self.dir}: {_why(err)}") from None
        return done, dropped

    def _load(self, path: Path) -> tuple[int, dict]:
        """A finished tile and its index, once it proves it belongs here (ValueError saying why not)."""
        try:
            index = int(path.stem.split("-")[1])
            with np.load(path, allow_pickle=False) as data:
                tile = {k: data[k] for k in data.files}
        except Exception:
            raise ValueError("was damaged") from None
        if not 0 <= index < self.n_tiles:
            raise ValueError("is not a tile of this sweep (its index is outside the grid)")
        proof = {k: tile.pop(k, None) for k in (*PROOF[:2], *(f"fsweep_{name}" for name in self.grids[index]))}
        if any(v is None for v in proof.values()) or str(proof["fsweep_key"]) != self.key:
            raise ValueError("does not carry this sweep's fingerprint")
        if proof["fsweep_index"].shape != () or int(proof["fsweep_index"]) != index:
            raise ValueError(f"carries another tile's index ({proof['fsweep_index']!s:.20})")
        for name, values in self.grids[index].items():
            got = proof[f"fsweep_{name}"]
            if got.dtype != values.dtype or got.shape != values.shape or not np.array_equal(got, values):
                raise ValueError(f"was computed at other {name} values than its place in this grid")
        if self.variables is None:
            raise ValueError("cannot be checked: the manifest records no variables")
        found = {k: v.dtype.str for k, v in tile.items()}
        if found != self.variables:
            missing, extra = sorted(set(self.variables) - set(found)), sorted(set(found) - set(self.variables))
            what = (f"lacks {', '.join(missing)}" if missing else f"holds {', '.join(extra)} too" if extra
                    else "holds variables of other dtypes")
            raise ValueError(f"{what}, unlike the tiles of this sweep")
        return index, tile

    def _write_manifest(self) -> None:
        manifest: dict = {"key": self.key, "tiles": self.n_tiles}
        if self.variables is not None:
            manifest["variables"] = self.variables
        atomic.write_bytes(self.dir / "manifest.json", json.dumps(manifest).encode())

    def save(self, index: int, tile: dict) -> None:
        grid = self.grids[index]
        entries: dict = {**tile, "fsweep_key": np.array(self.key), "fsweep_index": np.array(index),
                         **{f"fsweep_{name}": values for name, values in grid.items()}}
        try:
            if self.variables is None:  # the first tile: what every tile of this sweep holds
                self.variables = {k: np.asarray(v).dtype.str for k, v in tile.items()}
                self._write_manifest()
            atomic.write(self.dir / f"tile-{index:05d}.npz", lambda fh: np.savez(fh, **entries), sweep=False)
        except OSError as err:
            raise SaveFailed(f"could not save a finished tile in {self.dir}: {_why(err)}; its "
                             f"{self.finished()} finished tiles are kept: rerun with --resume once it can be "
                             f"written") from None

    def remove(self) -> None:
        """Remove the checkpoint: fsweep's own entries one by one, then the folder if that left it empty
        (anything else stays, and so does the folder: never a tree removed wholesale)."""
        if not self.dir.is_dir() or self.dir.is_symlink():
            return
        try:
            with os.scandir(self.dir) as entries:
                own = [Path(entry.path) for entry in entries if _own_entry(entry)]
        except OSError:
            return
        for path in own:
            _discard(path)
        try:
            self.dir.rmdir()
        except OSError:
            pass  # not empty (a stranger's file appeared during the run), or gone: left as it is


def _own_entry(entry: os.DirEntry) -> bool:
    """Whether a checkpoint folder's entry is fsweep's by name and kind: a regular file (not a link) named
    as fsweep names them, or an empty folder of such a name (it holds nothing to lose)."""
    if not (_OWN_NAME.fullmatch(entry.name) or _OWN_TEMPORARY.fullmatch(entry.name)):
        return False
    try:
        if entry.is_symlink():
            return False
        if entry.is_file(follow_symlinks=False):
            return True
        return entry.is_dir(follow_symlinks=False) and not any(os.scandir(entry.path))
    except OSError:
        return False


def _manifest_shape(manifest) -> bool:
    """Whether parsed JSON has the shape of the manifest fsweep writes (_write_manifest)."""
    return (isinstance(manifest, dict) and isinstance(manifest.get("key"), str)
            and type(manifest.get("tiles")) is int
            and set(manifest) <= {"key", "tiles", "variables"})


def _discard(path: Path) -> None:
    """Remove an entry of the checkpoint that is fsweep's (_own_entry): a file, or an empty folder."""
    try:
        if path.is_dir() and not path.is_symlink():
            path.rmdir()  # only ever empty: a folder holding anything is a stranger's, never removed
        else:
            path.unlink(missing_ok=True)
    except OSError:
        pass


def _why(err: BaseException) -> str:
    return (getattr(err, "strerror", None) or " ".join(str(err).split()) or type(err).__name__).rstrip(".")
