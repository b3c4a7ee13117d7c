"""The VLA's weight average and optimiser: the fused forms compute what the per-tensor forms do."""

import torch
from torch.optim.swa_utils import AveragedModel

from mobilemani_vla.config import TrainCfg
from mobilemani_vla.train import adamw, ema_update


def test_ema_follows_the_warmed_up_decay_over_every_weight():
    torch.manual_seed(0)
    model = torch.nn.Sequential(torch.nn.Linear(3, 4), torch.nn.Linear(4, 2))
    average = AveragedModel(model, multi_avg_fn=ema_update(0.9))
    expected = [p.detach().clone() for p in model.parameters()]
    average.update_parameters(model)  # the first update copies the weights
    for n in range(1, 40):
        with torch.no_grad():
            for p in model.parameters():
                p.add_(torch.randn_like(p))
        average.update_parameters(model)
        decay = min(0.9, (1 + n) / (10 + n))
        expected = [decay * e + (1 - decay) * p for e, p in zip(expected, model.parameters(), strict=True)]
    for kept, e in zip(average.module.parameters(), expected, strict=True):
        assert torch.allclose(kept, e, atol=1e-6)


def test_fused_adamw_takes_the_steps_of_the_per_tensor_loop():
    torch.manual_seed(0)
    fused_model = torch.nn.Linear(5, 3)
    loop_model = torch.nn.Linear(5, 3)
    loop_model.load_state_dict(fused_model.state_dict())
    cfg = TrainCfg()
    fused = adamw(fused_model, cfg)
    loop = torch.optim.AdamW(loop_model.parameters(), lr=cfg.lr, weight_decay=cfg.weight_decay, foreach=False)
    for _ in range(20):
        x = torch.randn(8, 5)
        for model, optimiser in ((fused_model, fused), (loop_model, loop)):
            model(x).square().mean().backward()
            optimiser.step()
            optimiser.zero_grad()
    for a, b in zip(fused_model.parameters(), loop_model.parameters(), strict=True):
        assert torch.allclose(a, b, atol=1e-6)
