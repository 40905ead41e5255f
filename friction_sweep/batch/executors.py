"""Where tiles run: in this process, in threads, in processes, or on a Dask cluster.

Every executor yields (tile index, result) as tiles complete. Results never depend on the executor:
a tile is a pure function of its inputs, and assembly places it by index.

A run can be stopped at any moment (Ctrl-C, SIGTERM, a failed save): `Tiles.stop()` returns at once,
whatever a worker is computing. Nothing waits for a running tile: threads are daemons that the
interpreter does not join at exit (a numba kernel cannot be interrupted), processes are killed,
a Dask cluster is closed without draining. Tiles finish in workers only; the caller saves what it
was handed (and `finished()`: tiles done but not yet handed over when it stopped), so a stop never
loses a finished tile and never writes part of one.
"""

from __future__ import annotations

import logging
import os
import queue
import signal
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

log = logging.getLogger("friction_sweep")

EXECUTORS = ("threads", "processes", "dask", "serial")
#: chosen by measurement on 2 cores (README, make bench): threads share one compiled kernel and skip
#: process start-up; the kernels release the GIL
DEFAULT_EXECUTOR = "threads"
#: the most workers a command may ask for (run and calibrate -j, the API's jobs); a run starts no more
#: than its tiles and, locally, the cores allow
MAX_JOBS = 1024
#: seconds between the main thread's looks for a signal while it waits for tiles
WAKE_S = 0.2


def cores() -> int:
    """The cores this process may run on (a container's or taskset's share, not the machine's)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def workers(executor: str, jobs: int, n_tiles: int) -> int:
    """Workers a run starts: one for serial; never more than tiles (the rest would idle), nor, on this
    machine, more than cores (they would share them and only cost memory and start-up). A remote
    Dask cluster's size is unknown here: -j is the user's word for it."""
    if executor == "serial" or jobs <= 1 or n_tiles <= 1:
        return 1
    if executor == "dask":
        return max(1, min(jobs, n_tiles))
    return max(1, min(jobs, n_tiles, cores()))


def capped(executor: str, jobs: int, n: int, n_tiles: int, scheduler: str | None) -> str:
    """Why `n` workers run where -j asked for `jobs` (more would idle, or share cores)."""
    if executor == "serial":
        return "--executor serial runs one"
    why = [f"the run has {n_tiles} tile(s)"] if n_tiles == n else []
    if not (executor == "dask" and scheduler is not None) and cores() == n:
        why.append(f"this machine has {n} core(s)")
    return " and ".join(why) or f"{n} can run at once"


def local_workers(executor: str, jobs: int, n_tiles: int, scheduler: str | None) -> int:
    """`workers` where the cluster is ours: a Dask LocalCluster runs on this machine's cores too."""
    return workers("threads" if executor == "dask" and scheduler is None else executor, jobs, n_tiles)


class Tiles:
    """Tiles in flight on some executor: iterate for (index, result) as they complete; `stop()` to end
    early without waiting; `finished()` after a stop for results done but not yet yielded."""

    def __iter__(self) -> Iterator[tuple[int, dict]]:
        raise NotImplementedError

    def finished(self) -> list[tuple[int, dict]]:
        return []

    def stop(self) -> None:
        """Cancel what has not started and abandon what has; return at once."""

    def __enter__(self) -> Tiles:
        return self

    def __exit__(self, *exc) -> None:
        self.stop()


class _DaemonThreads:
    """A pool of daemon threads: at a stop the interpreter exits without joining them (a running numba
    kernel cannot be interrupted; ThreadPoolExecutor joins its threads at exit, which kept a stopped
    run alive until every tile it had queued was computed)."""

    def __init__(self, jobs: int):
        self._queue: queue.SimpleQueue = queue.SimpleQueue()
        self._threads = [threading.Thread(target=self._work, name=f"fsweep-tile-{k}", daemon=True)
                         for k in range(jobs)]
        for t in self._threads:
            t.start()

    def submit(self, fn: Callable, args) -> Future:
        fut: Future = Future()
        self._queue.put((fut, fn, args))
        return fut

    def _work(self) -> None:
        # a process's signal goes to any thread that does not block it; taken by a thread in its kernel,
        # it would wait until a tile finished to interrupt the main thread, blocked in its wait
        if hasattr(signal, "pthread_sigmask"):
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        while (item := self._queue.get()) is not None:
            fut, fn, args = item
            if not fut.set_running_or_notify_cancel():
                continue
            try:
                fut.set_result(fn(args))
            except BaseException as err:  # handed to the caller, who raises it
                fut.set_exception(err)

    def shutdown(self) -> None:
        for _ in self._threads:
            self._queue.put(None)
        # a thread still in its kernel runs on until the process exits: at the lowest priority, so
        # that it does not slow the exit it cannot stop (Linux: a thread's own nice value)
        for t in self._threads:
            if t.is_alive() and t.native_id is not None:
                try:
                    os.setpriority(os.PRIO_PROCESS, t.native_id, 19)
                except (AttributeError, OSError):
                    pass


