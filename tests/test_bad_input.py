"""Bad input stops with one message naming the key or file, before anything is written."""

from pathlib import Path

import pytest
import torch
from checkout import ROOT, checkout_env
from data_helpers import tiny_cfg
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from omegaconf import OmegaConf

from mobilemani_data.metadata import check_dataset_files
from mobilemani_data.validate import validate
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_vla.data.synthetic import write_synthetic_dataset


def test_non_positive_counts_name_their_keys(tmp_path):
    with pytest.raises(ValueError, match=r"subset.episodes=-2, collect.num_envs=0, collect.workers=0"):
        tiny_cfg(tmp_path, "subset.episodes=-2", "collect.num_envs=0", "collect.workers=0")
    with pytest.raises(ValueError, match="num_envs=0"):
        MobileManiEnv(EnvCfg(num_envs=0))
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("export.gop=0", "export.gop=0"),
        ("collect.action_noise=-0.3", r"collect.action_noise=-0.3 \(a standard deviation, >= 0\)"),
        ("collect.compression=12", r"collect.compression=12 \(a gzip level, 0 to 9\)"),
        ("teacher.min_train_success=10", r"teacher.min_train_success=10.0 \(a success rate, 0 to 1\)"),
        ("export.crf=-1", r"export.crf=-1 \(0 to 63"),
        ("export.action_convention=referense", "unknown export.action_convention 'referense'"),
        ("export.ppo_label_window=4", r"export.ppo_label_window=4 must be an odd whole number"),
        ("env.episode_length=0", "env.episode_length=0"),
        ("validate.replay_episodes=-1", r"validate.replay_episodes=-1 \(>= 0\)"),
        ("preview.episodes=0", "preview.episodes=0"),
        ("bench.sizes=[224,0]", r"bench.sizes=\[224, 0\] \(image sizes in pixels, >= 1\)"),
        # the encoder refused these when the export's first frame came, after collection
        (
            "export.vcodec=libsvtav1 export.preset=99",
            r"export.vcodec=libsvtav1 does not open with export.width=64, export.height=64, export.crf=30, "
            r"export.gop=2, export.preset=99: \[Errno 34\] Numerical result out of range",
        ),
        (
            "export.width=65",
            r"export.vcodec=h264 does not open with export.width=65, .*width not divisible by 2 \(65x64\) "
            r"\(4:2:0 video such as h264's needs even sizes\)$",
        ),
    ],
)
def test_data_values_name_their_keys_before_anything_is_written(tmp_path, override, named):
    with pytest.raises(ValueError, match=named):
        tiny_cfg(tmp_path, *override.split())
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("diffusion.ddim_steps=0", "diffusion.ddim_steps=0"),
        ("diffusion.ddim_steps=500", r"diffusion.ddim_steps=500 \(<= its timesteps\)"),
        ("diffusion.cfg_dropout=1", r"diffusion.cfg_dropout=1.0 \(in \[0, 1\)"),
        ("inputs.state_dropout=1", r"inputs.state_dropout=1.0 \(in \[0, 1\)"),
        ("train.lr=-0.001", r"train.lr=-0.001 \(above 0\)"),
        ("train.ema_decay=1.5", r"train.ema_decay=1.5 \(in \[0, 1\); 0 keeps no average\)"),
        ("data.heldout_episodes=-1", r"data.heldout_episodes=-1 \(>= 0\)"),
        (
            "train.mixed_precision=bf32",
            r"invalid train.mixed_precision \['bf32'\]: each must be one of \['no'",
        ),
        ("train.lr_schedule=cosin", r"invalid train.lr_schedule \['cosin'\]: each must be one of \['linear'"),
        # each reached a library's traceback when the model or the dataset was built, or ran without a word
        (
            "diffusion.beta_schedule=cosine",
            r"invalid diffusion.beta_schedule \['cosine'\]: each must be one of \['linear', 'scaled_linear'",
        ),
        (
            "data.video_backend=ffmpeg",
            r"invalid data.video_backend \['ffmpeg'\]: each must be one of \['pyav'",
        ),
        ("diffusion.cfg_scale=-1", r"diffusion.cfg_scale=-1.0 \(>= 0; 1: no guidance\)"),
        ("train.diagnose_cfg_scales=[1,-2]", r"train.diagnose_cfg_scales=\[1.0, -2.0\] \(guidance scales"),
        (
            "model.vision.num_attention_heads=3",
            r"model.vision.num_attention_heads=3 \(a divisor of model.vision.hidden_size=32\)",
        ),
        (
            "model.text.num_key_value_heads=3",
            r"model.text.num_key_value_heads=3 \(a divisor of model.text.num_attention_heads=2\)",
        ),
    ],
)
def test_vla_training_values_name_their_keys(override, named):
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.config import compose_vla_cfg

    with pytest.raises(InputError, match=named):
        compose_vla_cfg([override])


