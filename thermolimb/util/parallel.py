"""Run independent jobs serially, over a local process pool, or as Ray tasks; the results come back in job order.

Each job is a tuple of arguments to one module-level function, so that the
same call runs in this process, in a worker process or on a Ray worker, and
gives the same result in each.  :class:`Runner` keeps a pool (or a Ray
connection) open across several maps; :func:`run_jobs` is one map.
"""

from __future__ import annotations

import socket
from concurrent.futures import ProcessPoolExecutor
from typing import Callable, Sequence

from .errors import UsageError

BACKENDS = ("process", "ray", "serial")
RAY_CONNECT_TIMEOUT_S = 10.0


def check_ray_address(address: str | None, timeout_s: float = RAY_CONNECT_TIMEOUT_S) -> None:
    """Refuse, within ``timeout_s``, a Ray address ``[ray://]host:port`` where nothing answers (Ray would wait)."""
    if address in (None, "auto", "local"):
        return
    host, sep, port = address.removeprefix("ray://").rpartition(":")
    if not sep or not port.isdigit():
        raise UsageError(f"--address {address!r}: expected HOST:PORT (or ray://HOST:PORT, or 'auto')")
    try:
        socket.create_connection((host, int(port)), timeout=timeout_s).close()
    except OSError as exc:
        raise UsageError(f"no Ray cluster answers at {address} (tried for {timeout_s:g} s: {exc})") from None


class Runner:
    """A backend held open: ``with Runner("process", 2) as r: r.map(func, jobs)``."""

    def __init__(self, backend: str = "process", workers: int = 2, address: str | None = None):
        if backend not in BACKENDS:
            raise UsageError(f"backend must be one of {', '.join(BACKENDS)}, got {backend!r}")
        self.backend, self.workers, self.address = backend, workers, address
        self._pool = None
        self._ray = None
        self._started_ray = False

    def __enter__(self) -> "Runner":
        if self.backend == "process":
            self._pool = ProcessPoolExecutor(max_workers=self.workers)
        elif self.backend == "ray":
            try:
                import ray
            except ImportError:
                raise UsageError("the ray backend needs Ray: pip install 'thermolimb[ray]'") from None
            check_ray_address(self.address)
            self._started_ray = not ray.is_initialized()
            ray.init(address=self.address, ignore_reinit_error=True, include_dashboard=False, log_to_driver=False)
            self._ray = ray
        return self

    def __exit__(self, *exc) -> None:
        if self._pool is not None:
            self._pool.shutdown()
        if self._ray is not None and self._started_ray:
            self._ray.shutdown()

    def map(self, func: Callable, jobs: Sequence[tuple]) -> list:
        """``[func(*job) for job in jobs]`` on this runner's backend."""
        if not jobs:
            return []
        if self._pool is not None:
            return list(self._pool.map(func, *zip(*jobs)))
        if self._ray is not None:
            remote = self._ray.remote(func)
            return self._ray.get([remote.remote(*job) for job in jobs])
        return [func(*job) for job in jobs]


def run_jobs(func: Callable, jobs: Sequence[tuple], backend: str = "process", workers: int = 2,
             address: str | None = None) -> list:
    """``[func(*job) for job in jobs]`` on the chosen backend (``process``, ``ray`` or ``serial``)."""
    with Runner(backend, workers, address) as runner:
        return runner.map(func, jobs)
