"""The scripted reference policy on a fixed sample of train objects (3 per category), both robots.

A (robot, category, skill) passes when every sampled object succeeds in >= 60 % of 4 seeded episodes. The
combinations listed in KNOWN_GAPS do not reach the bar with the current scripted policy (see the reasons);
they are expected failures, not skipped, so that a fix shows up as an unexpected pass.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from mobilemani_rl.assets.objects import CATEGORIES, get_object

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from scripted_success_table import PASS_RATE, episode_success, sample_objects  # noqa: E402

XHAND_OPEN = ("its straight fingers reach ~12 cm past the palm point along the approach and hit the surface "
              "behind the handle before the palm reaches it")
LID_CLOSE = "fingers opening vertically cannot straddle the edge of a lid tilted more than ~55 degrees"
PICK = "the scripted approach stalls near the pre-grasp point in part of the episodes"
FAUCET = "a lifted lever tilts like a lid (see LID_CLOSE); short levers leave little room for the pads"
ONE_OBJECT = "one of the three sampled objects falls below the bar (2 of 4 episodes or fewer)"
PUSH_ONLY = "closes only by pushing the open part, which misses in part of the episodes"
KNOWN_GAPS = {
    ("g1", "box", "close"): LID_CLOSE, ("g1", "laptop", "close"): LID_CLOSE, ("g1", "faucet", "open"): FAUCET,
    ("g1", "faucet", "close"): FAUCET, ("g1", "holistic", "pick"): PICK, ("xhand", "holistic", "pick"): PICK,
    **{("g1", c, "open"): ONE_OBJECT for c in ("oven", "microwave", "washing_machine", "safe", "fridge")},
    **{("xhand", c, "open"): XHAND_OPEN for c in ("dishwasher", "oven", "microwave", "refrigerator",
                                                 "washing_machine", "car", "safe", "fridge", "cabinet", "window",
                                                 "lever_door", "round_door", "faucet", "table", "trashcan")},
    **{("xhand", c, "close"): PUSH_ONLY for c in ("toilet", "oven", "microwave", "safe", "window", "round_door")},
    ("xhand", "cart", "pull"): ONE_OBJECT, ("xhand", "cart", "push"): ONE_OBJECT,
}
CASES = [(robot, category, skill) for robot in ("g1", "xhand") for category in CATEGORIES
         for skill in get_object(sample_objects(category, 1)[0]).skills]


def _param(case):
    reason = KNOWN_GAPS.get(case)
    marks = [pytest.mark.xfail(reason=reason, strict=False)] if reason else []
    return pytest.param(*case, marks=marks, id="-".join(case))


@pytest.mark.slow
@pytest.mark.parametrize(("robot", "category", "skill"), [_param(c) for c in CASES])
def test_scripted_policy_succeeds_on_sampled_objects(robot, category, skill):
    rates = {oid: episode_success(robot, oid, skill, episodes=4, seed=0) for oid in sample_objects(category, 3)}
    assert all(rate >= PASS_RATE for rate in rates.values()), rates
