"""Closed-loop evaluation: adaptive ensemble, reproduction of the reference policies' own success, resumable
results, and a tiny VLA through the whole protocol."""

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from checkout import ROOT
from hydra import compose, initialize_config_dir
from omegaconf import OmegaConf
from safetensors.torch import load_file, save_file

from mobilemani_rl.envs.base_frame import action_to_base
from mobilemani_rl.envs.config import EnvCfg, TaskCfg, with_env_task
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.rollout import run_first_episodes
from mobilemani_rl.rl.config import RLCfg
from mobilemani_rl.rl.eval import evaluate as evaluate_teacher
from mobilemani_rl.rl.run_dir import CONFIG, latest_checkpoint
from mobilemani_rl.rl.train import train as train_ppo
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError
from mobilemani_vla.config import ROOT_ONLY, VLACfg
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.eval.config import EvalCfg, compose_eval_cfg
from mobilemani_vla.eval.evaluate import evaluate
from mobilemani_vla.eval.harness import run_batch
from mobilemani_vla.eval.policies.privileged import RandomPolicy, ScriptedEvalPolicy, TeacherEvalPolicy
from mobilemani_vla.eval.results import ResultsFile, finished, read_records, record_key, summary_path
from mobilemani_vla.model.ensemble import AdaptiveEnsembler, ChunkExecutor, EnsembleCfg, ensemble_weights
from mobilemani_vla.train import train as train_vla

CONF = str(ROOT / "conf")
ENSEMBLE = EnsembleCfg()


def compose_cfg(name: str, overrides: list[str]):
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        return compose(config_name=name, overrides=overrides)


# ---------------------------------------------------------------- adaptive ensemble
def test_ensemble_weights_follow_cosine_similarity():
    candidates = np.array([[1.0, 0.0], [0.0, 2.0], [-3.0, 0.0]])  # cos to row 0: 1, 0, -1
    expected = np.exp(0.1 * np.array([1.0, 0.0, -1.0]))
    np.testing.assert_allclose(ensemble_weights(candidates, 0.1), expected / expected.sum())
    np.testing.assert_allclose(ensemble_weights(candidates, 0.0), np.full(3, 1 / 3))  # alpha 0: plain average


def test_ensemble_takes_each_chunks_row_for_the_current_step_and_keeps_k():
    ens = AdaptiveEnsembler(horizon=3, alpha=0.1)
    # Chunk t predicts step t + i with value 10 * t + i in both dimensions
    # (all positive: cos = 1, equal weights).
    chunk = lambda t: np.array([[10.0 * t + i] * 2 for i in range(5)])  # noqa: E731
    np.testing.assert_allclose(ens.update(chunk(0)), [0.0, 0.0])  # one chunk at episode start
    np.testing.assert_allclose(ens.update(chunk(1)), [(1 + 10) / 2] * 2)  # rows: chunk1[0]=10, chunk0[1]=1
    np.testing.assert_allclose(ens.update(chunk(2)), [(20 + 11 + 2) / 3] * 2)
    # K = 3: chunk 0 (row 3 would be 3) is dropped; candidates chunk3[0], chunk2[1], chunk1[2].
    np.testing.assert_allclose(ens.update(chunk(3)), [(30 + 21 + 12) / 3] * 2)
    ens.reset()
    np.testing.assert_allclose(ens.update(chunk(7)), [70.0, 70.0])


def test_ensemble_weights_favour_candidates_agreeing_with_the_newest_chunk():
    ens = AdaptiveEnsembler(horizon=2, alpha=0.1)
    ens.update(np.array([[1.0, 0.0], [0.0, 1.0]]))  # its row 1 (orthogonal to the next reference) weighs less
    out = ens.update(np.array([[1.0, 0.0], [1.0, 0.0]]))
    w_new, w_old = np.exp(0.1), 1.0
    np.testing.assert_allclose(
        out, (w_new * np.array([1.0, 0.0]) + w_old * np.array([0.0, 1.0])) / (w_new + w_old)
    )


