"""Ctrl-C and SIGTERM stop a run at once on every executor, keeping every finished tile; the pieces
that make it so (executors that return without waiting for a running tile, a runner that saves what
finished); Dask clusters that lose their workers or their scheduler end the run in one line.

Signal tests run `fsweep run` in its own process on a grid of minutes (rk4 at 16384 steps a period:
about 2.7 s of one core a tile of 32 x 11 points, 40 tiles), send the signal once the first tile is on
disk, and allow 15 s to stop: the run before this fix went on computing every queued tile (half a
minute and more on 2 cores) and kept none of them.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from friction_sweep.batch import executors
from friction_sweep.batch.runner import run_grid

LONG = """\
scene: {excitation: base}
grid:
  frequency_ratio: {start: 0.5, stop: 3.0, num: 1280}
  force_ratio: {start: 0.05, stop: 0.95, num: 11}
method: rk4
settings: {steps_per_period: 16384}
output: out.h5
"""
FSWEEP = "import sys; from friction_sweep.cli import main; sys.exit(main(sys.argv[1:]))"
#: seconds a stopped run may take to end: a guard against a run that goes on, not a speed test (it ends in
#: about a second; before, it took the rest of the run: 20 s to minutes, here ~2 minutes of rk4 a core)
STOP_S = 30.0


def _tiles(d: Path) -> list[Path]:
    return sorted((d / ".out.h5.partial").glob("tile-*.npz"))


def _group_gone(pgid: int, within: float) -> bool:
    """Whether no process of the run's group (its workers) is left, waiting up to `within` seconds."""
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


