"""Independent work items spread over worker processes (evaluation blocks, collection combinations).

Workers start with `spawn` (a fresh interpreter: no forked EGL contexts, CUDA state or torch thread pools),
each with an equal share of the CPU's threads, and build their state once (e.g. a policy). An item's result
must not depend on which worker runs it; the caller stays the only writer of any file the items share.

Stopping: the workers are terminated as soon as the caller stops, whether it finished, failed or was
interrupted; Ctrl-C reaches only the caller (workers ignore SIGINT), which then stops them. A worker whose
caller is gone (killed with SIGKILL, which no handler sees) exits within a second instead of running on and
racing a rerun for the same files. An item cut short leaves only what its task writes atomically.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from typing import Any

import torch

_worker: dict[str, Any] = {}


def threads_per_worker(workers: int) -> int:
    """Each worker's share of the CPU's threads: oversubscribed cores would slow every worker down."""
    return max(1, (os.cpu_count() or 1) // workers)


def _exit_when_orphaned(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


def _start_worker(task: Callable, make_state: Callable[[], Any] | None, threads: int, parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C signals the whole process group
    # The caller's pid comes from the caller: a worker still importing when the caller was killed would read
    # its new parent from os.getppid(), never see itself orphaned, and wait on the dead caller's queue
    # forever.
    threading.Thread(target=_exit_when_orphaned, args=(parent,), daemon=True).start()
    torch.set_num_threads(threads)
    _worker.update(task=task, state=make_state() if make_state else None)


def _run_in_worker(item: Any) -> Any:
    return _worker["task"](_worker["state"], item)


def run_in_pool[Item, Result](
    task: Callable[[Any, Item], Result],
    items: Sequence[Item],
    workers: int,
    make_state: Callable[[], Any] | None = None,
    local_state: Any = None,
) -> Iterator[tuple[Item, Result]]:
    """Each item with `task(state, item)`, in the order they finish. With more than one worker (and item),
    every worker builds `state` once with `make_state()` (None without it), and `task`, `make_state` and the
    items must pickle (module-level functions, partials of them, dataclasses); otherwise the items run here,
    in order, on `local_state`. A failing item stops the pool and raises in the caller; items not yet finished
    are dropped, so a rerun runs them."""
    workers = min(workers, len(items))  # no idle processes, and their threads go to the busy ones
    if workers <= 1:
        yield from ((item, task(local_state, item)) for item in items)
        return
    pool = ProcessPoolExecutor(
        workers,
        get_context("spawn"),
        initializer=_start_worker,
        initargs=(task, make_state, threads_per_worker(workers), os.getpid()),
    )
    futures: dict[Future, Item] = {pool.submit(_run_in_worker, item): item for item in items}
    try:
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        # Python 3.14's terminate_workers(): without it, an interrupted caller would wait for every item
        # already queued to a worker (minutes of evaluation) before it exits.
        for process in list((pool._processes or {}).values()):
            process.terminate()
        pool.shutdown(wait=True, cancel_futures=True)
