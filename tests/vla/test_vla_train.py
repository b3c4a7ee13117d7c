"""MobileManiVLA on a generated LeRobot dataset: batches, experiment configs, checkpoints,
resume, inference."""

import json
import threading
from pathlib import Path

import numpy as np
import pytest
import torch
from checkout import ROOT
from hydra import compose, initialize_config_dir
from payload import PlantedCode

from mobilemani_data import schema
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import InputError
from mobilemani_rl.utils.writer_lock import TRAIN_LOCK, WriterLock
from mobilemani_vla import checkpoint_diagnostics
from mobilemani_vla.config import ROOT_ONLY, VLACfg
from mobilemani_vla.data import frame_cache
from mobilemani_vla.data.dataset import fit_normalizer, open_data
from mobilemani_vla.data.frame_cache import cache_dir
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.inference import VLAPolicy
from mobilemani_vla.model.network import build_model
from mobilemani_vla.model.processor import VLAProcessor, camera_key, resize_images
from mobilemani_vla.model.tokenizer import build_word_tokenizer
from mobilemani_vla.train import train, trim_diagnostics

CONF = str(ROOT / "conf")
EXPERIMENTS = sorted(p.stem for p in (Path(CONF) / "experiment").glob("ablation_*.yaml"))
# the paper's name for a row, and the main model's second row
ALIASES = {"ablation_depth": "ablation_image_head_rgbd", "ablation_state_wrist_pose": "ablation_image_all"}


@pytest.fixture(scope="module")
def dataset_root(tmp_path_factory) -> Path:
    return write_synthetic_dataset(tmp_path_factory.mktemp("vla") / "g1", episodes=2, length=20)


def tiny_overrides(root: Path, out: Path) -> list[str]:
    """The tiny model and a quiet CPU training on the synthetic dataset at `root`, written to `out`."""
    return [
        "vla/model=tiny",
        "vla/train=cpu",
        f"data.root={root}",
        "data.repo_id=synthetic/g1",
        "data.heldout_episodes=1",
        f"train.output_dir={out}",
        "train.logger=none",
        "train.progress=false",
        "train.batch_size=4",
    ]


def tiny_cfg(root: Path, out: Path, overrides: list[str] = ()) -> VLACfg:
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        return to_dataclass(
            # The caller's overrides come last, so they win over the tiny defaults.
            compose(config_name="vla", overrides=[*tiny_overrides(root, out), *overrides]),
            VLACfg,
            ignore=ROOT_ONLY,
        ).validate()


def test_a_new_output_directory_is_made_before_the_first_diagnostics(dataset_root, tmp_path):
    out = tmp_path / "runs" / "new"
    train(tiny_cfg(dataset_root, out, ["train.steps=2", "train.diagnose_every=1", "train.save_every=100"]))
    lines = (out / "diagnostics.jsonl").read_text().splitlines()
    assert [json.loads(line)["step"] for line in lines] == [0, 1, 2]  # the untrained model's first


@pytest.mark.slow
def test_a_compiled_training_run_saves_plain_weights_that_an_uncompiled_run_resumes(dataset_root, tmp_path):
    """train.compile=true compiles the trained model in place: it trains, its checkpoint holds the plain
    model's keys (no compile wrapper's prefix), and a run without compiling resumes from it."""
    from safetensors import safe_open

    compiled = train(tiny_cfg(dataset_root, tmp_path, ["train.steps=2", "train.compile=true"]))
    assert len(compiled.losses) == 2 and np.isfinite(compiled.losses).all()
    with safe_open(str(compiled.checkpoint / "model.safetensors"), "pt") as weights:
        assert set(weights.keys()) == set(compiled.model.state_dict())
    resumed = train(tiny_cfg(dataset_root, tmp_path, ["train.steps=3"]))
    assert len(resumed.losses) == 1 and resumed.checkpoint.name == "step_00000003"


def test_a_second_training_run_on_the_same_output_directory_stops(dataset_root, tmp_path):
    out = tmp_path / "run"
    cfg = tiny_cfg(dataset_root, out, ["train.steps=1", "train.diagnose_every=0"])
    with WriterLock(out / TRAIN_LOCK, "the first run"):
        with pytest.raises(InputError, match=f"another training run is writing {out}; wait for it"):
            train(cfg)
        assert [p.name for p in out.iterdir()] == [TRAIN_LOCK]
    assert train(cfg).checkpoint.name == "step_00000001"


