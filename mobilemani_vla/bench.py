"""Training throughput and inference latency of MobileManiVLA at the project's model sizes.

    python -m mobilemani_vla.bench [--models tiny small] [--batch 8] [--steps 5] [--runs 5] [--cameras 4]

train: samples/s of one optimisation step (backbone + DiT forward/backward with r repeated diffusion steps,
AdamW), on synthetic batches so that video decoding is not measured. infer: seconds per action chunk for one
observation (backbone pass + 10 DDIM steps, guidance on). Best of the timed repeats, after one warm-up.
Also counts the parameters of every model config (paligemma2_3b on the meta device, no weights).
With `--dataset ROOT` (a MobileManiDataset), it also measures end-to-end training samples/s on that dataset
(loading + step) with the decoded-frame cache and without it (LeRobot decoding the videos per sample), in the
same run. Prints a table and JSON.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable

import torch

from mobilemani_rl.utils.cli import count, entry_point
from mobilemani_rl.utils.config_store import group_options
from mobilemani_rl.utils.video_logs import quiet_video_libraries
from mobilemani_vla.config import CAMERAS, VLACfg, compose_vla_cfg
from mobilemani_vla.data.dataset import fit_normalizer, open_data
from mobilemani_vla.model.network import MobileManiVLA, build_model
from mobilemani_vla.model.processor import VLAProcessor, states_width
from mobilemani_vla.model.tokenizer import build_word_tokenizer
from mobilemani_vla.train import adamw


def parameter_counts(model: MobileManiVLA) -> dict[str, int]:
    count = lambda m: sum(p.numel() for p in m.parameters())  # noqa: E731
    return {
        "backbone": count(model.backbone),
        "dit": count(model.head.dit),
        "state_encoder": 0 if model.state_encoder is None else count(model.state_encoder),
        "total": count(model),
    }


def synthetic_batch(model: MobileManiVLA, cfg: VLACfg, batch: int) -> dict[str, torch.Tensor]:
    size = model.backbone.image_size
    tokenizer = build_word_tokenizer()
    enc = tokenizer(
        [cfg.model.prompt.format(instruction="open washing machine")] * batch, return_tensors="pt"
    )
    return {
        "pixel_values": torch.rand(batch, len(cfg.inputs.cameras), 3, size, size),
        "input_ids": enc["input_ids"],
        "attention_mask": enc["attention_mask"],
        "state": torch.rand(batch, states_width(cfg.inputs.states)) * 2 - 1,
        "actions": torch.rand(batch, cfg.diffusion.chunk, cfg.action_dim) * 2 - 1,
    }


def best_seconds(fn: Callable[[], None], runs: int) -> float:
    fn()
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def bench(name: str, batch: int, steps: int, runs: int, cameras: int) -> dict:
    cfg = compose_vla_cfg([f"vla/model={name}", f"inputs.cameras=[{','.join(CAMERAS[:cameras])}]"])
    torch.manual_seed(0)
    model = build_model(cfg, build_word_tokenizer())
    data = synthetic_batch(model, cfg, batch)
    optimizer = adamw(model, cfg.train)

    def train_step() -> None:
        model.train()
        model(data).backward()
        optimizer.step()
        optimizer.zero_grad(set_to_none=True)

    one = {k: v[:1] for k, v in data.items() if k != "actions"}
    model.eval()
    infer = best_seconds(lambda: model.predict(one), runs)
    train = best_seconds(train_step, steps)
    return {
        "model": name,
        "image_size": model.backbone.image_size,
        "cameras": cameras,
        "image_tokens": cameras * model.backbone.tokens_per_image,
        "dit": cfg.model.dit,
        "params": parameter_counts(model),
        "train_batch": batch,
        "train_samples_per_s": batch / train,
        "infer_s_per_chunk": infer,
        "ddim_steps": cfg.diffusion.ddim_steps,
        "threads": torch.get_num_threads(),
    }


def bench_dataset(root: str, name: str, batch: int, steps: int) -> list[dict]:
    """Training samples/s on a real dataset, with and without the frame cache
    (same model, same batches size)."""
    out = []
    for cache in (False, True):
        cfg = compose_vla_cfg(
            [
                f"vla/model={name}",
                f"data.root={root}",
                f"data.cache={str(cache).lower()}",
                "data.heldout_episodes=0",
            ]
        )
        torch.manual_seed(0)
        # builds the cache if it is missing
        data = open_data(cfg, cfg.model.vision.image_size, progress=False)
        tokenizer = build_word_tokenizer(data.tasks)
        model = build_model(cfg, tokenizer)
        normalizer = fit_normalizer(data.table, data.table.rows(data.train_episodes), cfg.inputs.states)
        processor = VLAProcessor.for_config(cfg, tokenizer, normalizer, model.backbone.image_size)
        loader = iter(
            torch.utils.data.DataLoader(data.train, batch_size=batch, shuffle=True, collate_fn=processor)
        )
        optimizer = adamw(model, cfg.train)
        next(loader)
        start = time.perf_counter()
        for _ in range(steps):
            model(next(loader)).backward()
            optimizer.step()
            optimizer.zero_grad(set_to_none=True)
        train = steps * batch / (time.perf_counter() - start)
        start = time.perf_counter()
        for _ in range(steps):
            next(loader)
        load = steps * batch / (time.perf_counter() - start)
        out.append(
            {
                "model": name,
                "cache": cache,
                "batch": batch,
                "steps": steps,
                "train_samples_per_s": train,
                "load_only_samples_per_s": load,
            }
        )
    return out


def meta_counts() -> dict:
    cfg = compose_vla_cfg(
        ["vla/model=paligemma2_3b", "model.pretrained_path=null", "model.tokenizer_path=null"]
    )
    with torch.device("meta"):
        model = build_model(cfg, build_word_tokenizer())
    return {"model": "paligemma2_3b", "device": "meta", "params": parameter_counts(model)}


@entry_point
def main() -> None:
    quiet_video_libraries()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=["tiny", "small"], choices=group_options("vla/model"))
    parser.add_argument("--batch", type=count, default=8)
    parser.add_argument("--steps", type=count, default=3, help="timed training steps per model")
    parser.add_argument("--runs", type=count, default=3, help="timed inference calls per model")
    parser.add_argument("--cameras", type=int, default=4, choices=range(1, 5))
    parser.add_argument(
        "--dataset", help="a MobileManiDataset root: also time training on it, cache on and off"
    )
    parser.add_argument(
        "--dataset-model",
        default="cpu",
        choices=group_options("vla/model"),
        help="model config for --dataset",
    )
    args = parser.parse_args()
    results = [bench(m, args.batch, args.steps, args.runs, args.cameras) for m in args.models]
    on_data = bench_dataset(args.dataset, args.dataset_model, args.batch, args.steps) if args.dataset else []
    big = meta_counts()
    print(
        f"{'model':<14}{'img tok':>8}{'dit':>4}{'params (M)':>12}{'train samples/s':>17}{'infer s/chunk':>15}"
    )
    for r in results:
        print(
            f"{r['model']:<14}{r['image_tokens']:>8}{r['dit']:>4}{r['params']['total'] / 1e6:>12.2f}"
            f"{r['train_samples_per_s']:>17.2f}{r['infer_s_per_chunk']:>15.3f}"
        )
    print(f"{big['model']:<14}{'':>8}{'B':>4}{big['params']['total'] / 1e6:>12.1f}{'(meta, not run)':>32}")
    for r in on_data:
        print(
            f"{args.dataset} ({r['model']}, frame cache {'on' if r['cache'] else 'off'}): "
            f"{r['train_samples_per_s']:.1f} training samples/s, "
            f"{r['load_only_samples_per_s']:.1f} loaded samples/s"
        )
    print(json.dumps({"cpu": results, "meta": big, "dataset": on_data}, indent=1))


if __name__ == "__main__":
    main()
