"""`inputs.grasp_point_noise`: training frames get a fresh error on the grasp point input only; the evaluator
gives each episode one world-frame offset, whatever the base does."""

import numpy as np
import torch

from mobilemani_data import schema
from mobilemani_rl.envs.base_frame import points_to_base
from mobilemani_rl.utils.rotations import quat_apply
from mobilemani_vla.eval.policies.vla import GraspPointError
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.processor import VLAProcessor
from mobilemani_vla.model.tokenizer import build_word_tokenizer

STD = 0.05


def _processor(noise: float) -> VLAProcessor:
    # grasp-point bounds [-1, 3]: normalised = point / 2 - 0.5, and no error reaches the clip
    bounds = {
        schema.ACTION: ([-1.0] * 7, [1.0] * 7),
        schema.STATE: ([-2.0] * 10, [2.0] * 10),
        schema.GRASP_POINT_BASE: ([-1.0] * 3, [3.0] * 3),
    }
    states, targets = ["wrist_pose", "grasp_point"], ["grasp_point"]
    return VLAProcessor(
        build_word_tokenizer(), Normalizer(bounds), ["head_rgb"], states, 32, "{instruction}", targets, noise
    )


def _frames(n: int) -> list[dict]:
    rng = np.random.default_rng(0)
    return [
        {
            "observation.images.head_rgb": torch.zeros(3, 8, 8),
            schema.STATE: torch.as_tensor(rng.normal(size=10), dtype=torch.float32),
            schema.GRASP_POINT_BASE: torch.as_tensor(rng.uniform(0.5, 1.5, 3), dtype=torch.float32),
            schema.ACTION: torch.zeros(16, 7),
            f"{schema.ACTION}_is_pad": torch.zeros(16, dtype=torch.bool),
            "task": "open box",
        }
        for _ in range(n)
    ]


def test_training_frames_get_a_fresh_grasp_point_error_on_the_input_only():
    frames = _frames(3000)
    torch.manual_seed(0)
    noisy, exact = _processor(STD)(frames), _processor(0.0)(frames)
    wrist = slice(0, 9)
    assert torch.equal(noisy["state"][:, wrist], exact["state"][:, wrist])
    assert torch.equal(noisy["cognition_target"], exact["cognition_target"])  # the target stays exact
    error = 2 * (noisy["state"][:, 9:] - exact["state"][:, 9:])  # back to metres
    assert abs(error.mean().item()) < 0.005
    assert np.allclose(error.std(dim=0).numpy(), STD, rtol=0.05)
    assert torch.corrcoef(error.T).abs().fill_diagonal_(0).max() < 0.1  # each axis drawn on its own
    # a second batch draws again
    assert not torch.equal(_processor(STD)(frames[:8])["state"], _processor(STD)(frames[:8])["state"])


def test_live_observations_are_not_perturbed_by_the_processor():
    """The evaluator adds its own per-episode error; the processor's collate leaves live inputs as given."""
    frames = _frames(4)
    batch = {k: torch.stack([f[k] for f in frames]) for k in frames[0] if k != "task"}
    batch["task"] = ["open box"] * 4
    assert torch.equal(_processor(STD).collate(batch)["state"], _processor(0.0).collate(batch)["state"])


def test_the_evaluators_error_is_one_world_offset_per_episode_wherever_the_base_goes():
    n, rng = 64, np.random.default_rng(1)
    error = GraspPointError(STD, n, seed=7)
    grasp_world = rng.uniform(-1, 1, (n, 3))
    for _ in range(3):  # the base moves and turns between steps
        yaw = rng.uniform(-np.pi, np.pi, n)
        base_quat = np.stack([np.cos(yaw / 2), 0 * yaw, 0 * yaw, np.sin(yaw / 2)], axis=-1)
        base_pos = rng.uniform(-2, 2, (n, 3))
        seen = error(points_to_base(grasp_world, base_pos, base_quat), base_quat)
        # the point the policy is given, back in the world: the true point plus the episode's fixed offset
        world = base_pos + quat_apply(base_quat, seen)
        assert np.allclose(world - grasp_world, error.offsets, atol=1e-5)
    assert np.array_equal(error.offsets, GraspPointError(STD, n, seed=7).offsets)  # reproducible per seed
    assert 0.03 < error.offsets.std() < 0.07
    assert not GraspPointError(0.0, n, seed=7).offsets.any()