@pytest.mark.parametrize(
    ("episodes", "named"),
    [
        # it said "data.heldout_episodes=4 leaves no training episode of 1", of an episode that does not exist
        (
            [999],
            r"data.episodes=\[999\]: name one or more of the 3 episodes of .* \(0 to 2\), .*"
            r"not among them: \[999\]",
        ),
        ([1, 1], r"data.episodes=\[1, 1\]: .* without repeats"),
        ([], r"data.episodes=\[\]: name one or more"),
    ],
)
def test_vla_training_episodes_must_be_the_datasets(tmp_path, episodes, named):
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.config import compose_vla_cfg
    from mobilemani_vla.data.dataset import open_data

    root = write_synthetic_dataset(tmp_path / "g1", episodes=3, length=5)
    cfg = compose_vla_cfg([f"data.root={root}", "data.repo_id=synthetic/g1", "data.heldout_episodes=0"])
    cfg.data.episodes = episodes
    with pytest.raises(InputError, match=named):
        open_data(cfg, 32, progress=False)


def test_non_positive_evaluation_counts_name_their_keys():
    from hydra import compose, initialize_config_dir

    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_vla.eval.config import EvalCfg

    conf = str(ROOT / "conf")
    with initialize_config_dir(config_dir=conf, version_base="1.3"):
        cfg = compose(config_name="eval", overrides=["episodes_per_batch=0", "workers=0"])
    with pytest.raises(ValueError, match="episodes_per_batch=0, workers=0"):
        to_dataclass(with_env_task(cfg), EvalCfg).check()


@pytest.mark.parametrize("checkpoint", [None, ""])  # "": `policy.checkpoint=` on the command line
def test_a_model_policy_without_a_checkpoint_names_the_key(checkpoint):
    from mobilemani_vla.eval.config import PolicyCfg
    from mobilemani_vla.eval.policies.factory import build_policy

    for kind in ("vla", "lerobot"):
        with pytest.raises(ValueError, match=f"policy.kind={kind} needs policy.checkpoint="):
            build_policy(PolicyCfg(kind=kind, checkpoint=checkpoint))
    assert build_policy(PolicyCfg(kind="teacher", checkpoint=checkpoint)).checkpoint is None


def test_a_policy_setting_its_kind_does_not_read_is_refused():
    """`make eval POLICY=scripted CHECKPOINT=...` evaluated the scripted policy without a word."""
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import PolicyCfg
    from mobilemani_vla.eval.policies.factory import build_policy

    for kind in ("scripted", "random"):
        with pytest.raises(
            InputError, match=f"policy.kind={kind} does not read policy.checkpoint=ckpt; leave it out"
        ):
            build_policy(PolicyCfg(kind=kind, checkpoint="ckpt"))
    rename = {"observation.images.head_rgb": "observation.images.top"}
    with pytest.raises(
        InputError, match=r"policy.kind=teacher does not read policy.device=cuda, policy.rename="
    ):
        build_policy(PolicyCfg(kind="teacher", rename=rename, device="cuda"))
    with pytest.raises(InputError, match="policy.kind=vla does not read policy.runs_dir=runs/teachers"):
        build_policy(PolicyCfg(kind="vla", checkpoint="ckpt", runs_dir="runs/teachers"))