def test_forward_backward_on_a_dataset_batch(dataset_root, tmp_path):
    cfg = tiny_cfg(dataset_root, tmp_path)
    data = open_data(cfg, 32, progress=False)
    tokenizer = build_word_tokenizer()
    normalizer = fit_normalizer(data.table, data.table.rows(data.train_episodes), cfg.inputs.states)
    model = build_model(cfg, tokenizer)
    processor = VLAProcessor(
        tokenizer, normalizer, cfg.inputs.cameras, cfg.inputs.states, 32, cfg.model.prompt
    )
    frames = [data.train[i] for i in (0, 7, 18, 19)]  # the last two run past the episode end
    batch = processor(frames)
    assert batch["pixel_values"].shape == (4, 4, 3, 32, 32)
    assert batch["actions"].shape == (4, 16, 7) and batch["state"].shape == (4, 9)
    assert batch["actions"].abs().max() <= 1.0
    # Padded rows: the normalised zero wrist delta ("hold still"), the last gripper target kept.
    still = normalizer.normalize(schema.ACTION, torch.zeros(7))
    assert torch.allclose(batch["actions"][3, 1:, :6], still[:6].expand(15, 6))
    assert torch.allclose(batch["actions"][3, 1:, 6], batch["actions"][3, 0, 6].expand(15))
    loss = model(batch)
    assert torch.isfinite(loss)
    torch.nn.init.normal_(model.head.dit.out.weight, std=0.02)  # zero-initialised: no gradient flows back yet
    # the paper config's memory saver keeps gradients flowing
    model.backbone.vlm.gradient_checkpointing_enable()
    model(batch).backward()
    for part in (
        model.backbone.vlm.vision_tower,
        model.backbone.vlm.language_model,
        model.head.dit.blocks,
        model.state_encoder,
    ):
        assert any(p.grad is not None and p.grad.abs().sum() > 0 for p in part.parameters())
    assert model.backbone.cognition.grad.abs().sum() > 0


def test_cognition_targets_add_a_read_out_loss_and_its_diagnostic(dataset_root, tmp_path):
    targets = ["train.cognition_targets=[grasp_point]", "train.cognition_target_weight=0.5"]
    cfg = tiny_cfg(dataset_root, tmp_path, targets)
    data = open_data(cfg, 32, progress=False)
    normalizer = fit_normalizer(data.table, data.table.rows(data.train_episodes), cfg.read_states)
    model = build_model(cfg, build_word_tokenizer())
    processor = VLAProcessor.for_config(cfg, build_word_tokenizer(), normalizer, 32)
    frames = [data.train[i] for i in (0, 5, 11)]
    batch = processor(frames)
    # the target is the grasp point in the base frame, normalised; the state input stays the wrist pose
    grasp = torch.stack([torch.as_tensor(f[schema.GRASP_POINT_BASE]) for f in frames])
    assert torch.allclose(batch["cognition_target"], normalizer.normalize(schema.GRASP_POINT_BASE, grasp))
    assert batch["state"].shape == (3, 9)
    torch.manual_seed(0)
    loss = model(batch)
    torch.manual_seed(0)
    cognition, state = model.condition(batch)
    diffusion = model.head.loss(batch["actions"], cognition, state)
    read_out = model.cognition_probe(cognition)
    assert torch.allclose(loss, diffusion + 0.5 * (read_out - batch["cognition_target"]).pow(2).mean())
    loss.backward()  # the action head's output starts at zero, so only the read-out reaches the cameras yet
    assert any(p.grad.abs().sum() > 0 for p in model.backbone.vlm.vision_tower.parameters())
    # training logs the read-out's held-out error
    out = tmp_path / "run"
    train(tiny_cfg(dataset_root, out, [*targets, "train.steps=1", "train.diagnose_every=1"]))
    last = (out / "diagnostics.jsonl").read_text().splitlines()[-1]
    assert json.loads(last)["step"] == 1 and json.loads(last)["cognition/target_mse"] > 0


