"""Milliseconds per `predict_action_chunks` call of a VLA checkpoint: 5 envs, random 128 px images, 1 thread.

python docs/results/eval_paper_protocol/mask_memo/chunk_latency.py <checkpoint directory>
"""

import sys
import time

import numpy as np
import torch

from mobilemani_vla.policy import VLAPolicy

torch.set_num_threads(1)
policy = VLAPolicy.load(sys.argv[1])
envs = 5
rng = np.random.default_rng(0)
images = {c: rng.integers(0, 255, (envs, 128, 128, 3), dtype=np.uint8) for c in policy.cameras}
widths = {k: policy.processor.normalizer.bounds[k][0].shape[-1] for k in policy.vector_inputs}
vectors = {k: np.zeros((envs, width), np.float32) for k, width in widths.items()}


def chunk() -> np.ndarray:
    noise = torch.Generator().manual_seed(0)
    return policy.predict_action_chunks(images, ["open the box"] * envs, vectors, noise)


for _ in range(4):  # warm-up
    chunk()
calls = 20
start = time.perf_counter()
for _ in range(calls):
    chunk()
print("ms per call", round((time.perf_counter() - start) / calls * 1000, 1))
