"""PPO teachers' labels smoothed at export, and the held-out diagnostics' instruction variants."""

from __future__ import annotations

import numpy as np
import pytest

from mobilemani_data.config import ExportCfg
from mobilemani_data.convert import smoothed_labels
from mobilemani_data.export import label_window
from mobilemani_rl.utils.stats import wilson_interval
from mobilemani_vla.diagnostics import wrong_instructions
from mobilemani_vla.eval.results import summarize


def test_window_one_keeps_the_labels():
    actions = np.random.default_rng(0).uniform(-1, 1, (20, 7))
    assert smoothed_labels(actions, 1) is actions


def test_smoothing_removes_jitter_and_keeps_the_motion():
    t = np.arange(200)
    motion = np.stack([np.sin(t / 40.0), np.full(200, 0.5)], axis=1)  # slow course and a constant
    jitter = np.where(t % 2 == 0, 0.3, -0.3)[:, None]  # the sign flips every control step
    smoothed = smoothed_labels(motion + jitter, 9)
    assert smoothed.shape == (200, 2)
    roughness = np.abs(np.diff(smoothed, axis=0)).mean()
    assert roughness < np.abs(np.diff(motion + jitter, axis=0)).mean() / 8  # a 9-step window: ~1/9
    # the jitter averages out to 1/9 of its size; the slow course stays within 0.04 of itself
    assert np.abs(smoothed - motion)[4:-4].max() < 0.3 / 9 + 0.01
    # the wrist deltas add up to (almost) the same displacement over the episode
    assert abs(smoothed[:, 0].sum() - (motion + jitter)[:, 0].sum()) < 0.2
    np.testing.assert_allclose(smoothed_labels(np.full((5, 3), 0.7), 9), 0.7)  # ends padded with edge values


def test_only_ppo_labels_are_smoothed():
    cfg = ExportCfg(ppo_label_window=9)
    assert label_window(cfg, "outputs/rl/g1/test/box/open/model_99.pt") == 9
    assert label_window(cfg, "scripted") == 1


def test_a_wrong_instruction_is_another_task_or_another_skill():
    assert wrong_instructions(["open box", "pick object", "open box"]) == [
        "pick object",
        "open box",
        "pick object",
    ]
    assert wrong_instructions(["open box"] * 3) == ["close box"] * 3
    assert wrong_instructions(["pick object"]) == ["open object"]


@pytest.mark.parametrize(
    ("wins", "episodes", "low", "high"),
    [(0, 20, 0.0, 0.1611), (12, 20, 0.3866, 0.7812), (60, 60, 0.9398, 1.0), (33, 60, 0.4249, 0.6691)],
)
def test_wilson_interval(wins, episodes, low, high):
    assert wilson_interval(wins, episodes) == pytest.approx((low, high), abs=1e-4)


def test_summaries_carry_the_interval():
    records = [
        {"object_id": "test/box", "success": k < 3, "skill": "open", "category": "box"} for k in range(10)
    ]
    overall = summarize(records)["overall"]
    assert overall["successes"] == 3
    assert overall["ci95"] == pytest.approx(list(wilson_interval(3, 10)))