def test_the_evaluators_batch_gives_the_model_what_training_frames_give():
    """The evaluator hands the processor one (B, H, W, 3) uint8 view per camera; training, one float frame per
    sample. The model inputs must be the same, bit for bit."""
    from mobilemani_vla.model.normalizer import Normalizer

    cameras, states = ["head_rgb", "wrist_depth"], ["wrist_pose", "grasp_point"]
    bounds = {schema.ACTION: ([-1.0] * 7, [1.0] * 7), schema.STATE: ([-2.0] * 10, [2.0] * 10)}
    bounds[schema.GRASP_POINT_BASE] = ([-1.0] * 3, [3.0] * 3)
    processor = VLAProcessor(build_word_tokenizer(), Normalizer(bounds), cameras, states, 32, "{instruction}")
    rng = np.random.default_rng(0)
    images = {c: rng.integers(0, 256, (3, 70, 90, 3), dtype=np.uint8) for c in cameras}
    vectors = {schema.STATE: rng.normal(size=(3, 10)), schema.GRASP_POINT_BASE: rng.normal(size=(3, 3))}
    tasks = ["open box", "close box", "open box"]
    frames = [
        {
            **{camera_key(c): torch.from_numpy(images[c][i]).permute(2, 0, 1) / 255.0 for c in cameras},
            **{k: torch.as_tensor(v[i], dtype=torch.float32) for k, v in vectors.items()},
            "task": tasks[i],
        }
        for i in range(3)
    ]
    batch = {camera_key(c): torch.from_numpy(images[c]).permute(0, 3, 1, 2) for c in cameras}
    batch.update({k: torch.as_tensor(v, dtype=torch.float32) for k, v in vectors.items()})
    from_frames, from_batch = processor(frames), processor.collate({**batch, "task": tasks})
    assert from_batch["pixel_values"].shape == (3, 2, 3, 32, 32) and from_batch["state"].shape == (3, 12)
    assert from_frames.keys() == from_batch.keys()
    assert all(torch.equal(from_frames[k], from_batch[k]) for k in from_frames)


@pytest.mark.parametrize("experiment", EXPERIMENTS)
def test_experiment_configs_compose_and_train(experiment, dataset_root, tmp_path):
    cfg = tiny_cfg(dataset_root, tmp_path, [f"+experiment={experiment}", "train.steps=2"])
    assert cfg.name == ALIASES.get(experiment, experiment)
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):  # alone it is the paper's 3B setting
        paper = compose(config_name="vla", overrides=[f"+experiment={experiment}"])
    assert (paper.model.name, paper.train.batch_size, paper.train.steps) == ("paligemma2_3b", 120, 160000)
    assert paper.data.root == "outputs/data/ablation/lerobot"  # the ablation dataset, at either scale
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):  # the documented CPU scale
        cpu = compose(
            config_name="vla",
            overrides=[f"+experiment={experiment}", "vla/model=cpu", "vla/train=ablation_cpu"],
        )
    assert (cpu.model.name, cpu.train.batch_size, cpu.train.steps, cpu.train.piece_minutes) == (
        "cpu",
        32,
        30000,
        150,
    )
    assert cpu.inputs == paper.inputs and cpu.data.root == paper.data.root
    result = train(cfg)
    assert len(result.losses) == 2 and np.isfinite(result.losses).all()
    model = result.model
    batch = result.processor([open_data(cfg, 32, progress=False).train[3]])
    tokens = model.backbone.image_tokens(batch["pixel_values"])
    assert tokens.shape[1] == len(cfg.inputs.cameras) * 16  # 32 px / 8 px patches per camera
    state_dims = {"wrist_pose": 9, "grasp_point": 3, "goal_point": 3}
    expected = sum(state_dims[s] for s in cfg.inputs.states)
    if expected:
        assert model.state_encoder.mlp[0].in_features == expected == batch["state"].shape[1]
    else:
        assert model.state_encoder is None and "state" not in batch


