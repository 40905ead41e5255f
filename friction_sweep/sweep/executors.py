"""Where tiles run: in this process, in threads, in processes, or on a Dask cluster.

Every executor yields (tile index, result) as tiles complete. Results never depend on the executor:
a tile is a pure function of its inputs, and assembly places it by index.
"""

from __future__ import annotations

import logging
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, ThreadPoolExecutor, wait
from typing import Callable, Iterable, Iterator

log = logging.getLogger("friction_sweep")

EXECUTORS = ("serial", "threads", "processes", "dask")


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


def run_dask(fn, work, jobs, scheduler: str | None = None, retries: int = 3) -> Iterator[tuple[int, dict]]:
    """Tiles as Dask tasks: on `scheduler` (address) or on a LocalCluster of `jobs` workers.

    A worker that dies takes its tasks with it; the scheduler reassigns them (and `retries` covers
    tasks that raised), so every tile is computed once in the result.
    """
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    else:
        client = Client(scheduler)
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