def test_a_fixed_action_index_outside_the_chunk_stops_before_anything_is_written(tmp_path):
    """It stopped at the first step, after the run's config.json was written."""
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg
    from mobilemani_vla.eval.evaluate import evaluate

    cfg = compose_root(
        "eval",
        ["eval/policy=scripted", "eval/protocol=small", f"output_dir={tmp_path}", "ensemble.action_index=1"],
    )
    with pytest.raises(
        InputError, match="ensemble.action_index=1 is outside the policy's chunk of 1 actions"
    ):
        evaluate(to_dataclass(with_env_task(cfg), EvalCfg).check())
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("ensemble.horizon=0", "ensemble.horizon=0"),
        ("policy.batch_size=0", "policy.batch_size=0"),
        ("env.episode_length=0", "env.episode_length=0"),
        ("env.physics.substeps=0", "env.physics.substeps=0"),
        ("video_episodes=-1", r"video_episodes=-1 \(episodes to record, >= 0\)"),
        ("ensemble.action_index=-2", r"ensemble.action_index=-2 \(-1: adaptive ensemble"),
        (
            "action_convention=foo",
            "unknown action_convention 'foo'; valid action_conventions: conjugate, reference",
        ),
        ("image_size=[64]", r"image_size=\[64\] \(\[height, width\]\)"),
        ("image_size=[0,0]", r"image_size=\[0, 0\] \(\[height, width\]\)"),
        # reached torch's "Found no NVIDIA driver on your system" once the checkpoint loaded
        (f"policy.device=cuda:{torch.cuda.device_count()}", "CUDA device\\(s\\); use policy.device=cpu"),
    ],
)
def test_evaluation_config_names_each_bad_value(tmp_path, override, named):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg

    cfg = compose_root("eval", ["eval/policy=scripted", f"output_dir={tmp_path / 'out'}", override])
    with pytest.raises(InputError, match=named):
        to_dataclass(with_env_task(cfg), EvalCfg).check()


def test_validating_nothing_is_a_problem_not_valid(tmp_path):
    problems = validate(tiny_cfg(tmp_path / "nowhere"))
    assert len(problems) == 1 and "nothing to validate" in problems[0]


