"""GPU-path checks driven by run.sh beside this file (docs/results/gpu_paths.md):

- `gpu_paths.py data DIR`: a synthetic g1 dataset (6 episodes x 40 frames)
- `gpu_paths.py probe DIR DEVICE OUT`: 3 bf16 training steps in-process with dtype hooks, then a bfloat16
  backbone feeding the float32 head on DEVICE
- `gpu_paths.py policy DEVICE OUT CKPT...`: VLAEvalPolicy on DEVICE: generator device, chunks, timing
"""

import json
import sys
import time
from pathlib import Path

import numpy as np
import torch


def _sync(device: str) -> None:
    if device.startswith("cuda"):
        torch.cuda.synchronize()


def _merge(out: Path, key: str, value) -> None:
    data = json.loads(out.read_text()) if out.is_file() else {}
    data[key] = value
    out.write_text(json.dumps(data, indent=1, default=str))


def env_info() -> dict:
    import accelerate
    import transformers

    info = {
        "torch": torch.__version__,
        "transformers": transformers.__version__,
        "accelerate": accelerate.__version__,
        "numpy": np.__version__,
        "cuda_available": torch.cuda.is_available(),
    }
    if torch.cuda.is_available():
        info["gpu"] = torch.cuda.get_device_name(0)
        info["bf16_supported"] = torch.cuda.is_bf16_supported()
    return info


def data(root: str) -> None:
    from mobilemani_vla.synthetic import write_synthetic_dataset

    t = time.perf_counter()
    write_synthetic_dataset(Path(root), episodes=6, length=40)
    print(f"synthetic dataset {root}: {time.perf_counter() - t:.1f} s", flush=True)


def probe(root: str, device: str, out: str) -> None:
    """Which dtypes the modules produce inside accelerate's bf16 training step, and a bfloat16 backbone
    feeding the float32 head on DEVICE."""
    from transformers import PaliGemmaForConditionalGeneration

    from mobilemani_vla.backbone import paligemma_config
    from mobilemani_vla.config import ModelCfg, compose_vla_cfg
    from mobilemani_vla.model import build_model
    from mobilemani_vla.tokenizer import build_word_tokenizer, load_tokenizer
    from mobilemani_vla.train import train

    out = Path(out)
    _merge(out, "env", env_info())
    seen: dict[str, set] = {}
    grad_mode: dict[str, bool] = {}

    def hook(module, args, output):
        if not torch.is_grad_enabled():
            return
        name = type(module).__name__
        if isinstance(output, torch.Tensor):
            seen.setdefault(name, set()).add(str(output.dtype).replace("torch.", ""))
            grad_mode["autocast"] = grad_mode.get("autocast", False) or torch.is_autocast_enabled(
                output.device.type
            )

    handle = torch.nn.modules.module.register_module_forward_hook(hook)
    cfg = compose_vla_cfg(
        [
            "vla/model=tiny",
            f"data.root={root}",
            "data.repo_id=synthetic/g1",
            "data.heldout_episodes=1",
            f"train.output_dir={Path(root).parent / 'probe_run'}",
            "train.logger=none",
            "train.progress=false",
            "train.batch_size=32",
            "train.steps=3",
            "train.mixed_precision=bf16",
            "train.diagnose_every=0",
        ]
    )
    result = train(cfg)
    handle.remove()
    p = next(result.model.parameters())
    _merge(
        out,
        "probe_train_bf16",
        {
            "losses": result.losses,
            "param_device": str(p.device),
            "param_dtype": str(p.dtype),
            "autocast_seen_in_forward": grad_mode.get("autocast"),
            "cuda_max_memory_allocated_MiB": (
                round(torch.cuda.max_memory_allocated() / 2**20, 1) if torch.cuda.is_available() else None
            ),
            "output_dtypes_by_module": {
                k: sorted(v)
                for k, v in sorted(seen.items())
                if k in ("Linear", "Conv2d", "Embedding", "DiT", "MobileManiVLA", "CognitionBackbone")
                or "Gemma" in k
                or "Siglip" in k
            },
        },
    )

    # A bfloat16 pretrained backbone (saved tiny PaliGemma) feeding the float32 head, on DEVICE.
    tmp = Path(root).parent / "pretrained_tiny"
    torch.manual_seed(0)
    PaliGemmaForConditionalGeneration(paligemma_config(ModelCfg())).save_pretrained(tmp)
    build_word_tokenizer().save_pretrained(tmp)
    cfg = compose_vla_cfg(
        [f"model.pretrained_path={tmp}", f"model.tokenizer_path={tmp}", "model.dtype=bfloat16"]
    )
    model = build_model(cfg, load_tokenizer(tmp)).to(device)
    size = model.backbone.image_size
    enc = build_word_tokenizer()(["open box"] * 2, return_tensors="pt")
    batch = {
        "pixel_values": torch.rand(2, 4, 3, size, size),
        "input_ids": enc["input_ids"],
        "attention_mask": enc["attention_mask"],
        "state": torch.zeros(2, 9),
        "actions": torch.rand(2, 16, 7),
    }
    batch = {k: v.to(device) for k, v in batch.items()}
    loss = model(batch)
    loss.backward()
    grads_finite = all(torch.isfinite(q.grad).all().item() for q in model.parameters() if q.grad is not None)
    model.eval()
    gen = torch.Generator(device).manual_seed(0)
    chunk = model.predict(batch, gen)
    _merge(
        out,
        "bf16_backbone",
        {
            "device": str(next(model.parameters()).device),
            "backbone_dtypes": sorted({str(q.dtype) for q in model.backbone.vlm.parameters()}),
            "head_dtypes": sorted({str(q.dtype) for q in model.head.parameters()}),
            "loss": loss.item(),
            "loss_dtype": str(loss.dtype),
            "grads_finite": grads_finite,
            "chunk_shape": list(chunk.shape),
            "chunk_dtype": str(chunk.dtype),
            "chunk_finite": bool(torch.isfinite(chunk).all()),
        },
    )
    print(json.dumps(json.loads(out.read_text()), indent=1), flush=True)


