"""A Dask cluster to run sweeps on: the scheduler at an address (machines
running ``dask scheduler`` and ``dask worker ADDRESS``, or dask-jobqueue on
Slurm), or ``local``: a LocalCluster of one single-threaded worker process
per core of this machine."""
from __future__ import annotations

import os

from pdbfs.errors import ParameterError

#: how long to wait for a scheduler before saying it cannot be reached, s
CONNECT_TIMEOUT = 5.0


def connect(address: str, timeout: float = CONNECT_TIMEOUT, workers: int | None = None):
    """A dask.distributed Client for ``address`` ("local" or tcp://HOST:PORT)."""
    import logging

    from distributed import Client, LocalCluster
    if address == "local":
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
        n = workers or cores or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        return Client(cluster)
    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise ParameterError(f"cannot reach the Dask scheduler at {address!r} within "
                             f"{timeout:g} s ({first})") from None


def close(client):
    """Close a client, and its LocalCluster if it started one."""
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()