def test_a_deleted_dataset_file_is_named(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    meta = LeRobotDatasetMetadata("synthetic/g1", root=root)
    check_dataset_files(meta)
    video = root / meta.get_video_file_path(0, meta.video_keys[0])
    video.unlink()
    with pytest.raises(FileNotFoundError, match=str(Path(video).name)):
        check_dataset_files(meta)


def test_a_checkpoint_from_an_older_dataset_layout_is_refused_by_name():
    from mobilemani_vla.model.normalizer import Normalizer
    from mobilemani_vla.model.processor import VLAProcessor
    from mobilemani_vla.model.tokenizer import build_word_tokenizer

    old_bounds = Normalizer(
        {"action": ([-1.0] * 7, [1.0] * 7), "observation.wrist_pose_base": ([-1.0] * 9, [1.0] * 9)}
    )
    with pytest.raises(KeyError, match=r"no \['observation.state'\].*older dataset layout"):
        VLAProcessor(build_word_tokenizer(), old_bounds, ["head_rgb"], ["wrist_pose"], 32, "{instruction}")


# ---------------------------------------------------- one line per bad input, before anything is written


def compose_root(name: str, overrides: list[str]):
    """The composed root config `name`; importing the config modules registers the roots' schemas, so a test
    run alone composes as in the whole suite."""
    from hydra import compose, initialize_config_dir

    import mobilemani_rl.rl.config  # noqa: F401
    import mobilemani_vla.eval.config  # noqa: F401

    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        return compose(config_name=name, overrides=overrides)


def test_entry_points_end_bad_input_with_one_line_and_keep_tracebacks_for_bugs(tmp_path, capsys):
    import subprocess
    import sys

    from mobilemani_rl.utils.cli import entry_point
    from mobilemani_rl.utils.errors import InputError

    @entry_point
    def bad() -> None:
        raise InputError("rl.ppo.num_envs=0 must be at least 1")

    with pytest.raises(SystemExit) as stop:
        bad()
    assert stop.value.code == 2 and capsys.readouterr().err == "error: rl.ppo.num_envs=0 must be at least 1\n"
    with pytest.raises(ZeroDivisionError):  # a bug keeps its traceback
        entry_point(lambda: 1 / 0)()
    # As a user runs it: exit 2, one line on stderr, nothing written.
    done = subprocess.run(
        [sys.executable, "-m", "mobilemani_data.collect", "data/subset=tiny", "subset.episodes=-2"]
        + [f"data_dir={tmp_path / 'data'}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=checkout_env(),
    )
    assert done.returncode == 2
    assert done.stderr == "error: these must be whole numbers of at least 1: subset.episodes=-2\n"
    assert not (tmp_path / "data").exists()


def test_an_output_path_through_a_file_ends_with_one_line_naming_the_file(tmp_path, capsys):
    """`run_dir=`, `data_dir=`, `output_dir=` or `train.output_dir=` naming a file (or a path below one) ended
    in FileExistsError's or NotADirectoryError's traceback when the stage made its folder."""
    import subprocess
    import sys

    from mobilemani_rl.utils.cli import entry_point

    a_file = tmp_path / "notes.txt"
    a_file.write_text("kept")
    for folder in (a_file, a_file / "run"):

        @entry_point
        def make_output(folder: Path = folder) -> None:
            folder.mkdir(parents=True, exist_ok=True)

        with pytest.raises(SystemExit) as stop:
            make_output()
        message = f"error: cannot make the folder {folder}: {a_file} is a file; choose another path\n"
        assert stop.value.code == 2 and capsys.readouterr().err == message

    @entry_point
    def not_about_a_folder() -> None:
        raise FileExistsError("no path")

    with pytest.raises(FileExistsError):  # a bug keeps its traceback
        not_about_a_folder()
    done = subprocess.run(
        [sys.executable, "-m", "mobilemani_data.collect", "data/subset=tiny", f"data_dir={a_file}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=checkout_env(),
    )
    assert done.returncode == 2 and done.stderr.endswith(f"{a_file} is a file; choose another path\n")
    assert a_file.read_text() == "kept"


@pytest.mark.parametrize(
    ("module", "argv", "message"),
    [
        ("mobilemani_rl.envs.render_bench", ["--sizes", "0"], "argument --sizes: must be at least 1, got 0"),
        ("mobilemani_rl.envs.render_bench", ["--seconds", "0"], "argument --seconds: must be above 0, got 0"),
        ("mobilemani_rl.envs.render_bench", ["--object", "nope/0000"], "error: unknown object 'nope/0000'"),
        ("mobilemani_rl.envs.bench", ["--robots", "g1", "g2"], "argument --robots: invalid choice: 'g2'"),
        ("mobilemani_rl.envs.bench", ["--envs", "many"], "argument --envs: invalid count value: 'many'"),
        (
            "mobilemani_rl.rl.bench",
            ["--presets", "fast"],
            "argument --presets: invalid choice: 'fast'",
        ),
        ("mobilemani_rl.rl.sweep", ["--robot", "g2"], "argument --robot: invalid choice: 'g2'"),
        (
            "mobilemani_rl.envs.scene_sheet",
            ["--out", "x.png", "--size", "-5"],
            "argument --size: must be at least 1",
        ),
        (
            "mobilemani_rl.assets.__main__",
            ["preview", "--per-category", "0"],
            "--per-category: must be at least 1",
        ),
        # matplotlib and PIL refused these only after the half minute of rendering
        (
            "mobilemani_rl.assets.__main__",
            ["preview", "--out", "x.txt"],
            "argument --out: must name a .png file",
        ),
        (
            "mobilemani_rl.envs.scene_sheet",
            ["--out", "sheet"],
            "argument --out: must name a .png file, got sheet",
        ),
    ],
)
def test_command_line_tools_name_the_bad_option(module, argv, message, capsys, tmp_path, monkeypatch):
    """The argparse tools (benchmarks, sheets, sweeps) end bad input as the Hydra entry points do: exit 2 and
    one message naming the option and its valid values, before anything runs."""
    import importlib

    monkeypatch.chdir(tmp_path)
    main = importlib.import_module(module).main
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2 and message in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


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


def test_env_keys_that_data_and_evaluation_set_are_refused(tmp_path):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_vla.eval.config import EvalCfg

    with pytest.raises(ValueError, match=r"env.seed=3 \(set it through collect.seed\)"):
        tiny_cfg(tmp_path, "env.seed=3")
    cfg = compose_root("eval", ["env.num_envs=4"])
    with pytest.raises(ValueError, match=r"env.num_envs=4 \(set it through episodes_per_batch\)"):
        to_dataclass(with_env_task(cfg), EvalCfg).check()


@pytest.mark.parametrize(
    ("override", "named"),
    [
        # each reached a library's traceback (ZeroDivisionError, numpy's "high - low < 0", "all input arrays
        # must have the same shape") or ran without a word, never able to succeed or to observe anything
        ("env.physics.control_hz=0", r"env.physics.control_hz=0.0 \(above 0\)"),
        ("env.physics.solver_iterations=0", "env.physics.solver_iterations=0"),
        ("env.physics.nthread=-1", r"env.physics.nthread=-1 \(>= 0\)"),
        ("env.seed=-1", r"env.seed=-1 \(an integer >= 0\)"),
        ("env.success.threshold=0", r"env.success.threshold=0.0 \(above 0\)"),
        ("env.success.hold_steps=0", "env.success.hold_steps=0"),
        ("env.obs_clip=0", r"env.obs_clip=0.0 \(above 0\)"),
        ("env.actions.ik_damping=-1", r"env.actions.ik_damping=-1.0 \(>= 0\)"),
        ("env.reset.random_height=-0.5", r"env.reset.random_height=-0.5 \(>= 0\)"),
        (
            "env.reset.root_x_range=[0.25,-0.25]",
            r"env.reset.root_x_range=\[0.25, -0.25\] \(\[low, high\] with low <= high\)",
        ),
        ("env.reset.room_jitter_y=[0.1]", r"env.reset.room_jitter_y=\[0.1\] \(\[low, high\]"),
    ],
)
def test_env_values_are_checked_by_every_entry_point_and_the_env(tmp_path, override, named):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.rl.train import train
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg

    with pytest.raises(InputError, match=named):
        train(compose_root("rl", ["rl/ppo=tiny", f"run_dir={tmp_path / 'run'}", override]))
    with pytest.raises(InputError, match=named):
        tiny_cfg(tmp_path / "data", override)
    with pytest.raises(InputError, match=named):
        to_dataclass(with_env_task(compose_root("eval", [override])), EvalCfg).check()
    key, value = override.split("=")
    env_cfg = OmegaConf.merge(OmegaConf.structured(EnvCfg), OmegaConf.from_dotlist([f"{key[4:]}={value}"]))
    with pytest.raises(InputError, match=named):
        MobileManiEnv(OmegaConf.to_object(env_cfg))
    assert not any(tmp_path.iterdir())


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


def test_a_changed_run_names_each_changed_key(tmp_path):
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir, rules = tmp_path / "run", ConfigRules(("rl",))
    save_or_check_config(run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), rules)
    (run_dir / "model_2.pt").touch()  # it has something to resume
    changed = compose_root(
        "rl", ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.learning_rate=0.5", "rl.ppo.num_envs=16"]
    )
    each = r"\(rl.ppo.learning_rate: 0.001 -> 0.5; rl.ppo.num_envs: 8 -> 16\)"
    with pytest.raises(ConfigMismatchError, match=each):
        save_or_check_config(run_dir, changed, rules)


def test_a_resumed_run_may_move_devices_but_not_change_what_it_learns(tmp_path, capsys):
    """Where PPO computes (device, threads, physics threads) may change between pieces of one run, e.g. a run
    started on a GPU node goes on on a laptop; the saved config keeps the first values, and any learning
    setting is refused."""
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.rl.train import PLACEMENT_KEYS
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir, rules = tmp_path / "run", ConfigRules(("env", "rl"), placement=PLACEMENT_KEYS)
    save_or_check_config(run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), rules)
    (run_dir / "model_2.pt").touch()  # it has something to resume
    moved = [
        "rl/ppo=tiny",
        f"run_dir={run_dir}",
        "rl.ppo.device=cuda",
        "rl.ppo.update_threads=16",
        "env.physics.nthread=1",
    ]
    save_or_check_config(run_dir, compose_root("rl", moved), rules)
    moves = capsys.readouterr().out
    assert "rl.ppo.device: cpu -> cuda; rl.ppo.update_threads: 0 -> 16" in moves
    assert "env.physics.nthread: 0 -> 1" in moves
    assert OmegaConf.load(run_dir / "config.yaml").rl.ppo.device == "cpu"
    changed = compose_root("rl", [*moved, "rl.ppo.learning_rate=0.5"])
    with pytest.raises(ConfigMismatchError, match=r"\(rl.ppo.learning_rate: 0.001 -> 0.5\)"):
        save_or_check_config(run_dir, changed, rules)


def test_a_run_saved_before_a_key_existed_resumes_with_its_default(tmp_path):
    """A run started before `rl.ppo.precision` existed trained in fp32, the default: it resumes with that
    value and refuses another, naming it."""
    from mobilemani_rl.rl.config import RLCfg
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir = tmp_path / "run"
    save_or_check_config(
        run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), ConfigRules(("rl",))
    )
    saved = OmegaConf.load(run_dir / "config.yaml")
    del saved.rl.ppo["precision"]  # what an older version wrote
    OmegaConf.save(saved, run_dir / "config.yaml")
    (run_dir / "model_2.pt").touch()  # it has something to resume
    rules = ConfigRules(("rl",), defaults=OmegaConf.to_container(OmegaConf.structured(RLCfg)))
    resumed = compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"])
    save_or_check_config(run_dir, resumed, rules)
    changed = compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.precision=bf16"])
    with pytest.raises(ConfigMismatchError, match=r"\(rl.ppo.precision: fp32 -> bf16\)"):
        save_or_check_config(run_dir, changed, rules)


