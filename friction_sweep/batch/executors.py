"""Where tiles run: in this process, in threads, in processes, or on a Dask cluster.

Every executor yields (tile index, result) as tiles complete. Results never depend on the executor:
a tile is a pure function of its inputs, and assembly places it by index.
"""

from __future__ import annotations

import logging
import signal
import threading
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, ThreadPoolExecutor, wait

log = logging.getLogger("friction_sweep")

EXECUTORS = ("threads", "processes", "dask", "serial")
#: chosen by measurement on 2 cores (README, make bench): threads share one compiled kernel and skip
#: process start-up; the kernels release the GIL
DEFAULT_EXECUTOR = "threads"


def run_serial(fn: Callable, work: list) -> Iterator[tuple[int, dict]]:
    for i, args in enumerate(work):
        yield i, fn(args)


def _run_pool(pool_cls, fn, work, jobs) -> Iterator[tuple[int, dict]]:
    with pool_cls(max_workers=jobs) as pool:
        pending = {pool.submit(fn, args): i for i, args in enumerate(work)}
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                yield pending.pop(fut), fut.result()


def run_threads(fn, work, jobs) -> Iterator[tuple[int, dict]]:
    """The numba kernels release the GIL (nogil), so threads share one process and one compiled copy."""
    return _run_pool(ThreadPoolExecutor, fn, work, jobs)


def run_processes(fn, work, jobs) -> Iterator[tuple[int, dict]]:
    return _run_pool(ProcessPoolExecutor, fn, work, jobs)


class DaskUnavailable(RuntimeError):
    """Dask cannot run the tiles: not installed, or the scheduler's address is wrong or unreachable."""


#: seconds to wait for a scheduler's port to answer before a run starts (Dask's own wait is 30 s)
CONNECT_TIMEOUT_S = 5.0


def check_dask(scheduler: str | None) -> None:
    """DaskUnavailable with the reason, unless Dask is installed and `scheduler` (if given) is a
    reachable tcp:// address. Cheap: no client is made."""
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
            greeting = conn.recv(1)
    except OSError as err:
        why = err.strerror or ("no answer" if isinstance(err, TimeoutError) else str(err) or type(err).__name__)
        raise DaskUnavailable(f"--scheduler: cannot reach the Dask scheduler at {scheduler}: {why}") from None
    if not greeting:
        raise DaskUnavailable(f"--scheduler: {scheduler} closed the connection at once: not a Dask scheduler")


def run_dask(fn, work, jobs, scheduler: str | None = None, retries: int = 3) -> Iterator[tuple[int, dict]]:
    """Tiles as Dask tasks: on `scheduler` (address) or on a LocalCluster of `jobs` workers.

    A worker that dies takes its tasks with it; the scheduler reassigns them (and `retries` covers
    tasks that raised), so every tile is computed once in the result.
    """
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    # Dask's own INFO lines and a worker's shutdown noise at Ctrl-C are not the user's business
    # unless they asked (-v): fsweep reports what happened in one line
    quiet = logging.INFO if log.isEnabledFor(logging.INFO) else logging.CRITICAL
    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(quiet)
    if scheduler is None:
        # Ctrl-C reaches the whole process group: the workers would each print a traceback. Started
        # with SIGINT ignored (inherited), they leave it to this process, which closes the cluster.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if _main_thread() else None
        try:
            cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=None,
                                   silence_logs=quiet)
        finally:
            if previous is not None:
                signal.signal(signal.SIGINT, previous)
        client = Client(cluster)
    else:
        client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s")
    log.info("dask: %s", client)
    try:
        futures = {client.submit(fn, args, pure=False, retries=retries): i for i, args in enumerate(work)}
        # as_completed waits on the *current* client's loop by default; inside a caller's
        # `with Client(...)` that is another loop than these futures' one (flaky "bound to a
        # different event loop" in fut.result()), so name ours
        for fut in as_completed(futures, loop=client.loop):
            yield futures[fut], fut.result()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def execute(fn, work: list, executor: str, jobs: int, scheduler: str | None = None) -> Iterable[tuple[int, dict]]:
    if not work:
        return iter(())
    if executor == "dask":
        return run_dask(fn, work, jobs, scheduler)
    if executor == "serial" or jobs <= 1 or len(work) == 1:
        return run_serial(fn, work)
    if executor == "threads":
        return run_threads(fn, work, jobs)
    if executor == "processes":
        return run_processes(fn, work, jobs)
    raise ValueError(f"unknown executor {executor!r} (known: {', '.join(EXECUTORS)})")
