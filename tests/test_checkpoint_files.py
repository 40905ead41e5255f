"""Issue 28, files and checkpoints, where a CLI row cannot say it: a writer killed mid-write, a live
writer's temporary, a result published all or nothing without --overwrite, and what the checkpoint's
fingerprint covers."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from friction_sweep.batch import pipeline
from friction_sweep.spec import parse_spec_text
from friction_sweep.storage import atomic, outputs

SPEC = """\
scene: {excitation: base}
grid:
  frequency_ratio: {start: 0.5, stop: 2.0, num: 40}
  force_ratio: [0.1, 0.4]
method: event
"""


def _writing_child(target: Path) -> subprocess.Popen:
    """A process inside atomic.write of `target`, its writer blocked until killed."""
    code = ("import sys, time\nfrom friction_sweep.storage import atomic\n"
            "def writer(fh):\n    fh.write(b'x' * 1_000_000)\n    fh.flush()\n    time.sleep(600)\n"
            f"atomic.write({str(target)!r}, writer)\n")
    return subprocess.Popen([sys.executable, "-c", code])


def _temporaries(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.name.endswith(".tmp"))


def _wait_for_temporary(folder: Path, child: subprocess.Popen) -> Path:
    deadline = time.monotonic() + 60
    while not _temporaries(folder):
        assert child.poll() is None and time.monotonic() < deadline, "the writer never started"
        time.sleep(0.05)
    return _temporaries(folder)[0]


def test_the_next_write_removes_what_a_killed_writer_left(tmp_path):
    target = tmp_path / "big.h5"
    child = _writing_child(target)
    left = _wait_for_temporary(tmp_path, child)
    child.kill()
    child.wait()
    assert left.exists() and str(child.pid) in left.name
    atomic.write_bytes(target, b"new")
    assert target.read_bytes() == b"new" and _temporaries(tmp_path) == []


def test_a_live_writers_temporary_is_never_removed(tmp_path):
    target = tmp_path / "big.h5"
    child = _writing_child(target)
    try:
        live = _wait_for_temporary(tmp_path, child)
        atomic.write_bytes(target, b"other")  # a second writer of the same target, e.g. a plot
        assert atomic.remove_stale(target) == [] and live.exists()
    finally:
        child.kill()
        child.wait()


def _second_file_appears_meanwhile(folder: Path) -> Path:
    """write_all of two files without --overwrite, the second appearing while the first is staged: neither
    is published, the stranger's is kept. Returns the stranger's file."""
    first, second = folder / "a.csv", folder / "b.md"

    def appear_meanwhile(tmp: Path) -> None:
        atomic.write_text(tmp, "ours")
        second.write_text("theirs")

    with pytest.raises(outputs.Appeared):
        outputs.write_all([(first, lambda tmp: atomic.write_text(tmp, "ours")), (second, appear_meanwhile)],
                          overwrite=False)
    assert sorted(p.name for p in folder.iterdir()) == ["b.md"] and second.read_text() == "theirs"
    return second


def test_without_overwrite_a_result_appears_whole_or_not_at_all(tmp_path):
    _second_file_appears_meanwhile(tmp_path)


def _key(text: str = SPEC, settings: dict | None = None, extra: dict | None = None) -> str:
    spec = parse_spec_text(text)
    return pipeline.checkpoint_key(spec, settings if settings is not None else dict(spec.settings), extra or {})


@pytest.mark.parametrize("change", [
    lambda: _key(settings={"max_periods": 3}),  # what accuracy: resolved
    lambda: _key(extra={"accuracy_choice": "another row"}),
    lambda: _key(SPEC.replace("{excitation: base}", "{excitation: base, effects: {viscous_damping: 0.01}}")),
    lambda: _key(SPEC + "sweep: {direction: up}\n"),
    lambda: _key(SPEC + "sweep: {direction: down}\n"),
    lambda: _key(SPEC + "outputs: [transmissibility, regime]\n"),
    lambda: _key(SPEC.replace("num: 40", "num: 41")),
    lambda: _key(SPEC + "system: {natural_frequency: 10 Hz, mass: 1 kg, base_amplitude: 1 mm}\n"),
])
def test_the_checkpoint_key_covers_every_input_that_changes_a_number(change):
    assert change() != _key()


def test_the_checkpoint_key_covers_calibration_version_and_code(monkeypatch, tmp_path):
    import friction_sweep
    from friction_sweep.bench import workprecision

    accurate = SPEC + "accuracy: 1.0e-3\n"
    calibration = tmp_path / "calibration.json"
    calibration.write_text(workprecision.PACKAGED_CALIBRATION.read_text())
    monkeypatch.setattr(workprecision, "calibration_path", lambda: calibration)
    before = _key(accurate)
    calibration.write_text(workprecision.PACKAGED_CALIBRATION.read_text() + " ")
    assert _key(accurate) != before
    monkeypatch.setattr(friction_sweep, "__version__", "0.0.0-other")
    assert _key(accurate) != before
    versioned = _key(accurate)
    monkeypatch.setattr(pipeline, "code_version", lambda: "other kernels")
    assert _key(accurate) != versioned
    assert np.unique([_key(accurate) for _ in range(3)]).size == 1  # and nothing else moves it


def test_a_resumed_checkpoint_drops_the_tile_a_killed_run_was_writing(tmp_path):
    from friction_sweep.batch import checkpoint

    grids = [{"frequency_ratio": np.array([0.5, 1.5]), "force_ratio": np.array([0.1])}] * 2
    store = checkpoint.Checkpoint(tmp_path / "out.h5", "key", grids)
    store.start(resume=False)
    store.save(0, {"transmissibility": np.ones((1, 2))})
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    left = store.dir / f".tile-00001.npz.{child.pid}-abcdefgh.tmp"
    left.write_bytes(b"half a tile")
    done, dropped = checkpoint.Checkpoint(tmp_path / "out.h5", "key", grids).start(resume=True)
    assert list(done) == [0] and dropped == [] and not left.exists()


def test_removing_a_checkpoint_keeps_a_file_that_appeared_in_it(tmp_path):
    """Issue 28 round 2: a finished run removes its checkpoint entry by entry, never as a tree, so a user's
    file put into the folder during the run survives (and so does the folder holding it)."""
    from friction_sweep.batch.checkpoint import Checkpoint

    store = Checkpoint(tmp_path / "out.h5", "k" * 64, [{"frequency_ratio": np.ones(2)}])
    store.start(resume=False)
    store.save(0, {"regime": np.zeros(2, np.int8)})
    (store.dir / "thesis.tex").write_text("precious")
    store.remove()
    assert sorted(p.name for p in store.dir.iterdir()) == ["thesis.tex"]
    (store.dir / "thesis.tex").unlink()
    store.remove()
    assert not store.dir.exists()


NO_HARD_LINKS = [errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK, errno.EXDEV]


def _without_hard_links(monkeypatch, code: int) -> None:
    def refuse(*args, **kwargs):
        raise OSError(code, os.strerror(code))
    monkeypatch.setattr(os, "link", refuse)


@pytest.mark.parametrize("code", NO_HARD_LINKS, ids=errno.errorcode.get)
def test_without_hard_links_outputs_are_still_published_whole(tmp_path, monkeypatch, code):
    """Issue 28 round 2: FAT, exFAT, some CIFS/sshfs mounts have no hard links; a command without
    --overwrite still publishes its files (before: OSError from os.link), and a cube likewise."""
    _without_hard_links(monkeypatch, code)
    first, second = tmp_path / "a.csv", tmp_path / "b.md"
    paths = outputs.write_all([(first, lambda tmp: atomic.write_text(tmp, "one")),
                               (second, lambda tmp: atomic.write_text(tmp, "two"))], overwrite=False)
    assert paths == [first, second] and first.read_text() == "one" and second.read_text() == "two"
    atomic.write_bytes(tmp_path / "c.h5", b"cube", overwrite=False)
    assert (tmp_path / "c.h5").read_bytes() == b"cube"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.md", "c.h5"]


@pytest.mark.parametrize("code", NO_HARD_LINKS, ids=errno.errorcode.get)
def test_without_hard_links_a_file_that_appeared_is_never_replaced(tmp_path, monkeypatch, code):
    _without_hard_links(monkeypatch, code)
    second = _second_file_appears_meanwhile(tmp_path)
    with pytest.raises(FileExistsError):
        atomic.write_bytes(second, b"cube", overwrite=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.md"] and second.read_text() == "theirs"


def test_other_link_errors_are_not_taken_for_a_missing_feature(tmp_path, monkeypatch):
    """A full disk or an I/O error while publishing is reported, not worked around."""
    _without_hard_links(monkeypatch, errno.ENOSPC)
    with pytest.raises(OSError) as caught:
        atomic.write_bytes(tmp_path / "c.h5", b"cube", overwrite=False)
    assert caught.value.errno == errno.ENOSPC and list(tmp_path.iterdir()) == []
