"""The held-out diagnostics of saved checkpoints, as their training logged them at that step, including the
ones added since (mobilemani_vla.diagnostics):

    python -m mobilemani_vla.checkpoint_diagnostics outputs/demo/vla/checkpoints/step_00009000 [more ...]

One JSON line per checkpoint, on the held-out episodes of the dataset its config names.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.errors import InputError
from mobilemani_vla.data.dataset import open_data
from mobilemani_vla.diagnostics import diagnose, heldout_batch
from mobilemani_vla.inference import VLAPolicy


def checkpoint_diagnostics(checkpoint: Path) -> dict[str, float]:
    policy = VLAPolicy.load(checkpoint)
    cfg = policy.cfg
    data = open_data(cfg, policy.model.backbone.image_size, progress=False)
    if data.heldout is None:
        raise InputError(f"{checkpoint}: its config holds out no episodes (data.heldout_episodes=0)")
    batch = heldout_batch(data.heldout, cfg.train.diagnose_frames, policy.processor)
    return diagnose(policy.model, batch, cfg.train.diagnose_cfg_scales)


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("checkpoints", nargs="+", type=Path, help="checkpoint directories (step_*)")
    for checkpoint in parser.parse_args().checkpoints:
        print(json.dumps({"checkpoint": str(checkpoint), **checkpoint_diagnostics(checkpoint)}), flush=True)


if __name__ == "__main__":
    main()
