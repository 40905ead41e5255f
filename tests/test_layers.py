"""The package's layers (friction_sweep/__init__.py): no import runs back up, and the commands that
need no kernel load no numba."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "friction_sweep"

#: each module's layer, by its first dotted part below friction_sweep (a module may import its own
#: layer and those below, never one above)
LAYERS = {
    "": 0, "catalogue": 0, "codes": 0, "ties": 0, "exits": 0, "errors": 0, "progress": 0, "printable": 0,
    "packaged": 0, "posix": 0,
    "spec": 1,
    "theory": 2,
    "kernels": 3,
    "storage": 4,
    "methods": 5, "structures": 5,
    "bench": 6, "consistency": 6, "consistency_structure": 6, "design": 6, "quicklook": 6, "quicklook_structure": 6,
    "measured": 6,
    "batch": 7, "calibration": 7,
    "api": 8, "cli": 8, "validation": 8, "__main__": 8,
}
#: the package root re-exports the Python API, loaded on first attribute access (friction_sweep/__init__.py)
ROOT_EXPORTS = {"friction_sweep.api", "friction_sweep.errors", "friction_sweep.spec.errors"}


def _layer(module: str) -> int:
    parts = module.split(".")
    return LAYERS[parts[1] if len(parts) > 1 else ""]


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def _imports(path: Path, module: str):
    """Every friction_sweep module that `path` imports, at any depth (lazy imports included)."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names if a.name.split(".")[0] == "friction_sweep")
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the importing package
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            if target.split(".")[0] == "friction_sweep":
                for alias in node.names:  # `from friction_sweep import methods` imports a module
                    sub = f"{target}.{alias.name}"
                    yield sub if _is_module(sub) else target


def _is_module(name: str) -> bool:
    path = PACKAGE.parent.joinpath(*name.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_import_runs_back_up(path):
    module = _module_name(path)
    for target in _imports(path, module):
        if module == "friction_sweep" and target in ROOT_EXPORTS:
            continue
        assert _layer(target) <= _layer(module), f"{module} (layer {_layer(module)}) imports {target}"


def test_validate_settings_and_info_methods_load_no_kernel(tmp_path):
    """Numba-free: checking a spec, estimating its cost and listing methods."""
    spec = tmp_path / "spec.yaml"
    spec.write_text("scene: {excitation: base}\ngrid: {frequency_ratio: [0.5, 2.0], force_ratio: [0.1]}\n"
                    "method: event\n")
    code = ("import sys\nfrom friction_sweep.cli import main\n"
            f"for args in (['validate', {str(spec)!r}], ['settings'], ['info', '--methods']):\n"
            "    try:\n        main(args)\n    except SystemExit as e:\n        assert e.code == 0, (args, e.code)\n"
            "assert 'numba' not in sys.modules, 'numba was imported'\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