def test_chunk_executor_resets_per_env_and_executes_fixed_elements():
    chunks = np.arange(2 * 4 * 3, dtype=float).reshape(2, 4, 3) + 1.0
    np.testing.assert_allclose(ChunkExecutor(EnsembleCfg(action_index=2), 2)(chunks), chunks[:, 2])
    executor = ChunkExecutor(ENSEMBLE, 2)
    executor(chunks)
    executor.reset([0])
    out = executor(chunks + 100.0)
    np.testing.assert_allclose(out[0], chunks[0, 0] + 100.0)  # env 0 restarted: only the newest chunk
    assert not np.allclose(out[1], chunks[1, 0] + 100.0)  # env 1 still averages two chunks
    with pytest.raises(ValueError, match="outside"):
        ChunkExecutor(EnsembleCfg(action_index=4), 2)(chunks)


# ------------------------------------------------------------- reference policies reproduce their own success
def env_for(num_envs: int, seed: int, **task) -> MobileManiEnv:
    return MobileManiEnv(EnvCfg(num_envs=num_envs, seed=seed, task=TaskCfg(**task)))


class BaseFrameScripted(ScriptedEvalPolicy):
    """The scripted policy's actions encoded in the base frame: exercises the harness's decoding to world."""

    action_frame = "base"

    def act(self, obs):
        return action_to_base(super().act(obs), self.policy.env.frames.base_quat[:, None])


@pytest.mark.parametrize(
    "task",
    [dict(object="test/box", skill="open"), dict(object="test/box", skill="close", scene="tabletop/17")],
)
def test_scripted_policy_through_the_harness_reproduces_its_own_success(task):
    seed, n = 5, 12
    env = env_for(n, seed, **task)
    own = run_first_episodes(env, ScriptedPolicy(env), seed).success.mean()
    harness = run_batch(
        env_for(n, seed, **task), ScriptedEvalPolicy(), seed, "open box", ENSEMBLE
    ).success.mean()
    base = run_batch(env_for(n, seed, **task), BaseFrameScripted(), seed, "open box", ENSEMBLE).success.mean()
    assert own > 0.5
    assert abs(harness - own) <= 0.02 and abs(base - own) <= 0.02


def test_random_policy_scores_near_zero():
    stats = run_batch(
        env_for(12, 1, object="test/box", skill="open"), RandomPolicy(), 1, "open box", ENSEMBLE
    )
    assert stats.success.mean() <= 0.1


