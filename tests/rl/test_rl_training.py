"""PPO teacher training with the tiny preset: checkpoints load and evaluate, runs resume after a kill."""

import itertools
import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import torch
from checkout import ROOT, checkout_env
from hydra import compose, initialize_config_dir

from mobilemani_rl.rl.eval import evaluate
from mobilemani_rl.rl.factory import policy_objects
from mobilemani_rl.rl.run_dir import ConfigRules, latest_checkpoint, save_or_check_config
from mobilemani_rl.rl.runner import _shown
from mobilemani_rl.rl.train import train
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError
from mobilemani_rl.utils.writer_lock import TRAIN_LOCK, WriterLock


def compose_rl(overrides: list[str]):
    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        return compose(config_name="rl", overrides=overrides)


def test_tiny_training_checkpoint_loads_and_evaluates(tmp_path):
    run_dir = tmp_path / "run"
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}"]))
    assert (run_dir / "result.json").exists() and (run_dir / "config.yaml").exists()
    curve = json.loads((run_dir / "curve.json").read_text())
    assert [point["iteration"] for point in curve] == [0, 1, 2]
    checkpoint = latest_checkpoint(run_dir)
    assert checkpoint.name == "model_2.pt"
    result = evaluate(checkpoint, episodes=4, seed=3)
    box = result["objects"]["test/box"]
    assert box["episodes"] == 4 and 0.0 <= result["success_rate"] <= 1.0
    assert box["reward_terms"]["diff_hand_object"] < 0.0
    assert (run_dir / "eval_model_2_3.json").exists()
    # A finished run is left alone.
    before = sorted(p.name for p in run_dir.iterdir())
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}"]))
    assert sorted(p.name for p in run_dir.iterdir()) == before


def test_resume_with_another_config_is_refused(tmp_path):
    run_dir = tmp_path / "run"
    (run_dir).mkdir()
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1"]))
    (run_dir / "result.json").unlink()  # pretend it was interrupted
    with pytest.raises(ConfigMismatchError, match="different rl config"):
        train(
            compose_rl(
                ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1", "rl.ppo.learning_rate=0.1"]
            )
        )
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1"]))  # finishes it
    with pytest.raises(ConfigMismatchError, match="different rl config"):  # not "nothing to do"
        train(
            compose_rl(
                ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1", "rl.ppo.learning_rate=0.1"]
            )
        )


def test_a_finished_run_asked_for_more_iterations_goes_on_and_fewer_is_refused(tmp_path, capsys):
    run_dir = tmp_path / "run"
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=2"]))
    fewer = r"max_iterations: 2 -> 1.*only rl.ppo.max_iterations may grow"
    with pytest.raises(ConfigMismatchError, match=fewer):
        train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1"]))
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=4"]))
    out = capsys.readouterr().out
    assert "max_iterations=4" in out and "resuming" in out and "from model_1.pt (iteration 2 of 4)" in out
    result = json.loads((run_dir / "result.json").read_text())
    assert result["iterations"] == 4 and result["samples"] == 4 * 8 * 8
    assert latest_checkpoint(run_dir).name == "model_3.pt"
    curve = json.loads((run_dir / "curve.json").read_text())
    assert [row["iteration"] for row in curve] == [0, 1, 2, 3]  # the first two iterations are kept
    assert "max_iterations: 4" in (run_dir / "config.yaml").read_text()
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=4"]))
    assert "nothing to do" in capsys.readouterr().out