def test_checkpoint_resume_and_policy(dataset_root, tmp_path):
    cfg = tiny_cfg(
        dataset_root,
        tmp_path,
        [
            "train.steps=3",
            "train.save_every=2",
            "train.diagnose_every=2",
            "inputs.states=[wrist_pose,grasp_point,goal_point]",
        ],
    )
    first = train(cfg)
    assert [p.name for p in sorted((tmp_path / "checkpoints").iterdir())] == [
        "step_00000002",
        "step_00000003",
    ]
    assert {
        "model.safetensors",
        "ema.safetensors",
        "config.yaml",
        "normalizer.json",
        "dataset.json",
        "tokenizer",
        "backbone_config.json",
    } <= {p.name for p in first.checkpoint.iterdir()}
    assert_records_its_datasets_digest(first.checkpoint, cfg)
    longer = tiny_cfg(
        dataset_root,
        tmp_path,
        ["train.steps=5", "train.diagnose_every=2", "inputs.states=[wrist_pose,grasp_point,goal_point]"],
    )
    resumed = train(longer)
    assert len(resumed.losses) == 2  # steps 4 and 5 only
    diagnostics = [json.loads(line) for line in (tmp_path / "diagnostics.jsonl").read_text().splitlines()]
    assert [d["step"] for d in diagnostics] == [0, 2, 4]  # held-out diagnostics, none repeated by the resume
    keys = {"image", "null_image", "no_state", "null_instruction", "wrong_instruction"}
    assert {f"noise_mse/{k}" for k in keys} | {"open_loop_mse/cfg_1.5", "open_loop_mse/null_image"} <= set(
        diagnostics[-1]
    )
    assert diagnostics[-1]["cognition/spread"] > 0 and diagnostics[-1]["cognition/image_swap"] > 0
    assert json.loads((resumed.checkpoint / "trainer_state.json").read_text()) == {"step": 5}

    fewer = f"train.steps=4, but {resumed.checkpoint} is further on; only train.steps may grow"
    with pytest.raises(ValueError, match=fewer):
        train(
            tiny_cfg(
                dataset_root, tmp_path, ["train.steps=4", "inputs.states=[wrist_pose,grasp_point,goal_point]"]
            )
        )
    with pytest.raises(ValueError, match="different inputs config"):  # same output_dir, other inputs
        train(tiny_cfg(dataset_root, tmp_path, ["train.steps=6"]))
    other_data = write_synthetic_dataset(tmp_path / "other" / "g1", episodes=2, length=20)
    states = "inputs.states=[wrist_pose,grasp_point,goal_point]"
    with pytest.raises(ValueError, match="different data config"):  # same output_dir, another dataset
        train(tiny_cfg(other_data, tmp_path, ["train.steps=6", states]))
    # It trained a new run beside step 5, which the next rerun would then have resumed as this run.
    with pytest.raises(ValueError, match=r"train.resume=false starts a new run, but .* holds step_00000005"):
        train(tiny_cfg(dataset_root, tmp_path, ["train.steps=1", "train.resume=false", states]))
    assert [p.name for p in sorted((tmp_path / "checkpoints").iterdir())] == [
        "step_00000003",
        "step_00000005",
    ]

    policy = VLAPolicy.load(resumed.checkpoint)
    frame = open_data(cfg, 32, progress=False).train[5]
    images = {c: frame[f"observation.images.{c}"].permute(1, 2, 0).numpy() for c in policy.cameras}
    vectors = {k: frame[k].numpy() for k in policy.vector_inputs}
    assert policy.vector_inputs == [schema.STATE, schema.GRASP_POINT_BASE, schema.GOAL_POINT_BASE]
    chunk = policy.predict_action_chunk(images, "open box", vectors, torch.Generator().manual_seed(0))
    again = policy.predict_action_chunk(images, "open box", vectors, torch.Generator().manual_seed(0))
    assert chunk.shape == (16, 7) and np.array_equal(chunk, again)
    lo, hi = policy.processor.normalizer.bounds[schema.ACTION]
    assert np.all(chunk >= lo - 1e-5) and np.all(chunk <= hi + 1e-5)
    # The reloaded weights are the trained ones.
    trained = resumed.model.state_dict()
    assert all(torch.equal(v, trained[k]) for k, v in policy.model.state_dict().items())
    with pytest.raises(KeyError, match="wrist_depth"):
        policy.predict_action_chunk({"head_rgb": images["head_rgb"]}, "open box", vectors)
    with pytest.raises(KeyError, match="object.goal_point_base"):
        policy.predict_action_chunk(images, "open box", {schema.STATE: vectors[schema.STATE]})


def assert_records_its_datasets_digest(checkpoint: Path, cfg) -> None:
    """The checkpoint names its demonstrations by digest (the tables print it): the same frames give the same
    digest, one changed action label another."""
    from mobilemani_vla.checkpoint import training_scale
    from mobilemani_vla.data.dataset import FrameTable, open_metadata, vector_keys

    table = FrameTable.read(open_metadata(cfg), vector_keys(cfg.inputs.states))
    recorded = json.loads((checkpoint / "dataset.json").read_text())["sha256"]
    assert recorded == table.digest() == training_scale(checkpoint, cfg)["dataset_sha256"]
    table.columns["action"] = table.columns["action"].copy()
    table.columns["action"][5, 0] += 1e-6
    assert table.digest() != recorded


