"""Evaluation blocks spread over worker processes (`workers` > 1).

Every block's env seed and policy seed come from its combination and index (evaluate.batch_seed), so a block's
episodes do not depend on which process runs it or in what order; the parent stays the results file's only
writer. Workers start with `spawn` (a fresh interpreter: no forked EGL contexts, CUDA state or torch thread
pools) and build their own policy from the config, each on its share of the CPU's threads.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from typing import Any

import torch

from mobilemani_rl.tasks import Combination

Block = tuple[int, Combination, int]  # (combination index, combination, block index)
BlockRunner = Callable[[Any, Any, Combination, int], list[dict]]  # (cfg, policy, combination, block)

_worker: dict[str, Any] = {}


def _start_worker(run: BlockRunner, cfg: Any, make_policy: Callable[[], Any], threads: int) -> None:
    torch.set_num_threads(threads)
    _worker.update(run=run, cfg=cfg, policy=make_policy())


def _run_in_worker(combo: Combination, block: int) -> list[dict]:
    return _worker["run"](_worker["cfg"], _worker["policy"], combo, block)


def run_blocks_in_pool(
    run: BlockRunner, cfg: Any, make_policy: Callable[[], Any], blocks: Sequence[Block], workers: int
) -> Iterator[tuple[Block, list[dict]]]:
    """Each block with its records, in the order they finish. `run`, `cfg` and `make_policy` must pickle
    (module-level functions, dataclasses). A failing block stops the pool and raises in the caller; blocks
    not yet started are dropped, so a rerun runs them."""
    workers = max(1, min(workers, len(blocks)))  # no idle processes, and their threads go to the busy ones
    threads = max(1, (os.cpu_count() or 1) // workers)
    pool = ProcessPoolExecutor(
        workers, get_context("spawn"), initializer=_start_worker, initargs=(run, cfg, make_policy, threads)
    )
    futures: dict[Future, Block] = {pool.submit(_run_in_worker, b[1], b[2]): b for b in blocks}
    try:
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