def _ignore_interrupts() -> None:
    """A worker process's start: Ctrl-C reaches the whole process group, and each worker would print a
    traceback; the run's own process handles it (and kills the workers). SIGTERM ends a worker at once
    (the parent's handler, inherited by fork, would wait for the kernel to return)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


class _Processes:
    def __init__(self, jobs: int):
        self._pool = ProcessPoolExecutor(max_workers=jobs, initializer=_ignore_interrupts)

    def submit(self, fn: Callable, args) -> Future:
        return self._pool.submit(fn, args)

    def shutdown(self) -> None:
        # the pool's worker processes, read before shutdown forgets them (Python 3.14 has
        # terminate_workers(); before it, only this attribute names them)
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        self._pool.shutdown(wait=False, cancel_futures=True)
        for p in processes:  # a running tile is abandoned, not waited for
            try:
                p.kill()
            except (OSError, AttributeError, ValueError):
                pass


class _Local(Tiles):
    """Tiles on a local pool, at most `jobs` in flight: the next starts once one is handed over, so a
    stop cancels nothing that was queued and (serial) the tile after a saved one starts only after it
    was saved."""

    def __init__(self, pool, fn: Callable, work: list, jobs: int):
        self._pool, self._fn, self._jobs = pool, fn, jobs
        self._todo = iter(enumerate(work))
        self._in_flight: dict[Future, int] = {}
        self._stopped = False

    def _fill(self) -> None:
        while not self._stopped and len(self._in_flight) < self._jobs:
            nxt = next(self._todo, None)
            if nxt is None:
                return
            self._in_flight[self._pool.submit(self._fn, nxt[1])] = nxt[0]

    def __iter__(self) -> Iterator[tuple[int, dict]]:
        self._fill()
        while self._in_flight:
            # in steps: a signal that another thread of this process took (Dask's, the progress bar's)
            # is handled between them
            done, _ = wait(self._in_flight, timeout=WAKE_S, return_when=FIRST_COMPLETED)
            for fut in done:
                index = self._in_flight.pop(fut)
                yield index, fut.result()
                self._fill()
        self.stop()  # all handed over: the workers end (iterated outside a `with` too)

    def finished(self) -> list[tuple[int, dict]]:
        return [(i, f.result()) for f, i in list(self._in_flight.items())
                if f.done() and not f.cancelled() and f.exception() is None]

    def stop(self) -> None:
        if not self._stopped:
            self._stopped = True
            for fut in self._in_flight:
                fut.cancel()
            if self._pool is not None:
                self._pool.shutdown()


class DaskUnavailable(RuntimeError):
    """Dask cannot run the tiles: not installed, or the scheduler's address is wrong or unreachable."""


class DaskLost(RuntimeError):
    """The Dask scheduler was lost, or cancelled the run's tasks."""


class NoWorkers(RuntimeError):
    """The Dask cluster has had no worker for longer than NO_WORKER_S: its tiles would wait forever."""


#: seconds to wait for a scheduler's port to answer before a run starts (Dask's own wait is 30 s)
CONNECT_TIMEOUT_S = 5.0
#: seconds a Dask cluster may have no worker before the run fails (a nanny restarts a killed worker
#: in a second or two; an external cluster's workers may be restarting)
NO_WORKER_S = 20.0
#: seconds between looks at the scheduler's worker count while no tile completes
WATCH_S = 1.0


