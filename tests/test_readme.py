"""Every example in README.md and docs/*.md runs as written (issue 29): a README that drifts from the
code fails here, in CI.

Each fenced block is run in a fresh folder holding links to the repository's `configs/`, `figures/` and
`friction_sweep/` (the paths the examples name), so nothing is written into the repository:
- ```yaml: a sweep spec is checked by `fsweep validate`; a calibration spec (top-level `data:`) by the
  calibration spec's loader, data file included;
- ```python: executed (matplotlib without a screen);
- ```sh: each line run by the shell, `fsweep` being this interpreter's.
HTML comments right above a block (invisible on the rendered page) say what else it needs:
- `<!-- example: synopsis -->`: not run (placeholders such as SPEC, or commands CI runs itself);
- `<!-- example: after: COMMAND -->`: COMMAND is run first in the same folder (what the block reads).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from conftest import ROOT

from friction_sweep.calibration.spec import data_path, load_calibration_spec

DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
MARKER = re.compile(r"<!--\s*example:\s*(.*?)\s*-->")


@dataclass(frozen=True)
class Block:
    document: str
    line: int  # of the opening fence, 1-based
    language: str
    text: str
    markers: tuple[str, ...]

    @property
    def id(self) -> str:
        return f"{self.document}:{self.line}:{self.language or 'text'}"


def blocks(path: Path) -> list[Block]:
    """The fenced blocks of a Markdown file, each with the example markers in the comments above it."""
    lines = path.read_text().splitlines()
    found, i = [], 0
    while i < len(lines):
        fence = re.match(r"^```(\w*)\s*$", lines[i])
        if not fence:
            i += 1
            continue
        start, language = i, fence.group(1)
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            i += 1
        markers, j = [], start - 1
        while j >= 0 and MARKER.fullmatch(lines[j].strip()):
            markers.insert(0, MARKER.fullmatch(lines[j].strip()).group(1))
            j -= 1
        found.append(Block(path.name, start + 1, language, "\n".join(lines[start + 1:i]) + "\n", tuple(markers)))
        i += 1
    return found


ALL = [b for doc in DOCUMENTS for b in blocks(doc)]
RUN = [b for b in ALL if "synopsis" not in b.markers]


def _env(folder: Path) -> dict[str, str]:
    bin_dir = Path(sys.executable).parent
    return {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}", "MPLBACKEND": "Agg",
            "PYTHONPATH": str(ROOT)}


def _folder(tmp_path: Path) -> Path:
    for name in ("configs", "figures", "friction_sweep"):
        (tmp_path / name).symlink_to(ROOT / name)
    return tmp_path


def _shell(command: str, folder: Path) -> None:
    res = subprocess.run(command, shell=True, cwd=folder, env=_env(folder), capture_output=True, text=True,
                         check=False)
    assert res.returncode == 0, f"{command!r} failed ({res.returncode}):\n{res.stdout}\n{res.stderr}"


def test_the_documents_have_examples_and_every_marker_is_known():
    assert len(RUN) >= 6, [b.id for b in RUN]
    for b in ALL:
        assert b.language in {"yaml", "python", "sh", ""}, f"{b.id}: a block in {b.language!r} is not run"
        assert b.language or "synopsis" in b.markers, f"{b.id}: a block without a language must be a synopsis"
        for m in b.markers:
            assert m == "synopsis" or m.startswith("after: "), f"{b.id}: unknown marker {m!r}"


@pytest.mark.slow
@pytest.mark.parametrize("block", RUN, ids=lambda b: b.id)
def test_example_runs_as_written(block: Block, tmp_path: Path, compiled) -> None:
    folder = _folder(tmp_path)
    for m in block.markers:
        _shell(m.removeprefix("after: "), folder)
    if block.language == "yaml" and re.search(r"^data:", block.text, re.MULTILINE):
        # a calibration spec: its relative data path is read from configs/calibration/, as rig.yaml is
        path = folder / "specs" / "calibration" / "readme.yaml"  # ../../friction_sweep: the linked package
        path.parent.mkdir(parents=True)
        spec = load_calibration_spec(_write(path, block.text))
        assert data_path(spec).is_file(), data_path(spec)
    elif block.language == "yaml":
        _shell(f"fsweep validate {_write(folder / 'readme.yaml', block.text)}", folder)
    elif block.language == "python":
        res = subprocess.run([sys.executable, _write(folder / "readme_example.py", block.text)], cwd=folder,
                             env=_env(folder), capture_output=True, text=True, check=False)
        assert res.returncode == 0, f"{block.id} raised:\n{res.stderr[-3000:]}"
    elif block.language == "sh":
        for line in block.text.splitlines():
            command = line.split("#", 1)[0].strip()
            if command:
                _shell(command, folder)
    # the example wrote only into its own folder, never into the repository
    assert not (ROOT / "readme_example.py").exists()


def _write(path: Path, text: str) -> str:
    path.write_text(text)
    return str(path)


def test_the_command_line_synopsis_names_every_command():
    """The README's synopsis lists each command `fsweep --help` offers (validate-data was missing)."""
    from click.testing import CliRunner

    from friction_sweep.cli import main

    help_text = CliRunner().invoke(main, ["--help"]).output
    commands = re.findall(r"^  ([a-z][a-z-]+)\s", help_text.split("Commands:")[1], re.MULTILINE)
    synopsis = next(b for b in ALL if b.document == "README.md" and "fsweep run SPEC" in b.text)
    listed = set(re.findall(r"^fsweep ([a-z][a-z-]+)", synopsis.text, re.MULTILINE))
    assert set(commands) <= listed, set(commands) - listed