def test_a_segmentation_stream_trains_and_acts_as_an_image_input(dataset_root, tmp_path):
    """head_seg / wrist_seg are not among the paper's inputs, but a VLA reads them as any other stream."""
    cameras = ["head_rgb", "wrist_seg"]
    cfg = tiny_cfg(dataset_root, tmp_path, [f"inputs.cameras=[{','.join(cameras)}]", "train.steps=1"])
    policy = VLAPolicy.load(train(cfg).checkpoint)
    assert policy.cameras == cameras
    frame = open_data(cfg, 32, progress=False).train[3]
    images = {
        c: (frame[camera_key(c)].permute(1, 2, 0) * 255).round().to(torch.uint8).numpy() for c in cameras
    }
    vectors = {k: frame[k].numpy() for k in policy.vector_inputs}
    chunk = policy.predict_action_chunk(images, "open box", vectors, torch.Generator().manual_seed(0))
    assert chunk.shape == (16, 7) and np.isfinite(chunk).all()
    with pytest.raises(KeyError, match="wrist_seg"):
        policy.predict_action_chunk({"head_rgb": images["head_rgb"]}, "open box", vectors)


def test_a_checkpoints_diagnostics_are_those_its_training_logged(dataset_root, tmp_path, capsys, monkeypatch):
    out = tmp_path / "run"
    checkpoint = train(tiny_cfg(dataset_root, out, ["train.steps=2", "train.diagnose_every=2"])).checkpoint
    logged = json.loads((out / "diagnostics.jsonl").read_text().splitlines()[-1])
    monkeypatch.setattr("sys.argv", ["checkpoint_diagnostics", str(checkpoint)])
    checkpoint_diagnostics.main()
    again = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert again["checkpoint"] == str(checkpoint) and logged["step"] == 2
    assert {k: round(v, 6) for k, v in again.items() if k != "checkpoint"} == {
        k: round(v, 6) for k, v in logged.items() if k not in ("step", "train_loss")
    }


def test_a_training_state_holding_more_than_tensors_is_refused_on_resume(dataset_root, tmp_path):
    out, marker = tmp_path / "run", tmp_path / "PWNED"
    first = train(tiny_cfg(dataset_root, out, ["train.steps=1", "train.diagnose_every=0"]))
    # a whole torch.save archive (so not skipped as damaged) whose pickle runs code when loaded
    torch.save({"state": PlantedCode(marker)}, first.checkpoint / "optimizer.bin")
    with pytest.raises(
        ValueError, match=f"refusing the training state in {first.checkpoint}: Weights only load failed$"
    ):
        train(tiny_cfg(dataset_root, out, ["train.steps=2", "train.diagnose_every=0"]))
    assert not marker.exists()


@pytest.mark.slow
def test_overfitting_one_episode(tmp_path):
    root = write_synthetic_dataset(tmp_path / "one", episodes=1, length=30)
    overrides = ["train.steps=500", "train.lr=1e-3", "train.batch_size=8", "train.save_every=100000"]
    cfg = tiny_cfg(root, tmp_path / "out", [*overrides, "data.heldout_episodes=0"])  # the one episode trains
    losses = np.array(train(cfg).losses)
    start, end = losses[:5].mean(), losses[-50:].mean()
    print(
        "mean loss per 50 steps:",
        np.round([losses[i : i + 50].mean() for i in range(0, 500, 50)], 3).tolist(),
    )
    assert end < 0.1 * start, (start, end)


def test_frame_cache_is_built_once_reused_and_rebuilt_when_the_dataset_changes(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=12)
    cfg = tiny_cfg(root, tmp_path / "out")  # one episode trains, one is held out
    data = open_data(cfg, 32, progress=False)
    cache = cache_dir(root, cfg.inputs.cameras[0], 32) / "images.npy"
    built = cache.stat().st_mtime_ns
    # Cached frames are the LeRobot-decoded frames resized to the model's input (within uint8 rounding).
    decoded = open_data(tiny_cfg(root, tmp_path / "out", ["data.cache=false"]), 32, progress=False)
    assert len(data.train) == len(decoded.train) == 12
    for i in (0, 5, 11):
        for camera in cfg.inputs.cameras:
            key = f"observation.images.{camera}"
            want = resize_images(decoded.train[i][key][None].float(), 32)[0] * 255.0
            assert (data.train[i][key].float() - want).abs().max() <= 1.0
            assert torch.equal(data.train[i]["action"], decoded.train[i]["action"])
    open_data(cfg, 32, progress=False)
    assert cache.stat().st_mtime_ns == built  # reused
    (root / schema.STATS_FILE).write_text("{}")  # a rerun's statistics report changes no frame
    open_data(cfg, 32, progress=False)
    assert cache.stat().st_mtime_ns == built
    info = root / "meta" / "info.json"
    info.write_text(info.read_text())  # any change to the dataset's files invalidates the cache
    open_data(cfg, 32, progress=False)
    assert cache.stat().st_mtime_ns != built