def check_dask(scheduler: str | None) -> None:
    """DaskUnavailable with the reason, unless Dask is installed and `scheduler` (if given) is a
    reachable tcp:// address whose server speaks first, as a Dask scheduler does. Cheap: no client is
    made (a client that reads a foreign server's bytes as a message length tries to allocate it)."""
    import importlib.util
    import socket

    try:
        missing = importlib.util.find_spec("distributed") is None
    except (ImportError, ValueError):  # blocked in sys.modules, or a broken install
        missing = True
    if missing:
        raise DaskUnavailable("--executor dask needs dask.distributed: pip install 'friction_sweep[dask]'")
    if scheduler is None:
        return
    from urllib.parse import urlsplit

    url = urlsplit(scheduler if "://" in scheduler else f"tcp://{scheduler}")
    try:
        host, port = url.hostname, url.port
    except ValueError:
        host, port = None, None
    if url.scheme != "tcp" or not host or port is None or url.path not in ("", "/"):
        raise DaskUnavailable(f"--scheduler: {scheduler!r} is not a scheduler address (expected "
                              "tcp://HOST:PORT, as the scheduler prints it)")
    try:
        with socket.create_connection((host, port), timeout=CONNECT_TIMEOUT_S) as conn:
            # a scheduler greets every connection at once (its handshake); a port that accepts and
            # stays silent would leave Dask's client waiting forever
            greeting = _greeting(conn)
    except OSError as err:
        why = err.strerror or ("no answer" if isinstance(err, TimeoutError) else str(err) or type(err).__name__)
        raise DaskUnavailable(f"--scheduler: cannot reach the Dask scheduler at {scheduler}: {why}") from None
    if not greeting:
        raise DaskUnavailable(f"--scheduler: {scheduler} closed the connection at once: not a Dask scheduler")
    if not _is_dask_handshake(greeting):
        raise DaskUnavailable(f"--scheduler: {scheduler} answers, but not as a Dask scheduler does: not a Dask "
                              "scheduler")


def _greeting(conn) -> bytes:
    """The first frame header a server sends: up to 16 bytes, as many as arrive within the timeout."""
    data = b""
    while len(data) < 16:
        try:
            chunk = conn.recv(16 - len(data))
        except TimeoutError:
            if data:
                break
            raise
        if not chunk:
            break
        data += chunk
    return data


def _is_dask_handshake(data: bytes) -> bool:
    """Whether `data` opens a Dask TCP message (distributed.comm.tcp): a little-endian uint64 length of
    the message (a handshake: a few hundred bytes), then its uint64 count of frames (a handful). Any
    other server's greeting ("SSH-2.0-...", "220 ...") reads as an absurd length."""
    if len(data) < 8:
        return False
    length = int.from_bytes(data[:8], "little")
    frames = int.from_bytes(data[8:16], "little") if len(data) >= 16 else 1
    return 16 <= length <= 2**20 and 1 <= frames <= 64


def _route_dask_logs() -> None:
    """Dask's, tornado's and asyncio's log records go through fsweep's logging (their own handlers
    removed), shown with -v only: without it a failure is fsweep's one line, not their tracebacks."""
    shown = logging.INFO if log.isEnabledFor(logging.INFO) else logging.CRITICAL + 1
    families = ("distributed", "dask", "tornado", "asyncio", "bokeh")
    for name in list(logging.root.manager.loggerDict):
        if name.split(".")[0] in families:
            logger = logging.getLogger(name)
            logger.handlers.clear()
            logger.propagate = True
            logger.setLevel(logging.NOTSET)
    for name in families:
        logging.getLogger(name).setLevel(shown)


