"""The LeRobot env plugin (integrations/lerobot_env_mobilemanibench): its episodes are our harness's, and
stock `lerobot-eval` scores a LeRobot policy on it."""

import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from lerobot_env_mobilemanibench import MobileManiBenchEnvConfig, MobileManiBenchVectorEnv
from lerobot_env_mobilemanibench.tasks import task_combinations

from mobilemani_data import schema
from mobilemani_rl.envs.base_frame import action_to_base
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.errors import InputError
from mobilemani_vla.eval.config import EvalCfg, PolicyCfg
from mobilemani_vla.eval.evaluate import evaluate
from mobilemani_vla.eval.harness import batch_seed, episode_env, run_batch
from mobilemani_vla.eval.policies.privileged import ScriptedEvalPolicy
from mobilemani_vla.eval.results import read_records
from mobilemani_vla.model.ensemble import EnsembleCfg

TASK = "g1/test/box/open/unseen_unseen"
HEAD = schema.image_key("head", "rgb")
SIZE = 32


class BaseFrameScripted(ScriptedEvalPolicy):
    """The scripted policy's actions given in the base frame, as a LeRobot policy gives them, and the
    observations it was shown."""

    action_frame = "base"
    inputs = frozenset({HEAD, schema.STATE})

    def start(self, env, seed):
        super().start(env, seed)
        self.env, self.seen = env, []

    def act(self, obs):
        self.seen.append({k: np.copy(obs[k]) for k in self.inputs})
        return action_to_base(super().act(obs)[:, 0], self.env.frames.base_quat)[:, None]


def test_plugin_episodes_are_the_harness_episodes_of_the_same_seed():
    combo = task_combinations(TASK, scenes_per_object=1)[0]
    first, n = 5, 2
    seed = batch_seed(combo, first)
    harness_policy = BaseFrameScripted()
    env = episode_env(EnvCfg(), combo, n, seed)
    stats = run_batch(env, harness_policy, seed, combo.instruction, EnsembleCfg(), (SIZE, SIZE))

    vec = MobileManiBenchVectorEnv(
        combo, n, cameras=("head_rgb",), observation_height=SIZE, observation_width=SIZE
    )
    obs, _ = vec.reset(seed=list(range(first, first + n)))
    first_seen = harness_policy.seen[0]
    np.testing.assert_array_equal(obs["pixels"]["head_rgb"], first_seen[HEAD])
    np.testing.assert_array_equal(obs["agent_pos"], first_seen[schema.STATE])
    scripted = ScriptedPolicy(vec.episodes.env)
    done = np.zeros(n, dtype=bool)
    length = np.zeros(n, dtype=int)
    for _ in range(vec.call("_max_episode_steps")[0]):
        actions = action_to_base(scripted(), vec.episodes.env.frames.base_quat)
        obs, _, terminated, truncated, info = vec.step(actions)
        length += ~done
        done |= terminated | truncated
        if done.all():
            break
    vec.close()
    np.testing.assert_array_equal(length, stats.length)
    np.testing.assert_array_equal(info["is_success"], stats.success)
    assert stats.success.any(), "the scripted policy should open the box at least once"


def test_env_config_features_follow_the_dataset_and_tasks_expand_to_combinations():
    cfg = MobileManiBenchEnvConfig(
        task=f"{TASK},g1/box/open/seen_unseen", cameras=["head_rgb", "wrist_depth"], scenes_per_object=1
    )
    assert cfg.features_map["pixels/wrist_depth"] == schema.image_key("wrist", "depth")
    assert cfg.features["agent_pos"].shape == (schema.state_dim(1),)
    assert cfg.features["action"].shape == (7,)
    envs = cfg.create_envs(n_envs=3)
    assert list(envs) == [TASK, "g1/box/open/seen_unseen"]
    assert len(envs[TASK]) == 1 and len(envs["g1/box/open/seen_unseen"]) == 10  # box's 10 train objects
    assert envs[TASK][0].call("task_description") == ("open box",) * 3


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"task": "g1/box/open"}, "<robot>/<object id or category>/<skill>/<split>"),
        ({"task": "g1/test/box/fly/unseen_unseen"}, "skill"),
        ({"task": "g1/test/box/open/everywhere"}, "split"),
        ({"cameras": ["head_rgb", "top_rgb"]}, "env.cameras"),
        ({"observation_height": 2}, "env.observation_height"),
        ({"episode_length": 0}, "env.episode_length"),
    ],
)
def test_bad_env_settings_stop_with_one_message_naming_them(kwargs, named):
    with pytest.raises(InputError, match=named):
        cfg = MobileManiBenchEnvConfig(**kwargs)
        cfg.create_envs(n_envs=1)