def test_tiny_ppo_teacher_through_the_harness_reproduces_its_own_evaluation(tmp_path):
    run_dir = tmp_path / "run"
    train_ppo(compose_cfg("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]))
    checkpoint = latest_checkpoint(run_dir)
    own = evaluate_teacher(checkpoint, episodes=16, seed=3)["success_rate"]
    env_cfg = to_dataclass(OmegaConf.load(run_dir / CONFIG), RLCfg).env_cfg()
    env_cfg.num_envs = 16
    stats = run_batch(MobileManiEnv(env_cfg), TeacherEvalPolicy(str(checkpoint)), 3, "open box", ENSEMBLE)
    assert abs(stats.success.mean() - own) <= 0.02
    # The g1 teacher over xhand's protocol stops before anything is written.
    xhand = eval_cfg(
        tmp_path / "xhand", ["robot=xhand", "eval/policy=teacher", f"policy.checkpoint={checkpoint}"]
    )
    with pytest.raises(ValueError, match=f"{checkpoint} was trained for robot=g1, not robot=xhand"):
        evaluate(xhand)
    assert not (tmp_path / "xhand").exists()


def test_a_teacher_trained_on_since_is_not_counted_into_its_earlier_results(tmp_path):
    """Teachers are looked up per task under policy.runs_dir; after more iterations the lookup finds a newer
    checkpoint, whose episodes a rerun under the same name would have added to the older one's."""
    runs = tmp_path / "runs"
    run = ["rl/ppo=tiny", "task.object=box", "task.skill=open", f"run_dir={runs / 'g1/box/open'}"]
    train_ppo(compose_cfg("rl", [*run, "rl.ppo.max_iterations=2"]))
    first = latest_checkpoint(runs / "g1/box/open")
    cfg = eval_cfg(tmp_path / "eval", ["eval/policy=teacher", f"policy.runs_dir={runs}"])
    evaluate(cfg)
    saved = json.loads((tmp_path / "eval/g1/default/config.json").read_text())["task_checkpoints"]
    assert saved == {"g1 box/0010 open": str(first)}
    evaluate(cfg)  # the same teacher: nothing to run
    train_ppo(compose_cfg("rl", [*run, "rl.ppo.max_iterations=4"]))
    newer = latest_checkpoint(runs / "g1/box/open")
    with pytest.raises(
        ConfigMismatchError, match=f"other settings \\(g1 box/0010 open: {first} -> {newer}\\)"
    ):
        evaluate(cfg)


@pytest.mark.slow
def test_trained_box_teacher_reproduces_its_success_rate():
    """The real g1 open test/box checkpoint: 256 episodes, seed 1000, as `python -m mobilemani_rl.rl.eval`."""
    checkpoint = latest_checkpoint(ROOT / "outputs/rl/g1/test/box/open")
    if checkpoint is None:
        pytest.skip(
            "no trained teacher in outputs/rl/g1/test/box/open (make rl ROBOT=g1 OBJECT=test/box SKILL=open)"
        )
    own = evaluate_teacher(checkpoint, episodes=256, seed=1000)["success_rate"]
    env_cfg = to_dataclass(OmegaConf.load(checkpoint.parent / CONFIG), RLCfg).env_cfg()
    env_cfg.num_envs = 256
    stats = run_batch(MobileManiEnv(env_cfg), TeacherEvalPolicy(str(checkpoint)), 1000, "open box", ENSEMBLE)
    print(f"teacher success: own evaluation {own:.4f}, through the harness {stats.success.mean():.4f}")
    assert abs(stats.success.mean() - own) <= 0.02


# ---------------------------------------------------------------- the protocol: records, resume, summaries
def eval_cfg(tmp_path: Path, overrides: list[str]):
    base = [
        "eval/protocol=small",
        "subset.categories=[box]",
        "subset.skills=[open]",
        "episodes_per_batch=2",
        f"output_dir={tmp_path}",
        "env.episode_length=40",
    ]
    return compose_eval_cfg([*base, *overrides])


def test_missing_teachers_are_named_before_anything_is_written(tmp_path):
    runs = tmp_path / "runs"
    cfg = eval_cfg(
        tmp_path / "out",
        [
            "eval/policy=teacher",
            f"policy.runs_dir={runs}",
            "subset.categories=[box,cart]",
            "subset.skills=null",
        ],
    )
    each = r"for 4 of 4 object-skill tasks \(box/0010 close, box/0010 open, cart/0012 pull, cart/0012 push\)"
    with pytest.raises(FileNotFoundError, match=f"no PPO teacher in policy.runs_dir={runs} {each}"):
        evaluate(cfg)
    assert not (tmp_path / "out").exists()


def test_a_second_evaluation_under_the_same_name_stops_instead_of_appending_twice(tmp_path):
    cfg = eval_cfg(tmp_path, ["eval/policy=scripted", "name=scripted"])
    path = tmp_path / "g1" / "scripted" / "test_objects_test_scenes.jsonl"
    with ResultsFile(path):  # the first evaluation, still running
        with pytest.raises(InputError, match=f"another evaluation is writing {path}"):
            evaluate(cfg)
        assert not (path.parent / "config.json").exists()
    evaluate(cfg)  # the lock goes with the first
    assert len(read_records(path)) == 2


@pytest.mark.slow
def test_a_killed_evaluation_reruns_to_exact_counts(tmp_path):
    """kill -9 after the first block: the rerun gets the lock the dead run held, runs only the missing
    episodes, and the results hold each episode once."""
    command = [
        sys.executable,
        "-m",
        "mobilemani_vla.eval.evaluate",
        "eval/policy=random",
        "eval/protocol=small",
    ]
    command += ["episodes_per_batch=1", f"output_dir={tmp_path}"]
    path = tmp_path / "g1" / "default" / "test_objects_test_scenes.jsonl"
    run = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while not (path.is_file() and path.read_text()) and time.time() < deadline and run.poll() is None:
        time.sleep(0.01)
    run.kill()
    run.wait()
    assert 1 <= len(read_records(path)) < 10, "the kill should land between the first and the last block"
    rerun = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    assert rerun.returncode == 0, rerun.stderr
    keys = [record_key(r) for r in read_records(path)]
    assert len(keys) == len(set(keys)) == 10


def test_protocol_records_are_seeded_resumable_and_summarised(tmp_path):
    cfg = eval_cfg(tmp_path, ["eval/policy=scripted", "name=scripted", "subset.episodes=4"])
    summary = evaluate(cfg)
    path = tmp_path / "g1" / "scripted" / "test_objects_test_scenes.jsonl"
    records = read_records(path)
    assert [r["episode"] for r in records] == [0, 1, 2, 3]
    assert {r["object_id"] for r in records} == {"box/0010"} and records[0]["scene"] == "tabletop/16"
    assert records[0]["instruction"] == "open box" and records[0]["seed"] != records[2]["seed"]
    assert summary["per_skill"]["open"]["episodes"] == 4 and "box" in summary["per_category"]
    # A rerun adds nothing; a line cut off by a kill is dropped and its episodes are run again, identically.
    evaluate(cfg)
    assert read_records(path) == records
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:2]) + lines[2][:20])
    evaluate(cfg)
    assert sorted(read_records(path), key=lambda r: r["episode"]) == records
    with pytest.raises(ValueError, match="multiple"):
        evaluate(eval_cfg(tmp_path, ["eval/policy=scripted", "subset.episodes=3"]))