def test_runs_started_together_build_each_stream_of_the_frame_cache_once(tmp_path, monkeypatch):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=12)
    cfg = tiny_cfg(root, tmp_path / "out")
    building = {"first": threading.Event(), "second": threading.Event()}
    go_on, builds = threading.Event(), []

    def slow_build(*args, **kwargs) -> None:
        builds.append(threading.current_thread().name)
        building[threading.current_thread().name].set()
        go_on.wait()
        build(*args, **kwargs)

    build = frame_cache._build
    monkeypatch.setattr(frame_cache, "_build", slow_build)
    runs = {
        name: threading.Thread(target=open_data, args=(cfg, 32), kwargs={"progress": False}, name=name)
        for name in building
    }
    runs["first"].start()
    building["first"].wait()
    runs["second"].start()
    # While the first run builds its stream, the second builds another instead of waiting.
    assert building["second"].wait(timeout=120)
    go_on.set()
    for run in runs.values():
        run.join()
    assert builds[:2] == ["first", "second"]  # side by side
    assert len(builds) == len(cfg.inputs.cameras)  # each stream once


def test_a_training_piece_stops_at_its_time_with_a_checkpoint_the_next_piece_resumes(dataset_root, tmp_path):
    common = ["train.steps=4", "train.save_every=100", "train.diagnose_every=2"]
    piece = train(tiny_cfg(dataset_root, tmp_path, [*common, "train.piece_minutes=1e-9"]))
    assert len(piece.losses) == 1 and piece.checkpoint.name == "step_00000001"  # saved where it stopped
    assert not (tmp_path / "last_run.json").exists()  # nothing that looks like a finished run
    rest = train(tiny_cfg(dataset_root, tmp_path, common))
    assert len(rest.losses) == 3 and rest.checkpoint.name == "step_00000004"
    diagnostics = [json.loads(line) for line in (tmp_path / "diagnostics.jsonl").read_text().splitlines()]
    assert [d["step"] for d in diagnostics] == [0, 1, 2, 4]  # the piece's last step, then every 2nd
    assert "train_loss" not in diagnostics[0]  # the untrained model's has no training behind it
    assert diagnostics[1]["train_loss"] == pytest.approx(piece.losses[0])
    assert diagnostics[-1]["train_loss"] == pytest.approx(np.mean(rest.losses[-2:]))


def test_diagnostics_of_a_killed_run_are_trimmed_to_where_the_rerun_starts(tmp_path):
    log = tmp_path / "diagnostics.jsonl"
    log.write_text("".join(json.dumps({"step": s, "noise_mse/image": 1.0}) + "\n" for s in (0, 1000, 2000)))
    trim_diagnostics(log, 1000)  # resumed from the step-1000 checkpoint: the step-2000 line goes
    assert [json.loads(line)["step"] for line in log.read_text().splitlines()] == [0, 1000]
    trim_diagnostics(log, 0)  # killed before its first checkpoint: the rerun measures step 0 again
    assert log.read_text() == ""


@pytest.mark.slow
def test_killed_training_resumes_from_its_last_checkpoint_without_repeats(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=20)
    out = tmp_path / "out"
    overrides = [
        *tiny_overrides(root, out),
        "train.steps=40",
        "train.save_every=2",
        "train.diagnose_every=2",
        "train.keep_checkpoints=100",
    ]
    command = [sys.executable, "-m", "mobilemani_vla.train", *overrides]
    project = Path(CONF).parent
    proc = subprocess.Popen(command, cwd=project, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 300
    saved = lambda: sorted((out / "checkpoints").glob("step_*"))  # noqa: E731
    while time.time() < deadline and proc.poll() is None and len(saved()) < 2:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 2 <= len(saved()) < 20, "the kill should land between the first checkpoints and the end"
    done = subprocess.run(command, cwd=project, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    steps = [int(p.name.split("_")[1]) for p in sorted((out / "checkpoints").iterdir())]
    assert steps == list(range(2, 41, 2))  # every checkpoint once, no temporary directory left
    diagnostics = [json.loads(line)["step"] for line in (out / "diagnostics.jsonl").read_text().splitlines()]
    assert diagnostics == sorted(set(diagnostics)) and diagnostics[-1] == 40  # nothing repeated by the resume