def test_a_run_that_stopped_before_its_first_checkpoint_takes_the_corrected_config(tmp_path):
    run_dir = tmp_path / "run"
    save_or_check_config(
        run_dir,
        compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.learning_rate=-1"]),
        ConfigRules(("rl",)),
    )  # what a run that crashed at start leaves behind
    train(compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1"]))
    assert (run_dir / "result.json").exists()


def test_a_second_training_run_on_the_same_run_dir_stops_before_writing(tmp_path):
    """Two processes training one run directory would interleave their checkpoints and curves."""
    run_dir = tmp_path / "run"
    cfg = compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.max_iterations=1"])
    with WriterLock(run_dir / TRAIN_LOCK, "the first run"):
        with pytest.raises(InputError, match=f"another training run is writing {run_dir}; wait for it"):
            train(cfg)
        assert [p.name for p in run_dir.iterdir()] == [TRAIN_LOCK]
    train(cfg)
    assert (run_dir / "result.json").exists()


def test_killed_training_resumes_from_last_checkpoint(tmp_path):
    run_dir = tmp_path / "run"
    command = [
        sys.executable,
        "-m",
        "mobilemani_rl.rl.train",
        "rl/ppo=tiny",
        f"run_dir={run_dir}",
        "rl.ppo.max_iterations=8",
        "rl.ppo.num_steps_per_env=32",
    ]
    env = checkout_env()
    proc = subprocess.Popen(command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    deadline = time.time() + 120
    while (run_dir / "model_2.pt").exists() is False and time.time() < deadline and proc.poll() is None:
        time.sleep(0.1)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert (run_dir / "model_2.pt").exists() and not (run_dir / "result.json").exists()
    # A kill during a save leaves at most a `.tmp`; every file under a checkpoint's name is whole.
    for checkpoint in run_dir.glob("model_*.pt"):
        torch.load(checkpoint, weights_only=True)
    killed_at = latest_checkpoint(run_dir)
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    start = int(killed_at.stem.split("_")[1]) + 1
    assert f"resuming {run_dir} from {killed_at.name} (iteration {start} of 8)" in done.stdout
    assert latest_checkpoint(run_dir).name == "model_7.pt" and (run_dir / "result.json").exists()
    assert not list(run_dir.glob("*.tmp"))  # the rerun's saves replace a `.tmp` the kill left
    curve = json.loads((run_dir / "curve.json").read_text())
    assert [row["iteration"] for row in curve] == list(range(8))  # the iterations before the kill are kept
    # samples and seconds count the whole run across the resume
    assert [row["samples"] for row in curve] == [(i + 1) * curve[0]["samples"] for i in range(8)]
    assert all(a["seconds"] < b["seconds"] for a, b in itertools.pairwise(curve))


def test_multi_object_policy_trains_over_a_category_and_evaluates_per_split(tmp_path):
    run_dir = tmp_path / "laptops"
    train(
        compose_rl(
            [
                "rl/ppo=tiny",
                f"run_dir={run_dir}",
                "task.object=laptop",
                "objects_per_policy=2",
                "rl.ppo.max_iterations=1",
            ]
        )
    )
    result = evaluate(latest_checkpoint(run_dir), episodes=2, seed=0)
    assert set(result["success_by_split"]) == {"train", "test"}
    assert len(result["objects"]) == 36  # laptop: 30 train + 6 test objects
    # The headline is the policy's own task: the two objects it trained on, not the category's 36.
    trained = [oid for oid, entry in result["objects"].items() if entry["trained"]]
    assert trained == policy_objects("laptop", 2)
    assert result["success_rate"] == np.mean([result["objects"][oid]["success_rate"] for oid in trained])


def test_the_run_result_keeps_the_last_measured_success_not_a_nan():
    from mobilemani_rl.rl.train import last_measured_success

    curve = [{"success": 0.5}, {"success": 0.75}, {"success": float("nan")}]
    assert last_measured_success(curve) == 0.75
    assert last_measured_success([{"success": float("nan")}]) is None


def test_an_unreadable_newest_checkpoint_falls_back_to_the_previous_one(tmp_path, capsys):
    run_dir = tmp_path / "run"
    cfg = compose_rl(["rl/ppo=tiny", f"run_dir={run_dir}"])
    train(cfg)
    (run_dir / "result.json").unlink()
    newest = latest_checkpoint(run_dir)
    newest.write_bytes(newest.read_bytes()[:100])  # cut short
    train(cfg)
    out = capsys.readouterr().out
    assert f"skipping an unreadable checkpoint: cannot load teacher checkpoint {newest}" in out
    assert "resuming" in out and (run_dir / "result.json").exists()
    assert [row["iteration"] for row in json.loads((run_dir / "curve.json").read_text())] == [0, 1, 2]


def test_update_runs_with_its_own_thread_count(monkeypatch):
    """Collection keeps `torch_threads` (MuJoCo has the cores); the PPO update runs with `update_threads`."""
    from rsl_rl.algorithms import PPO

    from mobilemani_rl.rl.factory import build_runner

    seen: list[int] = []
    monkeypatch.setattr(PPO, "update", lambda self: seen.append(torch.get_num_threads()) or {})
    previous = torch.get_num_threads()
    try:
        runner = build_runner(
            compose_rl(["rl/ppo=tiny", "rl.ppo.torch_threads=1", "rl.ppo.update_threads=2"]), run_dir=None
        )
        runner.alg.update()
        assert seen == [2] and torch.get_num_threads() == 1
    finally:
        torch.set_num_threads(previous)


@pytest.mark.parametrize("precision", ["fp32", "bf16"])
def test_precision_sets_the_update_dtype(precision):
    """`rl.ppo.precision=bf16` runs the hidden layers in bf16 (bf16 matmuls are ~4x faster than fp32 on
    AVX512-BF16 cores), in the update and in collection's inference alike, and keeps the output layers
    (values, action means) in fp32; the update stays finite."""
    from mobilemani_rl.rl.factory import build_runner

    runner = build_runner(compose_rl(["rl/ppo=tiny", f"rl.ppo.precision={precision}"]), run_dir=None)
    assert runner.alg.optimizer.defaults["fused"]
    # (layer, grad enabled: in the update) -> the dtypes the layer output
    seen: dict[tuple[str, bool], set[torch.dtype]] = {}
    for model in (runner.alg.actor, runner.alg.critic):
        layers = [m for m in model.modules() if isinstance(m, torch.nn.Linear)]
        for name, layer in (("hidden", layers[0]), ("output", layers[-1])):
            layer.register_forward_hook(
                lambda _m, _i, out, name=name: seen.setdefault((name, torch.is_grad_enabled()), set()).add(
                    out.dtype
                )
            )
    update = runner.alg.update
    losses: list[dict] = []
    runner.alg.update = lambda: losses.append(update()) or losses[-1]
    runner.learn(num_learning_iterations=1)
    hidden = {torch.bfloat16 if precision == "bf16" else torch.float32}
    assert seen[("hidden", False)] == seen[("hidden", True)] == hidden
    assert seen[("output", False)] == seen[("output", True)] == {torch.float32}
    assert losses and all(np.isfinite(v) for v in losses[0].values() if v is not None)


def test_hidden_activations_run_in_place_and_keep_the_gradient():
    """The ELUs overwrite the linear outputs (no backward reads those) and differentiate from their own
    output: the fp32 gradient is the one out-of-place ELUs give, up to rounding."""
    from mobilemani_rl.rl.factory import build_runner

    runner = build_runner(compose_rl(["rl/ppo=tiny", "rl.ppo.precision=fp32"]), run_dir=None)
    obs = runner.env.get_observations()

    def gradient(model: torch.nn.Module) -> torch.Tensor:
        model.zero_grad()
        model(obs).square().sum().backward()
        return torch.cat([p.grad.flatten() for p in model.parameters() if p.grad is not None])

    for model in (runner.alg.actor, runner.alg.critic):
        elus = [m for m in model.modules() if isinstance(m, torch.nn.ELU)]
        assert elus and all(m.inplace for m in elus)
        in_place = gradient(model)
        for m in elus:
            m.inplace = False
        assert in_place.abs().sum() > 0
        torch.testing.assert_close(in_place, gradient(model), rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize(
    ("avx512_bf16", "amx", "aten", "onednn", "chosen"),
    [
        (True, False, "AVX512", None, "bf16"),
        (False, True, "AVX512", "AVX512_CORE_AMX", "bf16"),
        (False, False, "AVX512", None, "fp32"),
        # bf16 hardware, but torch held to AVX2 as on a CPU without AVX-512: bf16 would run emulated
        (True, True, "AVX2", None, "fp32"),
        (True, False, "AVX512", "AVX2", "fp32"),
    ],
)
def test_auto_precision_is_bf16_only_where_torch_multiplies_bf16_natively(
    monkeypatch, avx512_bf16, amx, aten, onednn, chosen
):
    from mobilemani_rl.rl.config import PpoCfg, update_precision

    monkeypatch.setattr(torch.cpu, "_is_avx512_bf16_supported", lambda: avx512_bf16)
    monkeypatch.setattr(torch.cpu, "_is_amx_tile_supported", lambda: amx)
    monkeypatch.setattr(torch.backends.cpu, "get_cpu_capability", lambda: aten)
    if onednn is None:
        monkeypatch.delenv("ONEDNN_MAX_CPU_ISA", raising=False)
    else:
        monkeypatch.setenv("ONEDNN_MAX_CPU_ISA", onednn)
    assert update_precision(PpoCfg(precision="auto")) == chosen
    assert update_precision(PpoCfg(precision="fp32")) == "fp32"


@pytest.mark.parametrize("device", ["cpu"] + (["cuda"] if torch.cuda.is_available() else []))
def test_ppo_trains_on_its_device_and_the_teacher_evaluates_on_the_cpu(tmp_path, device):
    """`rl.ppo.device` holds PPO's networks (the warm start, collection's inference and the update) while the
    env stays on the CPU; a teacher trained on any device loads on the CPU, beside MuJoCo, to evaluate."""
    run_dir = tmp_path / "run"
    overrides = ["rl/ppo=tiny", f"run_dir={run_dir}", f"rl.ppo.device={device}"]
    train(compose_rl([*overrides, "rl.ppo.warm_start.episodes=8", "rl.ppo.warm_start.epochs=2"]))
    checkpoint = latest_checkpoint(run_dir)
    saved = torch.load(checkpoint, weights_only=True)["actor_state_dict"]
    assert {t.device.type for t in saved.values()} == {torch.device(device).type}
    result = evaluate(checkpoint, episodes=4, seed=3)
    assert result["objects"]["test/box"]["episodes"] == 4


def test_the_progress_bar_shows_a_dash_until_an_episode_has_ended():
    assert _shown(float("nan"), ".2f") == "-"
    assert _shown(0.5, ".2f") == "0.50"
    assert _shown(-85.34, ".1f") == "-85.3"