def test_small_protocol_runs_as_written_and_reports_totals_and_eta(tmp_path, capsys):
    """PROTOCOL=small (2 episodes) with the root's episodes_per_batch=10: one batch of 2, the same seeds as an
    explicit episodes_per_batch=2, and the total up front with an ETA per batch."""
    protocol = [
        "eval/protocol=small",
        "eval/policy=random",
        "subset.categories=[box]",
        "subset.skills=[open]",
        "env.episode_length=20",
    ]
    cfg = to_dataclass(
        with_env_task(compose_cfg("eval", [*protocol, f"output_dir={tmp_path / 'default'}"])), EvalCfg
    ).check()
    assert cfg.episodes_per_batch == 10 and cfg.batch_size == 2
    evaluate(cfg)
    out = capsys.readouterr().out
    assert (
        "random on test_objects_test_scenes: 1 combinations x 2 episodes = 2 episodes; 0 done, 2 to run"
        in out
    )
    assert "block 0: success" in out and "| 2/2 episodes, " in out and " ETA 0s" in out
    explicit = to_dataclass(
        with_env_task(
            compose_cfg("eval", [*protocol, f"output_dir={tmp_path / 'explicit'}", "episodes_per_batch=2"])
        ),
        EvalCfg,
    ).check()
    evaluate(explicit)
    split = "g1/default/test_objects_test_scenes.jsonl"
    assert [r["seed"] for r in read_records(tmp_path / "default" / split)] == [
        r["seed"] for r in read_records(tmp_path / "explicit" / split)
    ]
    evaluate(cfg)  # a finished protocol says so up front and runs nothing
    assert "2 episodes; 2 done, 0 to run" in capsys.readouterr().out
    # Other settings under the same name would pass the old episodes off as theirs: refused, naming them.
    changed = to_dataclass(
        with_env_task(
            compose_cfg("eval", [*protocol, f"output_dir={tmp_path / 'default'}", "env.episode_length=12"])
        ),
        EvalCfg,
    ).check()
    with pytest.raises(ConfigMismatchError, match=r"env.episode_length: 20 -> 12"):
        evaluate(changed)


def test_an_evaluation_stopped_by_its_minutes_looks_unfinished_and_a_rerun_completes_it(tmp_path, capsys):
    """piece_minutes: no block starts after the budget; the results so far stay resumable, without the
    summary that marks a finished run, and the same command runs the rest."""
    cfg = eval_cfg(
        tmp_path, ["eval/policy=random", "subset.episodes=4", "env.episode_length=8", "piece_minutes=1e-6"]
    )
    results = tmp_path / "g1" / "default" / "test_objects_test_scenes.jsonl"
    evaluate(cfg)  # 4 episodes in blocks of 2: the first block ends past the budget
    assert len(read_records(results)) == 2 and not summary_path(results).exists()
    assert "piece_minutes reached with 1 blocks left: a rerun resumes" in capsys.readouterr().out
    cfg.piece_minutes = 0
    summary = evaluate(cfg)
    assert summary["episodes"] == 4 and finished(results, read_records(results))


