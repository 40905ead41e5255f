"""Dask: a worker that dies mid-sweep has its tiles recomputed; the result is unchanged."""

import os
import signal

import numpy as np
import pytest

from friction_sweep.batch import executors
from friction_sweep.batch.runner import compute_tile, tiles

distributed = pytest.importorskip("dask.distributed")


@pytest.mark.slow
def test_a_worker_that_dies_has_its_tiles_recomputed():
    r = np.linspace(0.1, 3.0, 32 * 12)
    beta = np.array([0.0, 0.2, 0.5, 0.9])
    work = [("event", "base", r[s], beta, ("transmissibility", "regime"), {}, {}, None) for s in tiles(r.size)]
    reference = {i: compute_tile(args) for i, args in enumerate(work)}

    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    try:
        with distributed.Client(cluster) as watcher:
            pids = list(watcher.run(os.getpid).values())
            results = {}
            killed = False
            for i, tile in executors.run_dask(compute_tile, work, 2, scheduler=cluster.scheduler_address):
                results[i] = tile
                if not killed:  # the first tile is back: the workers hold the others; kill one of them
                    os.kill(pids[0], signal.SIGKILL)
                    killed = True
        assert killed and sorted(results) == list(range(len(work)))
        for i, tile in results.items():
            for name in tile:
                np.testing.assert_array_equal(tile[name], reference[i][name])
    finally:
        cluster.close()
