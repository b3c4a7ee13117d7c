"""Combinations, instructions, shards of work,
and the Hydra tree converting to the dataclasses (no simulation)."""

import numpy as np
import pytest
from data_helpers import CONF, tiny_cfg
from hydra import compose, initialize_config_dir
from omegaconf.errors import ConfigKeyError

from mobilemani_data.combos import shard_of, shard_path
from mobilemani_data.config import DataCfg, ShardCfg, SubsetCfg
from mobilemani_data.convert import episode_vectors
from mobilemani_data.shards import FRAME_KEYS, Episode
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.envs.tasks import instruction, select_combinations
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import UnknownNameError


@pytest.mark.parametrize(
    ("skill", "category", "text"),
    [
        ("open", "washing_machine", "open washing machine"),
        ("open", "lever_door", "open door"),
        ("close", "round_door", "close door"),
        ("pull", "cart", "pull cart"),
        ("pick", "holistic", "pick object"),
    ],
)
def test_instruction_follows_the_reference_verbs_and_nouns(skill, category, text):
    assert instruction(skill, category) == text


def test_tiny_subset_is_two_objects_two_skills_two_scenes(tmp_path):
    cfg = tiny_cfg(tmp_path)
    combos = select_combinations(cfg.robot, cfg.subset)
    assert len(combos) == 8
    assert {c.scene for c in combos} == {"tabletop/00", "tabletop/01", "space/00", "space/01"}
    assert len({shard_path(c) for c in combos}) == 8
    assert combos[0].seed(0) == combos[0].seed(0) != combos[1].seed(0)


def test_shards_of_work_partition_the_combinations():
    combos = select_combinations("g1", SubsetCfg(categories=["box", "cart"], scenes_per_object=2))
    parts = [shard_of(combos, ShardCfg(i, 3)) for i in range(3)]
    assert sorted(sum(parts, []), key=combos.index) == combos


def test_test_split_uses_test_objects_and_rooms():
    combos = select_combinations("g1", SubsetCfg(split="test", categories=["box"]))
    assert {c.split for c in combos} == {"test"} and {c.scene_split for c in combos} == {"test"}
    assert {c.scene for c in combos} == {f"tabletop/{i}" for i in range(16, 20)}


def test_unknown_names_stop_with_the_valid_choices():
    with pytest.raises(UnknownNameError, match="valid objects"):
        select_combinations("g1", SubsetCfg(objects=["box/9999"]))
    with pytest.raises(UnknownNameError, match="valid skills"):
        select_combinations("g1", SubsetCfg(categories=["box"], skills=["fly"]))
    with pytest.raises(UnknownNameError, match="valid robots"):
        select_combinations("h1", SubsetCfg())


def test_an_empty_selection_names_the_key_that_emptied_it():
    # `make recipe RECIPE_SKILL=pull` asks box for a skill it does not have
    with pytest.raises(
        UnknownNameError, match=r"subset.skills=\['pull'\], but .*\(test/box\) offer close, open$"
    ):
        select_combinations("g1", SubsetCfg(objects=["test/box"], skills=["pull"]))
    with pytest.raises(UnknownNameError, match=r"subset.scenes=\['door/00'\] .* tabletop/16, "):
        select_combinations("g1", SubsetCfg(objects=["test/box"], split="test", scenes=["door/00"]))


@pytest.mark.parametrize("subset", ["small", "tiny", "train", "test", "ablation"])
def test_hydra_tree_converts_to_the_dataclasses(subset):
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        composed = compose("data", overrides=[f"data/subset={subset}", "robot=xhand"])
    cfg = to_dataclass(with_env_task(composed), DataCfg).check()
    assert isinstance(cfg, DataCfg) and cfg.robot == "xhand" and cfg.raw_dir == "outputs/data/xhand/raw"
    assert cfg.env.task.robot == "xhand"
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"), pytest.raises(ConfigKeyError):
        to_dataclass(with_env_task(compose("data", overrides=["+export.no_such_key=1"])), DataCfg)


def test_the_ablation_preset_is_the_papers_ablation_subset_at_cpu_scale():
    """272 train objects x 16 train rooms (4,352 combinations) and 66 test objects x 4 test rooms (264), of
    six categories and the skills open, pull and pick, as the paper's Section 4.2 lists them."""
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        composed = compose("data", overrides=["data/preset=ablation"])
    cfg = to_dataclass(with_env_task(composed), DataCfg).check()
    train = select_combinations(cfg.robot, cfg.subset)
    assert len(train) == 4352 and len({c.object_id for c in train}) == 272
    assert {c.category for c in train} == {"laptop", "cabinet", "faucet", "table", "cart", "holistic"}
    assert {c.skill for c in train} == {"open", "pull", "pick"} and {c.split for c in train} == {"train"}
    rooms = {}
    for combo in train:
        rooms.setdefault(combo.object_id, set()).add(combo.scene)
    assert {len(scenes) for scenes in rooms.values()} == {16}
    test = select_combinations(cfg.robot, SubsetCfg(**{**vars(cfg.subset), "split": "test"}))
    assert len(test) == 264 and len({c.object_id for c in test}) == 66
    assert (cfg.robot, cfg.teacher.kind, cfg.teacher.runs_dir) == ("g1", "ppo", "outputs/teachers")
    assert cfg.collect.action_noise > 0 and cfg.export.room_repaint > 0
    assert (cfg.export.width, cfg.export.height, cfg.export.episodes_per_combination) == (64, 64, 1)
    assert (cfg.export.cameras, cfg.export.modalities) == (["head", "wrist"], ["rgb", "depth"])


def test_labels_are_shifted_and_states_drop_the_reset():
    t, rng = 5, np.random.default_rng(0)
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (t, 1))
    arrays = {k: rng.normal(size=(t, 3)) for k in FRAME_KEYS}
    arrays.update({k: quat for k in ("hand_quat", "base_quat", "palm_quat", "grasp_quat")})
    arrays.update(
        joint_pos=rng.normal(size=(t, 10)),
        joint_vel=rng.normal(size=(t, 10)),
        state=np.zeros((t, 4)),
        action=rng.uniform(-1, 1, (t, 7)),
        success=np.ones(t, bool),
        goal_pos=np.array([0.0, 0.0, 1.0]),
    )
    vectors = episode_vectors(Episode(arrays), num_hand_joints=1, convention="conjugate")
    assert np.allclose(vectors["world.action"], arrays["action"][1:])
    assert np.allclose(vectors["action"], arrays["action"][1:])  # identity base
    assert np.allclose(vectors["observation.state"][:, -1], arrays["joint_pos"][1:, -1])
    assert np.allclose(vectors["observation.state"][:, :3], arrays["hand_pos"][1:] - arrays["base_pos"][1:])
    assert np.allclose(vectors["world.state"][:, -1], arrays["joint_pos"][1:, -1])
    assert np.allclose(vectors["object.grasp_point_base"], arrays["grasp_pos"][0] - arrays["base_pos"][1:])
