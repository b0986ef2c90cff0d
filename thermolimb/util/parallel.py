"""Run independent jobs serially, over a local process pool, or as Ray tasks; the results come back in job
order.

Each job is a tuple of arguments to one module-level function, so that the
same call runs in this process, in a worker process or on a Ray worker, and
gives the same result in each.  :class:`Runner` keeps a pool (or a Ray
connection) open across several maps; :func:`run_jobs` is one map.

Local workers never outlive the command: they leave Ctrl-C to the parent
(a terminal sends it to every process of the group), die with the parent
(Linux's parent-death signal), and are ended by the parent when it leaves a
map by an interrupt or an error, whatever the timing of further signals.
Their number is bounded by the cores and the memory available
(:func:`worker_limit`).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import socket
import sys
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Callable, Iterator, Sequence

from .errors import UsageError
from .interrupts import check, held

BACKENDS = ("process", "ray", "serial")
RAY_CONNECT_TIMEOUT_S = 10.0
# what one local worker takes once it has imported the suite and holds a fit or a PyBullet world
# (150-170 MB measured for a fleet fit; a hexapod world is in the same range), with some room
WORKER_MEMORY_BYTES = 250e6
PR_SET_PDEATHSIG = 1  # prctl(2)
STOP_GRACE_S = 5.0  # a worker ended by SIGTERM that is still there after this is killed


def worker_limit(requested: int) -> tuple[int, str | None]:
    """The local workers this machine can run of ``requested``, and a sentence saying why when fewer.

    Bounded by the cores this process may use and by the memory available
    (the cgroup's limit where there is one: a container's, a CI job's), at
    :data:`WORKER_MEMORY_BYTES` each: more workers than cores only queue, and
    more than the memory holds get the command killed without a word.
    """
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    memory = available_memory_bytes()
    by_memory = requested if memory is None else max(1, int(memory // WORKER_MEMORY_BYTES))
    count = max(1, min(requested, cores, by_memory))
    if count == requested:
        return count, None
    held = f"{memory / 1e9:.1f} GB of memory available" if memory is not None else "memory not known"
    return count, (f"--workers {requested} lowered to {count}: this "
                   f"machine gives the command {cores} core(s) and "
                   f"{held} (about {WORKER_MEMORY_BYTES / 1e6:.0f} MB per worker)")


def available_memory_bytes() -> float | None:
    """Memory this process can still take: the system's available memory, or its cgroup's room if smaller."""
    found = []
    with contextlib.suppress(OSError, ValueError):
        for line in open("/proc/meminfo"):
            if line.startswith("MemAvailable:"):
                found.append(float(line.split()[1]) * 1024)
    for limit, usage in (("memory.max", "memory.current"),  # cgroup v2, then v1
                         ("memory/memory.limit_in_bytes", "memory/memory.usage_in_bytes")):
        with contextlib.suppress(OSError, ValueError):  # no such cgroup file, or "max": no limit there
            room = float(open(f"/sys/fs/cgroup/{limit}").read()) - float(
                open(f"/sys/fs/cgroup/{usage}").read()
            )
            if room < 2 ** 60:
                found.append(max(room, 0.0))
    return min(found) if found else None


_SHARED = None  # what a runner's ``shared`` gave this process: sent once to each worker, not with every job


def shared():
    """The ``shared`` value of the runner running this job (:class:`Runner`): data every job reads, such as
    the log a stability check perturbs, sent to each local worker once instead of in every job."""
    return _SHARED


def _worker_start(parent: int, value=None) -> None:
    """Each local worker: Ctrl-C is the parent's to answer, and the worker dies when the parent does."""
    global _SHARED
    _SHARED = value
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent:  # the parent died before the death signal was set
        os._exit(1)


def check_ray_address(address: str | None, timeout_s: float = RAY_CONNECT_TIMEOUT_S) -> None:
    """Refuse, within ``timeout_s``, a Ray address ``[ray://]host:port`` where nothing answers (Ray would
    wait)."""
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
    """A backend held open: ``with Runner("process", 2) as r: r.map(func, jobs)``.  ``shared``: a value every
    job reads by :func:`shared` (local backends only), sent once to each worker."""

    def __init__(self, backend: str = "process", workers: int = 2, address: str | None = None, shared=None):
        if backend not in BACKENDS:
            raise UsageError(f"backend must be one of {', '.join(BACKENDS)}, got {backend!r}")
        if shared is not None and backend == "ray":
            raise UsageError("a runner's shared value is for the local backends (process, serial), not ray")
        self.backend, self.workers, self.address, self.shared = backend, workers, address, shared
        self._pool = None
        self._ray = None
        self._started_ray = False

    def __enter__(self) -> "Runner":
        global _SHARED
        self._before, _SHARED = _SHARED, self.shared  # serially, the jobs run here
        if self.backend == "process":
            self.workers = worker_limit(self.workers)[0]
            self._pool = ProcessPoolExecutor(max_workers=self.workers, initializer=_worker_start,
                                             initargs=(os.getpid(), self.shared))
        elif self.backend == "ray":
            try:
                import ray
            except ImportError:
                raise UsageError("the ray backend needs Ray: pip install 'thermolimb[ray]'") from None
            check_ray_address(self.address)
            self._started_ray = not ray.is_initialized()
            ray.init(address=self.address, ignore_reinit_error=True, include_dashboard=False,
                     log_to_driver=False)
            self._ray = ray
        return self

    def __exit__(self, exc_type, *exc) -> None:
        global _SHARED
        _SHARED = self._before
        if self._pool is not None:
            if exc_type is None:
                self._pool.shutdown()
            else:
                _end_pool(self._pool)
        if self._ray is not None and self._started_ray:
            self._ray.shutdown()

    def map(self, func: Callable, jobs: Sequence[tuple]) -> list:
        """``[func(*job) for job in jobs]`` on this runner's backend."""
        if not jobs:
            return []
        # waited for a second at a time, as as_completed does (a lost signal's raise)
        if self._pool is not None:
            out = [None] * len(jobs)
            for i, result in self.as_completed(func, jobs):
                out[i] = result
            return out
        if self._ray is not None:
            remote = self._ray.remote(func)
            return self._ray.get([remote.remote(*job) for job in jobs])
        return [func(*job) for job in jobs]

    def as_completed(self, func: Callable, jobs: Sequence[tuple]) -> Iterator[tuple[int, object]]:
        """``(index, func(*jobs[index]))`` as each job finishes, submitted in the order given (put the longest
        first: the pool then finishes soonest).  Serially and on Ray, in job order."""
        if self._ray is not None:
            yield from enumerate(self.map(func, jobs))
            return
        if self._pool is None:
            for i, job in enumerate(jobs):
                yield i, func(*job)
            return
        pending = {self._pool.submit(func, *job): i for i, job in enumerate(jobs)}
        while pending:
            # a signal whose raise was lost inside a library ends the wait within a second (util/interrupts)
            check()
            done, _ = wait(pending, timeout=1.0, return_when=FIRST_COMPLETED)
            for future in sorted(done, key=pending.get):
                yield pending.pop(future), future.result()


def _end_pool(pool: ProcessPoolExecutor) -> None:
    """Cancel what is queued and end the workers now (an interrupt or an error left the map).

    Python 3.11's pool has no public call that ends running workers (3.14 adds
    ``terminate_workers``), so its process table is read.  Further Ctrl-C or
    SIGTERM wait until the workers are gone, so that no timing of repeated
    signals can leave a worker behind or the pool's threads waiting on one.
    """
    with held():
        processes = list((pool._processes or {}).values())
        manager = getattr(pool, "_executor_manager_thread", None)  # shutdown forgets it
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        for process in processes:
            process.join(STOP_GRACE_S)
            if process.is_alive():
                process.kill()
                process.join()
        # the pool's manager thread sees its workers gone and closes its wake-up pipe: waited for here, or the
        # interpreter's exit hook can write to that pipe as it closes ("Exception ignored ... Bad file
        # descriptor", a race in Python 3.11's pool between its wake-up's check and its write)
        if manager is not None:
            manager.join(STOP_GRACE_S)


# One BLAS thread per job where the parallelism is across jobs: two workers of two BLAS threads each
# oversubscribe two cores, and OpenBLAS's waiting threads then spin (a 7200 x 12 SVD: 3 ms alone, 17-56 ms
# beside a busy core; the UR3 J5 walk's stability replicates took 37.0 s against 28.1 s with one thread,
# medians of five alternated runs). A fixed count also keeps every sum in the same order: a job gives the same
# bits on every backend.
BLAS_THREADS = 1
_CONTROLLER = None


def one_blas_thread():
    """A context limiting BLAS to :data:`BLAS_THREADS` (the loaded libraries are scanned once per process).

    SciPy's LAPACK is an OpenBLAS of its own, beside NumPy's, loaded with :mod:`scipy.linalg`: it is loaded
    here before the scan, or a scan made before a command's first fit (the command line imports its modules
    lazily) misses it, and its solvers keep two threads each.  Two workers' SVDs then took 30 ms where they
    take 0.4 ms (UR3 J5's refits: 5.9 s pooled against 3.5 s here, before this import).
    """
    global _CONTROLLER
    if _CONTROLLER is None:
        import scipy.linalg  # noqa: F401  (its OpenBLAS, for the scan)
        from threadpoolctl import ThreadpoolController

        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=BLAS_THREADS)


def with_one_blas_thread(func: Callable, *args):
    """``func(*args)`` with one BLAS thread: as a job ``(func, *args)`` of :func:`run_jobs`, alike on any
    backend."""
    with one_blas_thread():
        return func(*args)


def run_jobs(func: Callable, jobs: Sequence[tuple], backend: str = "process", workers: int = 2,
             address: str | None = None, shared=None) -> list:
    """``[func(*job) for job in jobs]`` on the chosen backend (``process``, ``ray`` or ``serial``);
    ``shared``: see :class:`Runner`."""
    with Runner(backend, workers, address, shared) as runner:
        return runner.map(func, jobs)