class _Dask(Tiles):
    """Tiles as Dask tasks: on `scheduler` (address) or on a LocalCluster of `jobs` workers.

    A worker that dies takes its tasks with it; the scheduler reassigns them (and `retries` covers
    tasks that raised), so every tile is computed once in the result. A cluster left without any
    worker for NO_WORKER_S fails the run (NoWorkers) instead of waiting for one forever.
    """

    def __init__(self, fn: Callable, work: list, jobs: int, scheduler: str | None, retries: int):
        from dask.distributed import Client, LocalCluster

        _route_dask_logs()
        self.cluster = None
        if scheduler is None:
            # Ctrl-C reaches the whole process group: the workers would each print a traceback. Started
            # with SIGINT ignored (inherited), they leave it to this process, which closes the cluster.
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if _main_thread() else None
            try:
                quiet = logging.INFO if log.isEnabledFor(logging.INFO) else logging.CRITICAL
                # no dashboard; the scheduler's HTTP server (health and metrics routes) still starts, by
                # default on port 8787, warning when that port is taken: a free loopback port instead
                self.cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                            dashboard_address=None, silence_logs=quiet,
                                            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
            finally:
                if previous is not None:
                    signal.signal(signal.SIGINT, previous)
            _route_dask_logs()  # the cluster set its own levels on this process's loggers
            client = Client(self.cluster)
        else:
            client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s")
        self.client = client
        log.info("dask: %s", self.client)
        self.futures = {self.client.submit(fn, args, pure=False, retries=retries): i for i, args in enumerate(work)}
        self._handed: set = set()
        self._stopped = False

    def __iter__(self) -> Iterator[tuple[int, dict]]:
        from dask.distributed import as_completed

        # as_completed waits on the *current* client's loop by default; inside a caller's
        # `with Client(...)` that is another loop than these futures' one (flaky "bound to a
        # different event loop" in fut.result()), so name ours
        done = as_completed(self.futures, loop=self.client.loop)
        seen = last_look = time.monotonic()
        while not done.is_empty():
            if not done.has_ready():
                now = time.monotonic()
                if now - last_look >= WATCH_S:
                    last_look = now
                    if self._worker_count() > 0:
                        seen = now
                    elif now - seen > NO_WORKER_S:
                        raise NoWorkers(f"the Dask cluster has had no worker for {NO_WORKER_S:g} s; its tiles "
                                        "cannot run")
                time.sleep(0.05)
                continue
            fut = next(done)
            self._handed.add(fut)
            try:
                result = fut.result()
            except Exception as err:
                if fut.status != "cancelled":
                    raise  # the tile raised, on every retry: the run fails with its reason
                # the scheduler dropped it: Dask's own words name the reason (a lost connection)
                raise DaskLost(f"the Dask scheduler dropped the run's tasks: {str(err).split(': ', 1)[-1]}") from None
            yield self.futures[fut], result
        self.stop()  # all handed over: the client and our cluster close (iterated outside a `with` too)

    def _worker_count(self) -> int:
        try:
            return int(self.client.scheduler_info(n_workers=0).get("n_workers", 0))
        except Exception:  # a scheduler that does not answer: the futures say so, or no worker comes
            return 0

    def finished(self) -> list[tuple[int, dict]]:
        results = []
        for fut, i in self.futures.items():
            if fut not in self._handed and fut.status == "finished":
                try:
                    results.append((i, fut.result(timeout=1)))
                except Exception:  # gone with its worker: computed again on --resume
                    pass
        return results

    def stop(self) -> None:
        if self._stopped:
            return
        self._stopped = True
        if self.cluster is not None:
            # our workers are killed, not asked to finish their tile: a graceful close waits for it
            # (and, timed out, again at exit); closing the client releases the tasks not started
            for nanny in list(self.cluster.workers.values()):
                pid = getattr(getattr(getattr(nanny, "process", None), "process", None), "pid", None)
                if pid:
                    try:
                        os.kill(pid, signal.SIGKILL)
                    except OSError:
                        pass
        for closing in (self.client, self.cluster):
            if closing is not None:
                try:
                    closing.close(timeout=2)
                except Exception as err:  # a lost scheduler: nothing left to close
                    log.info("dask: closing: %s", err)


def run_dask(fn, work, jobs, scheduler: str | None = None, retries: int = 3) -> Tiles:
    return _Dask(fn, work, jobs, scheduler, retries)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def execute(fn, work: list, executor: str, jobs: int, scheduler: str | None = None) -> Tiles:
    """The tiles of `work` computed by `fn` on `executor`, with at most `workers(...)` workers (a log line
    says where -j asked for more than help)."""
    if executor not in EXECUTORS:
        raise ValueError(f"unknown executor {executor!r} (known: {', '.join(EXECUTORS)})")
    n = local_workers(executor, jobs, len(work), scheduler)
    if n < jobs:
        log.info("-j %d: %d worker(s), as %s", jobs, n, capped(executor, jobs, n, len(work), scheduler))
    if not work:
        return _Local(None, fn, work, 1)
    if executor == "dask":
        return run_dask(fn, work, n, scheduler)
    if executor == "processes" and n > 1:
        return _Local(_Processes(n), fn, work, n)
    return _Local(_DaemonThreads(n), fn, work, n)  # serial: one thread, so that a signal is handled at once