def test_tiny_vla_runs_the_protocol_end_to_end(tmp_path):
    root = write_synthetic_dataset(tmp_path / "data", episodes=2, length=20)
    vla_cfg = to_dataclass(
        compose_cfg(
            "vla",
            [
                "vla/model=tiny",
                "vla/train=cpu",
                f"data.root={root}",
                "data.repo_id=synthetic/g1",
                f"train.output_dir={tmp_path / 'vla'}",
                "train.logger=none",
                "train.progress=false",
                "train.batch_size=2",
                "train.steps=2",
                "data.heldout_episodes=1",
                "inputs.states=[wrist_pose,grasp_point,goal_point]",
            ],
        ),
        VLACfg,
        ignore=ROOT_ONLY,
    ).validate()
    checkpoint = train_vla(vla_cfg).checkpoint
    cfg = eval_cfg(
        tmp_path / "results",
        [f"policy.checkpoint={checkpoint}", "name=tiny_vla", "video_episodes=1", "env.episode_length=12"],
    )  # rendered at the dataset's 48 x 64
    summary = evaluate(cfg)
    run = tmp_path / "results" / "g1" / "tiny_vla"
    records = read_records(run / "test_objects_test_scenes.jsonl")
    assert len(records) == 2 and all(r["policy"] == "vla" and r["length"] <= 12 for r in records)
    assert summary["overall"]["episodes"] == 2
    config = json.loads((run / "config.json").read_text())
    assert "observation.images.wrist_depth" in config["policy_inputs"]
    training = config["policy_training"]  # what the tables' captions state of the run
    assert (training["model"], training["steps"], training["samples"]) == ("tiny", 2, 4)
    assert training["image_size"] == [48, 64] and training["train_episodes"] >= 1
    assert len(list((run / "videos").rglob("*.mp4"))) == 1
    assert summary["nan_action_entries"] == 0 and all(r["nan_actions"] == 0 for r in records)
    # New weights under the same checkpoint path (a model trained again) are not counted into these results.
    assert evaluate(cfg)["episodes"] == 2  # the same weights: nothing to run
    weights = checkpoint / "model.safetensors"
    retrained = {k: t + 1 if t.is_floating_point() else t for k, t in load_file(weights).items()}
    save_file(retrained, weights)
    with pytest.raises(ConfigMismatchError, match="policy weights sha256 .* -> "):
        evaluate(cfg)
    assert len(read_records(run / "test_objects_test_scenes.jsonl")) == 2
    # A g1 checkpoint on xhand stops before anything is written (7-d actions for an 18-d robot).
    xhand = eval_cfg(tmp_path / "xhand", [f"policy.checkpoint={checkpoint}", "robot=xhand", "name=tiny_vla"])
    with pytest.raises(ValueError, match="7-d actions but robot=xhand takes 18-d"):
        evaluate(xhand)
    assert not (tmp_path / "xhand").exists()
    # The training run's directory instead of one of its checkpoints: the error names the newest checkpoint.
    for given in (checkpoint.parent.parent, checkpoint.parent):
        mistaken = eval_cfg(tmp_path / "run_dir", [f"policy.checkpoint={given}", "name=tiny_vla"])
        with pytest.raises(FileNotFoundError, match=f"the newest of the 1 it holds is {checkpoint}$"):
            evaluate(mistaken)
    assert not (tmp_path / "run_dir").exists()


def test_workers_run_blocks_in_parallel_with_the_same_episodes(tmp_path, capsys):
    """Blocks spread over two worker processes give the records of one process, episode by episode."""
    runs = {}
    for workers in (1, 2):
        cfg = eval_cfg(
            tmp_path / str(workers),
            ["eval/policy=random", "name=random", "subset.episodes=4", f"workers={workers}"],
        )
        evaluate(cfg)
        records = read_records(tmp_path / str(workers) / "g1" / "random" / "test_objects_test_scenes.jsonl")
        runs[workers] = sorted(records, key=lambda r: r["episode"])
    assert [r["episode"] for r in runs[2]] == [0, 1, 2, 3]
    assert runs[2] == runs[1]
    assert "| 4/4 episodes, " in capsys.readouterr().out
    with pytest.raises(InputError, match="workers=2"):
        evaluate(cfg, RandomPolicy())