@pytest.mark.slow
@pytest.mark.parametrize("executor, jobs, signum", [
    ("serial", 1, signal.SIGTERM), ("threads", 2, signal.SIGTERM), ("threads", 2, signal.SIGINT),
    ("processes", 2, signal.SIGTERM), ("processes", 2, signal.SIGINT), ("dask", 2, signal.SIGTERM),
    ("dask", 2, signal.SIGINT),
], ids=lambda v: getattr(v, "name", str(v)))
def test_a_signal_stops_the_run_at_once_keeping_every_finished_tile(tmp_path, compiled, executor, jobs, signum):
    if executor == "dask":
        pytest.importorskip("distributed")
    (tmp_path / "spec.yaml").write_text(LONG)
    p = subprocess.Popen([sys.executable, "-c", FSWEEP, "run", "spec.yaml", "-q", "--executor", executor, "-j",
                          str(jobs)], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    deadline = time.monotonic() + 600
    while not _tiles(tmp_path) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert p.poll() is None and _tiles(tmp_path), "the run ended before its first tile, or never made one"
    if signum == signal.SIGINT:
        os.killpg(p.pid, signum)  # Ctrl-C: the terminal signals the whole group, workers included
    else:
        p.send_signal(signum)
    sent = time.monotonic()
    try:
        _, err = p.communicate(timeout=STOP_S)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        pytest.fail(f"{executor}: still running {STOP_S:g} s after {signum.name}")
    took = time.monotonic() - sent
    assert p.returncode == (143 if signum == signal.SIGTERM else 130), err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    kept = re.search(r"(\d+) finished tiles are kept", err)
    assert kept, err
    assert int(kept.group(1)) == len(_tiles(tmp_path)) >= 1, (err, _tiles(tmp_path))
    assert not (tmp_path / "out.h5").exists() and not (tmp_path / ".out.h5.lock").exists()
    assert not [q for q in tmp_path.rglob("*") if q.name.endswith(".tmp")]
    assert _group_gone(p.pid, STOP_S), f"{executor}: workers outlived the run"
    print(f"{executor} -j {jobs} {signum.name}: ended {took:.1f} s after the signal")


# ---- the executors and the runner: a stop returns at once, and finished tiles are kept ----------


def _blocking(release: threading.Event):
    """A tile function whose first tile returns at once and whose others wait for `release` (as a
    numba kernel does, holding no lock Python can break)."""
    def fn(args):
        if args != 0:
            release.wait(60)
        return {"x": np.array([args])}
    return fn


@pytest.mark.parametrize("executor, jobs", [("serial", 1), ("threads", 2), ("threads", 8)])
def test_a_stop_returns_without_waiting_for_running_tiles(executor, jobs):
    release = threading.Event()
    try:
        with executors.execute(_blocking(release), list(range(6)), executor, jobs) as tiles:
            first = next(iter(tiles))
            tiles.stop()
        # stop() returned while tiles still run (they end only when `release` is set, below): it did not
        # wait for them; and nothing the interpreter would wait for at exit: their threads are daemons
        running = [t for t in threading.enumerate() if t.name.startswith("fsweep-tile")]
        assert first[0] == 0 and not release.is_set()
        assert running and all(t.daemon for t in running)
    finally:
        release.set()


def test_tiles_finished_but_not_yet_handed_over_are_returned_after_a_stop():
    release = threading.Event()
    done = threading.Event()

    def fn(args):
        if args == 2:
            release.wait(60)
        done.set() if args == 1 else None
        return {"x": np.array([args])}

    try:
        tiles = executors.execute(fn, [0, 1, 2], "threads", 3)
        it = iter(tiles)
        handed = next(it)
        assert done.wait(10)
        time.sleep(0.2)  # tile 1 is finished in its worker; tile 2 still runs
        tiles.stop()
        left = tiles.finished()
        assert {i for i, _ in left} | {handed[0]} == {0, 1}
    finally:
        release.set()


def test_a_signal_while_a_tile_is_saved_keeps_that_tile(compiled):
    """The signal's KeyboardInterrupt comes out of the save itself: the tile is saved again before
    the run ends (an atomic save that was interrupted leaves nothing)."""
    saved: dict[int, dict] = {}
    calls = []

    def on_done(index, tile):
        calls.append(index)
        if len(calls) == 1:
            raise KeyboardInterrupt
        saved[index] = tile

    r = np.linspace(0.5, 2.0, 96)
    with pytest.raises(KeyboardInterrupt):
        run_grid("theory", "base", r, np.array([0.1, 0.3]), ("transmissibility",), executor="serial",
                 on_done=on_done)
    assert calls[0] in saved


def test_a_failed_save_is_not_tried_again():
    """A save that fails (a full disk) ends the run with its error; saving again would only fail again
    and hide it."""
    calls = []

    def on_done(index, tile):
        calls.append(index)
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError):
        run_grid("theory", "base", np.linspace(0.5, 2.0, 96), np.array([0.1]), ("transmissibility",),
                 executor="threads", jobs=2, on_done=on_done)
    assert len(calls) == 1


@pytest.mark.parametrize("executor, jobs, tiles, most", [
    ("threads", 1024, 3, None), ("processes", 32, 100, None), ("threads", 8, 1, 1), ("serial", 8, 10, 1),
    ("dask", 24, 1, 1),
])
def test_workers_never_outnumber_tiles_nor_cores(executor, jobs, tiles, most):
    n = executors.workers(executor, jobs, tiles)
    assert 1 <= n <= min(jobs, tiles, executors.cores())
    if most is not None:
        assert n == most


def test_a_remote_dask_cluster_gets_the_workers_asked_for_up_to_the_tiles():
    assert executors.workers("dask", 24, 100) == 24
    assert executors.local_workers("dask", 24, 100, scheduler=None) <= executors.cores()


