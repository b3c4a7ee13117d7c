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

KNOWN_GAPS: dict[tuple[str, str, str], str] = {}
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
