"""Whether numba's on-disk cache holds a compiled kernel, read without importing numba or the kernel
(the estimate stays numba-free): a run whose kernels are not cached compiles them first (estimate.py:
COMPILE_SECONDS).

numba (numba.core.caching) keeps, per jitted function, an index `<module>.<function>-<line>.pyXY.nbi`
in the first of: NUMBA_CACHE_DIR/<folder>_<sha1 of the source's folder>, the source's __pycache__, the
user's cache folder. The index holds numba's version, then the SHA-256 of the source file it was
compiled from and the compiled signatures; numba ignores an index of another version or source. A
kernel compiled for another choice that is a type (the integrator: `rk4` None or True, see
kernels/period_map.py) is cold for this one: a signature is read as the names of its types.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import os
import pickle
import sys
from pathlib import Path

KERNELS = Path(__file__).resolve().parent.parent / "kernels"


def warm(module: str, function: str, last: tuple[str, ...] = ()) -> bool:
    """Whether a first call of `function` of friction_sweep.kernels.`module` (dotted: a module of a kernel
    package too, as structure.steady) finds it compiled: numba's cache holds it for this numba and this
    source, for a signature whose last argument types are named `last` (numba's names: "none", "bool"; any
    signature where empty), or numba compiles nothing (NUMBA_DISABLE_JIT). Any doubt: False, so that an
    estimate counts the compile rather than misses it."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return True  # pure Python: nothing is compiled
    source = KERNELS.joinpath(*module.split(".")).with_suffix(".py")
    try:
        version = importlib.metadata.version("numba")
        stamp = hashlib.sha256(source.read_bytes()).digest()
    except (OSError, importlib.metadata.PackageNotFoundError):
        return False
    pattern = f"{source.stem}.{function}-*.py{sys.version_info.major}{sys.version_info.minor}.nbi"
    for folder in _folders(source):
        try:
            indexes = sorted(folder.glob(pattern))
        except OSError:
            continue
        if indexes:  # numba reads the first folder it can use; an index there decides
            return any(_compiled(index, version, stamp, last) for index in indexes)
    return False


def _folders(source: Path) -> list[Path]:
    """Where numba looks for `source`'s cache, in its order."""
    subpath = f"{source.parent.name}_{hashlib.sha1(str(source.parent).encode()).hexdigest()}"
    configured = os.environ.get("NUMBA_CACHE_DIR")
    if configured:
        return [Path(configured) / subpath]
    user = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "numba" / subpath
    return [source.parent / "__pycache__", user]


class _Opaque:
    """Stands in for numba's classes while an index is read: the source's stamp is wanted, and of a type
    its name (numba pickles a type as _type_reconstructor(reconstructor, args, state), state its __dict__)."""

    def __init__(self, *args, **kwargs):
        state = args[2] if len(args) == 3 and isinstance(args[2], dict) else {}
        self.name = state.get("name")

    def __setstate__(self, state):
        pass


class _Shallow(pickle.Unpickler):
    def find_class(self, module: str, name: str):
        if module.split(".")[0] in ("numba", "llvmlite"):
            return _Opaque
        return super().find_class(module, name)


def _compiled(index: Path, version: str, stamp: bytes, last: tuple[str, ...]) -> bool:
    """Whether an index of this numba `version` and source `stamp` holds a signature ending in types named
    `last`. Its payload is (stamp, {(signature, codegen, hashes): data file})."""
    import io

    try:
        with open(index, "rb") as fh:
            if _Shallow(fh).load() != version:
                return False
            found, overloads = _Shallow(io.BytesIO(fh.read())).load()
        if found != stamp:
            return False
        names = [tuple(getattr(t, "name", None) for t in key[0]) for key in overloads]
    except Exception:  # unreadable, truncated, another format: numba would recompile
        return False
    return any(len(sig) >= len(last) and sig[len(sig) - len(last):] == last for sig in names)