def policy(device: str, out: str, *checkpoints: str) -> None:
    from mobilemani_vla.policies.vla import VLAEvalPolicy

    out = Path(out)
    results = {}
    for ckpt in checkpoints:
        ckpt = Path(ckpt)
        files = sorted(p.name for p in ckpt.iterdir())
        pol = VLAEvalPolicy(ckpt, device=device)
        pol.start(env=None, seed=3)
        model_device = next(pol.policy.model.parameters()).device
        size = pol.policy.model.backbone.image_size
        b = 8
        rng = np.random.default_rng(0)
        images = {c: rng.integers(0, 255, (b, size, size, 3), dtype=np.uint8) for c in pol.policy.cameras}
        vectors = {k: rng.standard_normal((b, 10)).astype(np.float32) for k in pol.policy.vector_inputs}
        tasks = ["open box"] * b
        first = pol.policy.predict_action_chunks(images, tasks, vectors, pol.generator)
        pol.start(env=None, seed=3)
        again = pol.policy.predict_action_chunks(images, tasks, vectors, pol.generator)
        _sync(device)
        reps = 20
        t = time.perf_counter()
        for _ in range(reps):
            pol.policy.predict_action_chunks(images, tasks, vectors, pol.generator)
        _sync(device)
        ms = (time.perf_counter() - t) / reps * 1e3
        results[ckpt.name if ckpt.parent.name == "checkpoints" else str(ckpt)] = {
            "path": str(ckpt),
            "files": files,
            "model_device": str(model_device),
            "generator_device": str(pol.generator.device),
            "generator_on_model_device": pol.generator.device == model_device,
            "chunk_shape": list(first.shape),
            "chunk_finite": bool(np.isfinite(first).all()),
            "same_seed_same_chunks": bool(np.array_equal(first, again)),
            "ms_per_batch_of_8_chunks": round(ms, 2),
            "first_chunk_row0": first[0, 0].round(4).tolist(),
        }
    _merge(out, f"policy_{device}", results)
    print(json.dumps(results, indent=1), flush=True)


if __name__ == "__main__":
    {"data": data, "probe": probe, "policy": policy}[sys.argv[1]](*sys.argv[2:])
