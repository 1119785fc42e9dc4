"""A Dask cluster to run sweeps on: the scheduler at an address (machines
running ``dask scheduler`` and ``dask worker ADDRESS``, or dask-jobqueue on
Slurm), or ``local``: a LocalCluster of one single-threaded worker process
per core of this machine."""
from __future__ import annotations

import os

from pdbfs.errors import ParameterError, require_extra

#: how long to wait for a scheduler before saying it cannot be reached, s
CONNECT_TIMEOUT = 5.0


def connect(address: str, timeout: float = CONNECT_TIMEOUT, workers: int | None = None):
    """A dask.distributed Client for ``address`` ("local" or tcp://HOST:PORT)."""
    import logging

    require_extra("dask", "a sweep on a Dask cluster")
    from distributed import Client, LocalCluster
    if address == "local":
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
        n = workers or cores or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        return Client(cluster)
    probe(address, timeout)
    try:
        return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError, MemoryError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise ParameterError(f"cannot reach a Dask scheduler at {address!r} within "
                             f"{timeout:g} s ({first})") from None


#: a scheduler's first message (its handshake) is small; a larger length read
#: from a socket is something else talking (Dask would try to allocate it)
HANDSHAKE_MAX = 1 << 20


def probe(address: str, timeout: float = CONNECT_TIMEOUT) -> None:
    """For tcp:// addresses: a Dask scheduler answers a connection at once
    with a framed handshake (8 bytes of length, then the message). A server
    that says nothing, or something else, is refused within ``timeout``;
    Dask itself would wait without end or read a length of exabytes."""
    import socket
    import struct
    import time
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme != "tcp":
        return                   # tls and others: their own handshake; Dask's timeout holds
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")

    def fail(why):
        raise ParameterError(f"cannot reach a Dask scheduler at {address!r} within "
                             f"{timeout:g} s ({why})")
    try:
        port = int(port.split("/")[0])
    except ValueError:
        fail("expected tcp://HOST:PORT")
    deadline = time.monotonic() + timeout
    try:
        with socket.create_connection((host, port), timeout=timeout) as sock:
            head = b""
            while len(head) < 8:
                sock.settimeout(max(deadline - time.monotonic(), 1e-3))
                chunk = sock.recv(8 - len(head))
                if not chunk:
                    fail("the server closed the connection without a Dask handshake")
                head += chunk
    except socket.timeout:
        fail("the server there sends no Dask handshake: is it a Dask scheduler?")
    except OSError as err:
        fail(err.strerror or str(err))
    (n,) = struct.unpack("<Q", head)
    if not 0 < n <= HANDSHAKE_MAX:
        fail(f"the server there speaks another protocol (it began {head!r})")


def close(client):
    """Close a client, and its LocalCluster if it started one."""
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()
