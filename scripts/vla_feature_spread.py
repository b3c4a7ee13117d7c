"""Whether trained VLAs' backbones still read their inputs: the held-out diagnostics' `cognition_spread` on
evenly spaced frames of the dataset they trained on (how much the cognition feature varies from frame to
frame, and how much it moves when the frames' images are swapped, relative to its size). A backbone whose
feature no longer depends on its input (spread 0) leaves the action head only the state.

    python -m scripts.vla_feature_spread --data outputs/demo/data/lerobot \
        outputs/demo/vla/checkpoints/step_00009000
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from mobilemani_vla.data.dataset import open_data
from mobilemani_vla.diagnostics import cognition_spread
from mobilemani_vla.inference import VLAPolicy


def feature_spread(policy: VLAPolicy, data_root: str, frames: int) -> dict[str, float]:
    policy.cfg.data.root = data_root
    dataset = open_data(policy.cfg, policy.model.backbone.image_size, progress=False).train
    picks = np.linspace(0, len(dataset) - 1, frames).round().astype(int)
    return cognition_spread(policy.model, policy.processor([dataset[int(i)] for i in picks]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoints", nargs="+", help="VLA checkpoint directories")
    parser.add_argument("--data", required=True, help="the LeRobot dataset the VLAs trained on")
    parser.add_argument("--frames", type=int, default=256)
    args = parser.parse_args()
    for checkpoint in args.checkpoints:
        spread = feature_spread(VLAPolicy.load(checkpoint), args.data, args.frames)
        rounded = {key: round(value, 4) for key, value in spread.items()}
        print(json.dumps({"checkpoint": checkpoint, **rounded}), flush=True)


if __name__ == "__main__":
    main()
