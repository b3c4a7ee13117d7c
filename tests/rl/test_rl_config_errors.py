"""PPO training and evaluation configs and teacher checkpoints: each bad value or path named, before the
run directory is written."""

import pytest
import torch
from roots import compose_root


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("rl.ppo.num_envs=0", "rl.ppo.num_envs=0"),
        ("rl.ppo.max_iterations=-1", "rl.ppo.max_iterations=-1"),
        (
            "task.object=nope/0000",
            r"unknown task.object 'nope/0000'; valid: an object \(box/0000 to box/0013, .*, test/can\) "
            r"or a category, .*\(box, toilet, ",
        ),
        ("task.skill=fly", "unknown skill 'fly'; valid skills: close, open"),
        # a category trains one policy for its objects; the default skill, open, is none of holistic's
        (
            "task.object=holistic",
            r"skill 'open' does not apply to holistic/0000 \(rigid\); valid skills for it: pick",
        ),
        ("logger=foo", "unknown logger 'foo'; valid loggers: tensorboard, wandb"),
        ("rl.ppo.activation=foo", "rl.ppo.activation: Invalid activation function 'foo'"),
        (
            "rl.ppo.precision=fp16",
            "unknown rl.ppo.precision 'fp16'; valid rl.ppo.precisions: auto, bf16, fp32",
        ),
        ("rl.ppo.device=tpu", "rl.ppo.device='tpu': valid devices are cpu, cuda and cuda:<index>"),
        (f"rl.ppo.device=cuda:{torch.cuda.device_count()}", "CUDA device\\(s\\); use rl.ppo.device=cpu"),
        ("env.num_envs=4", r"env.num_envs=4 \(set it through rl.ppo.num_envs\)"),
        ("env.seed=4", r"env.seed=4 \(set it through rl.ppo.seed\)"),
        ("env.episode_length=0", "env.episode_length=0"),
        ("rl.ppo.gamma=1.5", r"rl.ppo.gamma=1.5 \(a discount, in \(0, 1\]\)"),
        ("rl.ppo.learning_rate=-1e-3", r"rl.ppo.learning_rate=-0.001 \(above 0\)"),
        ("rl.ppo.num_mini_batches=1000", r"rl.ppo.num_mini_batches=1000 \(at most the 64 samples"),
        ("rl.ppo.actor_hidden_dims=[64,0]", r"rl.ppo.actor/critic_hidden_dims=\[64, 0, "),
        ("rl.ppo.warm_start.learning_rate=0", r"rl.ppo.warm_start.learning_rate=0.0 \(above 0\)"),
        # numpy's "expected non-negative integer" once the env was built, after the run dir was written
        ("rl.ppo.seed=-1", r"rl.ppo.seed=-1 \(an integer >= 0\)"),
        (
            "task.scene=door/00",
            r"scene 'door/00' is a door placement but test/box \(box\) goes into tabletop; "
            "valid scenes: tabletop/00 to tabletop/19$",
        ),
    ],
)
def test_rl_training_checks_its_config_before_writing_the_run_dir(tmp_path, override, named):
    from mobilemani_rl.rl.train import train
    from mobilemani_rl.utils.errors import InputError

    with pytest.raises(InputError, match=named):
        train(compose_root("rl", ["rl/ppo=tiny", f"run_dir={tmp_path / 'run'}", override]))
    assert not (tmp_path / "run").exists()


def test_rl_evaluation_names_its_keys():
    from mobilemani_rl.rl.config import EvalRlCfg

    with pytest.raises(ValueError, match="checkpoint=<path to a model_.*.pt> is required"):
        EvalRlCfg().check()
    with pytest.raises(ValueError, match="episodes=0"):
        EvalRlCfg(checkpoint="model_1.pt", episodes=0).check()
    with pytest.raises(ValueError, match="seed=-1 must be an integer >= 0"):  # it reached numpy's traceback
        EvalRlCfg(checkpoint="model_1.pt", seed=-1).check()


def test_a_run_directory_given_as_teacher_checkpoint_names_its_newest(tmp_path):
    from mobilemani_rl.rl.teacher import check_checkpoint_file

    run_dir = tmp_path / "run"
    run_dir.mkdir()
    with pytest.raises(FileNotFoundError, match=f"{run_dir} is a directory; it holds no model_"):
        check_checkpoint_file(run_dir)
    for iteration in (50, 100):
        (run_dir / f"model_{iteration}.pt").touch()
    with pytest.raises(FileNotFoundError, match=f"its newest checkpoint is {run_dir / 'model_100.pt'}$"):
        check_checkpoint_file(run_dir)
    with pytest.raises(FileNotFoundError, match="model_300.pt does not exist"):
        check_checkpoint_file(run_dir / "model_300.pt")
    check_checkpoint_file(run_dir / "model_50.pt")