def test_export_values_are_checked_with_the_data_config_before_collection():
    """`make data` collects before it exports: a bad export value stopped it only after collecting."""
    from mobilemani_data.config import DataCfg, ExportCfg

    with pytest.raises(ValueError, match="export.vcodec='foo' is no video encoder"):
        ExportCfg(vcodec="foo").check()
    ExportCfg(vcodec="h264").check()
    with pytest.raises(ValueError, match=r"export.room_repaint=1.5 must lie in \[0, 1\]"):
        ExportCfg(vcodec="h264", room_repaint=1.5).check()
    with pytest.raises(
        ValueError, match=r"invalid export.modalities \['rgb', 'thermal'\]: name one or more of"
    ):
        DataCfg(export=ExportCfg(modalities=["rgb", "thermal"])).check()


def test_vla_training_counts_and_logger_name_their_keys():
    from mobilemani_vla.config import VLACfg

    cfg = VLACfg()
    cfg.train.steps, cfg.train.batch_size = 0, -1
    with pytest.raises(ValueError, match=r"train.steps=0, train.batch_size=-1"):
        cfg.validate()
    cfg = VLACfg()
    cfg.train.logger = "tensorboard"
    with pytest.raises(ValueError, match=r"train.logger \['tensorboard'\]"):
        cfg.validate()


@pytest.mark.parametrize(
    ("deleted", "named"), [("meta/tasks.parquet", "meta/tasks.parquet"), ("meta/episodes", "meta/episodes")]
)
def test_a_deleted_metadata_file_is_named(tmp_path, deleted, named):
    import shutil

    from mobilemani_data.metadata import open_dataset_metadata

    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    open_dataset_metadata("synthetic/g1", root)
    victim = root / deleted
    shutil.rmtree(victim) if victim.is_dir() else victim.unlink()
    with pytest.raises(FileNotFoundError, match=named):
        open_dataset_metadata("synthetic/g1", root)


@pytest.mark.parametrize("damaged_name", ["model.safetensors", "optimizer.bin", "random_states_0.pkl"])
def test_a_damaged_vla_checkpoint_is_named_and_training_resumes_from_the_previous_one(
    damaged_name, tmp_path, capsys
):
    import json

    import torch
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