def test_cores_are_those_this_process_may_use(monkeypatch):
    monkeypatch.setattr(executors.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    assert executors.cores() == 1
    assert executors.workers("threads", 16, 50) == 1


# ---- Dask: a cluster without workers, a lost scheduler, a server that is no scheduler -----------


@pytest.mark.slow
def test_a_dask_cluster_left_without_workers_fails_the_run(monkeypatch):
    """The cluster's only worker leaves: the run used to wait for one forever."""
    distributed = pytest.importorskip("distributed")
    from friction_sweep.batch.runner import compute_tile, tiles

    monkeypatch.setattr(executors, "NO_WORKER_S", 2.0)
    r = np.linspace(0.5, 3.0, 32 * 12)  # rk4 at 16384 steps: about half a second a tile
    work = [("rk4", "base", r[s], np.array([0.1, 0.3]), ("transmissibility",), {}, {"steps_per_period": 16384},
             None) for s in tiles(r.size)]
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None)
    outcome: list = []

    def run():
        try:
            for _ in executors.run_dask(compute_tile, work, 1, scheduler=cluster.scheduler_address):
                cluster.scale(0)  # the only worker leaves after the first tile
        except Exception as err:
            outcome.append(err)

    try:
        t = threading.Thread(target=run, daemon=True)
        t.start()
        t.join(120)
        assert not t.is_alive(), "the run still waits for a worker"
        assert len(outcome) == 1 and isinstance(outcome[0], executors.NoWorkers), outcome
    finally:
        cluster.close()


@pytest.mark.slow
def test_a_killed_scheduler_ends_the_run_in_one_line(tmp_path):
    pytest.importorskip("distributed")
    (tmp_path / "spec.yaml").write_text(LONG)
    bin_dir = Path(sys.executable).parent
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", "0",
                                  "--no-dashboard", "--scheduler-file", "s.json"], cwd=tmp_path,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = run = None
    try:
        deadline = time.monotonic() + 60
        while not (tmp_path / "s.json").exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        import json

        time.sleep(0.5)
        address = json.loads((tmp_path / "s.json").read_text())["address"]
        worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                                   "--no-dashboard"], cwd=tmp_path, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        run = subprocess.Popen([sys.executable, "-c", FSWEEP, "run", "spec.yaml", "-q", "--scheduler", address],
                               cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "PATH": f"{bin_dir}:{os.environ.get('PATH', '')}"})
        deadline = time.monotonic() + 600
        while not _tiles(tmp_path) and run.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert run.poll() is None and _tiles(tmp_path)
        scheduler.kill()
        _, err = run.communicate(timeout=120)
    finally:
        for proc in (run, worker, scheduler):
            if proc is not None and proc.poll() is None:
                proc.kill()
                proc.wait()
    assert run.returncode == 1, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert "Dask scheduler" in err and f"{len(_tiles(tmp_path))} finished tiles are kept" in err


def _greeting_server(greeting: bytes):
    import socket

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)

    def serve():
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return
            conn.sendall(greeting)
            time.sleep(0.5)
            conn.close()

    threading.Thread(target=serve, daemon=True).start()
    return server


@pytest.mark.parametrize("greeting", [b"SSH-2.0-OpenSSH_9.6\r\n", b"220 mail.example.com ESMTP\r\n", b"\x00" * 16,
                                      b"HTTP/1.1 400 Bad Request\r\n\r\n"])
def test_a_server_that_greets_but_is_no_dask_scheduler_is_refused(tmp_path, monkeypatch, greeting):
    """A client that took its greeting for a Dask message's length tried to allocate 2.82 EiB."""
    pytest.importorskip("distributed")
    from click.testing import CliRunner

    from friction_sweep.cli import main

    server = _greeting_server(greeting)
    (tmp_path / "spec.yaml").write_text(LONG)
    monkeypatch.chdir(tmp_path)
    try:
        res = CliRunner().invoke(main, ["run", "spec.yaml", "-q", "--scheduler",
                                        f"tcp://127.0.0.1:{server.getsockname()[1]}"])
    finally:
        server.close()
    assert res.exit_code == 2 and "not a Dask scheduler" in res.output, res.output
    assert len(res.output.splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]
