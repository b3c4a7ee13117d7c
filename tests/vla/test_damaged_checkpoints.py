"""VLA checkpoints that cannot be used are named: a copy cut short (training resumes from the previous one),
one from an older dataset layout."""

import pytest
import torch


def test_a_checkpoint_from_an_older_dataset_layout_is_refused_by_name():
    from mobilemani_vla.model.normalizer import Normalizer
    from mobilemani_vla.model.processor import VLAProcessor
    from mobilemani_vla.model.tokenizer import build_word_tokenizer

    old_bounds = Normalizer(
        {"action": ([-1.0] * 7, [1.0] * 7), "observation.wrist_pose_base": ([-1.0] * 9, [1.0] * 9)}
    )
    with pytest.raises(KeyError, match=r"no \['observation.state'\].*older dataset layout"):
        VLAProcessor(build_word_tokenizer(), old_bounds, ["head_rgb"], ["wrist_pose"], 32, "{instruction}")


@pytest.mark.parametrize("damaged_name", ["model.safetensors", "optimizer.bin", "random_states_0.pkl"])
def test_a_damaged_vla_checkpoint_is_named_and_training_resumes_from_the_previous_one(
    damaged_name, tmp_path, capsys
):
    import json

    from safetensors.torch import save_file

    from mobilemani_vla.checkpoint import check_weights, checkpoint_dir
    from mobilemani_vla.config import VLACfg, vla_cfg_to_yaml
    from mobilemani_vla.train import _resume_point

    cfg = VLACfg()
    for step in (1, 2):
        directory = checkpoint_dir(tmp_path, step)
        directory.mkdir(parents=True)
        (directory / "config.yaml").write_text(vla_cfg_to_yaml(cfg))
        (directory / "trainer_state.json").write_text(json.dumps({"step": step}))
        save_file({"w": torch.zeros(64)}, str(directory / "model.safetensors"))
        for state in ("optimizer.bin", "random_states_0.pkl"):  # accelerate's torch.save archives
            torch.save({"step": torch.tensor(step), "w": torch.zeros(64)}, directory / state)
    damaged = checkpoint_dir(tmp_path, 2) / damaged_name
    damaged.write_bytes(damaged.read_bytes()[:40])  # a copy cut short
    if damaged.suffix == ".safetensors":  # evaluation needs only the weights
        with pytest.raises(ValueError, match=f"unreadable checkpoint weights {damaged}"):
            check_weights(damaged.parent)
    assert _resume_point(cfg, tmp_path) == checkpoint_dir(tmp_path, 1)
    assert f"skipping an unreadable checkpoint: {damaged}" in capsys.readouterr().out
