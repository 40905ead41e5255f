"""Write a file under a temporary name in its folder and rename it into place: a failed or
interrupted write never leaves a partial file, and never damages the one it replaces."""

from __future__ import annotations

import os
from pathlib import Path


def _replace(path, write) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def write_text(path, text: str) -> Path:
    return _replace(path, lambda tmp: tmp.write_text(text))


def save_figure(fig, path, **savefig_kwargs) -> Path:
    """Save a matplotlib figure as PNG atomically, and close it."""
    import matplotlib.pyplot as plt

    try:
        return _replace(path, lambda tmp: fig.savefig(tmp, format="png", **savefig_kwargs))
    finally:
        plt.close(fig)
