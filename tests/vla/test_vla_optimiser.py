"""The VLA's weight average and optimiser: the fused forms compute what the per-tensor forms do."""

import pytest
import torch
from torch.optim.swa_utils import AveragedModel

from mobilemani_vla.config import TrainCfg
from mobilemani_vla.train import adamw, ema_update, lr_schedule


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


class _Model(torch.nn.Module):
    def __init__(self) -> None:
        super().__init__()
        self.backbone = torch.nn.Linear(3, 3)
        self.head = torch.nn.Linear(3, 2)


def test_held_backbone_keeps_its_weights_then_warms_up_while_the_head_trains():
    torch.manual_seed(0)
    model = _Model()
    cfg = TrainCfg(steps=100, warmup_steps=10, backbone_hold_steps=30)
    optimiser = adamw(model, cfg)
    schedule = lr_schedule(optimiser, cfg)
    start = [p.detach().clone() for p in model.backbone.parameters()]
    head_start = model.head.weight.detach().clone()
    rates = []
    for _ in range(60):
        rates.append([group["lr"] for group in optimiser.param_groups])
        model.head(model.backbone(torch.randn(4, 3))).square().mean().backward()
        optimiser.step()
        schedule.step()
        optimiser.zero_grad()
        if len(rates) == 30:  # the hold's last step taken: the backbone is where it started
            assert all(torch.equal(p, s) for p, s in zip(model.backbone.parameters(), start, strict=True))
            assert not torch.equal(model.head.weight, head_start)
    backbone_rates, head_rates = zip(*rates, strict=True)
    assert all(rate == 0 for rate in backbone_rates[:31])
    # released at step 30, warmed up linearly over the 10 warm-up steps, then the head's rate
    assert backbone_rates[35] == pytest.approx(0.5 * head_rates[35])
    assert backbone_rates[40:] == pytest.approx(head_rates[40:])
    assert head_rates[10] == pytest.approx(cfg.lr)
    assert not any(torch.equal(p, s) for p, s in zip(model.backbone.parameters(), start, strict=True))


def test_without_a_hold_one_group_follows_the_schedule():
    model = _Model()
    cfg = TrainCfg(steps=50, warmup_steps=5)
    optimiser = adamw(model, cfg)
    schedule = lr_schedule(optimiser, cfg)
    (group,) = optimiser.param_groups
    assert len(group["params"]) == len(list(model.parameters()))
    rates = []
    for _ in range(20):
        rates.append(group["lr"])
        optimiser.step()
        schedule.step()
    assert rates[0] == 0 and rates[5] == pytest.approx(cfg.lr) and rates[19] < rates[5]