def test_gymnasium_ids_make_one_env_and_a_batched_vector():
    env = gym.make("MobileManiBench/g1-v0", object="test/box", skill="open", cameras=(), episode_length=3)
    obs, _ = env.reset(seed=0)
    assert obs["agent_pos"].shape == (schema.state_dim(1),) and "pixels" not in obs
    assert env.step(np.zeros(7))[0]["agent_pos"].shape == obs["agent_pos"].shape
    env.close()
    vec = gym.make_vec(
        "MobileManiBench/g1-v0", num_envs=2, vectorization_mode="vector_entry_point", cameras=()
    )
    assert isinstance(vec, MobileManiBenchVectorEnv) and vec.num_envs == 2
    with pytest.raises(InputError, match="consecutive"):
        vec.reset(seed=[0, 2])


def tiny_act(path, state_dim: int) -> None:
    """A randomly initialised ACT over head RGB and the state, saved with its pipelines as lerobot-train
    saves a checkpoint. It predicts a chunk every step and executes its first action: deterministic, and
    executed alike by LeRobot (select_action) and our harness (ensemble.action_index=0)."""
    from lerobot.configs import FeatureType, PolicyFeature
    from lerobot.policies.act.configuration_act import ACTConfig
    from lerobot.policies.act.modeling_act import ACTPolicy
    from lerobot.policies.factory import make_pre_post_processors

    features = {HEAD: (FeatureType.VISUAL, (3, SIZE, SIZE)), schema.STATE: (FeatureType.STATE, (state_dim,))}
    cfg = ACTConfig(
        input_features={k: PolicyFeature(type=t, shape=s) for k, (t, s) in features.items()},
        output_features={schema.ACTION: PolicyFeature(type=FeatureType.ACTION, shape=(7,))},
        chunk_size=4,
        n_action_steps=1,
        dim_model=16,
        n_heads=2,
        dim_feedforward=32,
        n_encoder_layers=1,
        n_decoder_layers=1,
        use_vae=False,
        pretrained_backbone_weights=None,
        device="cpu",
        push_to_hub=False,
    )
    torch.manual_seed(0)
    ACTPolicy(cfg).save_pretrained(path)
    stats = {
        HEAD: {"mean": torch.full((3, 1, 1), 0.5), "std": torch.full((3, 1, 1), 0.25)},
        schema.STATE: {"mean": torch.zeros(state_dim), "std": torch.ones(state_dim)},
        schema.ACTION: {"mean": torch.zeros(7), "std": torch.full((7,), 0.3)},
    }
    for pipeline in make_pre_post_processors(cfg, dataset_stats=stats):
        pipeline.save_pretrained(path)


def test_lerobot_eval_scores_a_tiny_act_as_our_harness_does(tmp_path):
    """Stock lerobot-eval on the plugin env and our harness, same policy, seed and batch size: the same
    episodes (returns and successes)."""
    from lerobot.configs.default import EvalConfig
    from lerobot.configs.eval import EvalPipelineConfig
    from lerobot.configs.policies import PreTrainedConfig
    from lerobot.scripts.lerobot_eval import eval_main

    act, length, n = tmp_path / "act", 12, 2
    tiny_act(act, schema.state_dim(1))
    policy = PreTrainedConfig.from_pretrained(act)
    policy.pretrained_path = act
    env = MobileManiBenchEnvConfig(
        task=TASK,
        cameras=["head_rgb"],
        observation_height=SIZE,
        observation_width=SIZE,
        episode_length=length,
        scenes_per_object=1,
    )
    out = tmp_path / "lerobot_eval"
    eval_main(
        EvalPipelineConfig(
            env=env, eval=EvalConfig(n_episodes=n, batch_size=n), policy=policy, output_dir=out, seed=3
        )
    )
    info = json.loads((out / "eval_info.json").read_text())
    assert info["overall"]["n_episodes"] == n and 0.0 <= info["overall"]["pc_success"] <= 100.0

    cfg = EvalCfg(
        output_dir=str(tmp_path / "harness"),
        policy=PolicyCfg(kind="lerobot", checkpoint=str(act)),
        episodes_per_batch=n,
        seed=3,
        ensemble=EnsembleCfg(action_index=0),
    )
    cfg.subset.objects, cfg.subset.skills, cfg.subset.episodes, cfg.subset.scenes_per_object = (
        ["test/box"],
        ["open"],
        n,
        1,
    )
    cfg.env.episode_length = length
    evaluate(cfg.check())
    records = sorted(
        read_records(Path(cfg.output_dir) / "g1" / "default" / f"{cfg.split_name}.jsonl"),
        key=lambda r: r["episode"],
    )
    metrics = info["per_task"][0]["metrics"]
    assert [r["success"] for r in records] == metrics["successes"]
    np.testing.assert_allclose([r["return"] for r in records], metrics["sum_rewards"], rtol=1e-5)
