"""The batch's executors: a local pool of worker processes (LocalPool) and an existing Dask cluster (DaskPool).
Both run one task (a module-level function of a job dict returning its summary row: ruled.batch.batch.run_face)
and make a row of a job whose task crashed or ran past the timeout with ``failed(job, reason, seconds)``; a local
worker first runs ``warm()`` (the task's start-up, while the batch plans), where given."""

from __future__ import annotations

import contextlib
import os
import sys
import time
from typing import Callable, Optional

from ruled.core.errors import BadInputError


def _worker(conn, threads: int, task: Callable, warm: Optional[Callable]) -> None:
    """A pool process: warm(), then the task on the jobs it is sent, one at a time, until it receives None; its
    kernels use `threads` threads (the cores shared among the workers), or fewer where the caller's environment
    caps them (RULED_THREADS=1 and the like: a batch started beside other work)."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)         # Ctrl-C is the parent's to handle
    for name in ("RULED_THREADS", "NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        given = os.environ.get(name, "")
        os.environ[name] = str(min(threads, int(given)) if given.isdigit() and int(given) > 0 else threads)
    if warm is not None:
        with contextlib.suppress(Exception):     # (nothing of it is needed: the first task would do it)
            warm()
    while True:
        job = conn.recv()
        if job is None:        # done: out at once (its outputs are closed; tearing its modules down took 0.8 s)
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(0)
        try:
            conn.send(("row", task(job)))
        except BaseException as exc:  # a crash in the task: the parent records the face as failed
            conn.send(("error", f"{type(exc).__name__}: {exc}"))


class LocalPool:
    """N worker processes; a worker whose face crashes it or runs past the timeout is replaced."""

    def __init__(self, jobs: int, timeout: float, task: Callable, failed: Callable, warm: Optional[Callable] = None):
        import multiprocessing as mp
        self.ctx = mp.get_context("spawn")
        self.n, self.timeout, self.task, self.failed, self.warm = jobs, timeout, task, failed, warm
        self.workers: list = []

    def _start(self):
        a, b = self.ctx.Pipe()
        threads = max(1, (os.cpu_count() or 1) // self.n)
        p = self.ctx.Process(target=_worker, args=(b, threads, self.task, self.warm), daemon=True)
        p.start()
        return {"proc": p, "conn": a, "job": None, "t0": 0.0}

    def start(self, count: int) -> None:
        """count workers started now (each loads what a face needs while the batch plans the faces)."""
        self.workers += [self._start() for _ in range(count - len(self.workers))]

    def run(self, jobs: list, on_row) -> None:
        pending = list(jobs)
        self.start(min(self.n, len(pending)))
        busy = 0
        while pending or busy:
            for w in self.workers:
                if w["job"] is None and pending:
                    w["job"], w["t0"] = pending.pop(0), time.perf_counter()
                    w["conn"].send(w["job"])
                    busy += 1
            time.sleep(0.02)
            for i, w in enumerate(self.workers):
                if w["job"] is None:
                    continue
                job, dt = w["job"], time.perf_counter() - w["t0"]
                row = None
                if w["conn"].poll():
                    try:
                        kind, what = w["conn"].recv()
                        row = what if kind == "row" else self.failed(job, f"crashed: {what}", dt)
                    except (EOFError, OSError):
                        row = self.failed(job, "crashed: its worker process died", dt)
                elif not w["proc"].is_alive():
                    row = self.failed(job, f"crashed: its worker process died (exit code {w['proc'].exitcode})", dt)
                elif dt > self.timeout:
                    row = self.failed(job, f"ran past --face-timeout {self.timeout:g} s", dt)
                if row is None:
                    continue
                if row["status"] == "failed":     # the worker is replaced
                    w["proc"].kill()
                    self.workers[i] = self._start()
                else:
                    w["job"] = None
                busy -= 1
                on_row(row)

    def close(self) -> None:
        """Idle workers are told to stop; busy ones (an interrupted batch) are killed."""
        for w in self.workers:
            try:
                if w["job"] is None and w["proc"].is_alive():
                    w["conn"].send(None)
                else:
                    w["proc"].kill()
            except OSError:
                w["proc"].kill()
        end = time.perf_counter() + 5.0
        for w in self.workers:
            w["proc"].join(max(0.0, end - time.perf_counter()))
            if w["proc"].is_alive():
                w["proc"].kill()
        self.workers = []


class DaskPool:
    """The same face task on an existing Dask distributed cluster (``ruled[dask]``)."""

    def __init__(self, address: str, timeout: float, task: Callable, failed: Callable):
        try:
            from distributed import Client
        except ImportError:
            raise BadInputError("--scheduler needs Dask: pip install 'ruled[dask]'") from None
        try:
            self.client = Client(address, timeout=5)
        except (OSError, TimeoutError) as exc:
            raise BadInputError(f"cannot reach the Dask scheduler {address} ({exc}); check the address") from None
        self.timeout, self.task, self.failed = timeout, task, failed

    def run(self, jobs: list, on_row) -> None:
        """No more faces in flight than the cluster has threads, so that a face's clock starts when it
        starts; a face past --face-timeout is recorded as failed and the batch goes on (Dask cannot stop
        a running task: its thread is counted busy until the face ends, its result then dropped)."""
        from distributed import wait
        slots = max(1, sum(self.client.nthreads().values()))
        pending = list(jobs)
        running: dict = {}
        overdue: set = set()
        while pending or running:
            overdue = {f for f in overdue if not f.done()}
            while pending and len(running) + len(overdue) < slots:
                job = pending.pop(0)
                running[self.client.submit(self.task, job, pure=False)] = (job, time.perf_counter())
            try:
                done = wait(list(running), timeout=0.25, return_when="FIRST_COMPLETED").done
            except TimeoutError:
                done = ()
            for f in done:
                job, t0 = running.pop(f)
                try:
                    on_row(f.result())
                except Exception as exc:  # the task raised on its worker (or the worker died): the face failed
                    on_row(self.failed(job, f"crashed: {type(exc).__name__}: {exc}", time.perf_counter() - t0))
            now = time.perf_counter()
            for f, (job, t0) in list(running.items()):
                if now - t0 > self.timeout:
                    running.pop(f)
                    overdue.add(f)
                    on_row(self.failed(job, f"ran past --face-timeout {self.timeout:g} s", now - t0))

    def start(self, count: int) -> None:
        """(The cluster's workers run already.)"""

    def close(self) -> None:
        self.client.close()
