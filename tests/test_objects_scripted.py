"""The scripted reference policy on a fixed sample of train objects (3 per category), both robots.

A (robot, category, skill) passes when every sampled object succeeds in >= 60 % of 4 seeded episodes.
"""

from __future__ import annotations

import pytest

from mobilemani_rl.assets.objects import CATEGORIES, get_object
from mobilemani_rl.scripted_table import PASS_RATE, episode_success, sample_objects

CASES = [
    (robot, category, skill)
    for robot in ("g1", "xhand")
    for category in CATEGORIES
    for skill in get_object(sample_objects(category, 1)[0]).skills
]


@pytest.mark.slow
@pytest.mark.parametrize(("robot", "category", "skill"), CASES, ids=["-".join(c) for c in CASES])
def test_scripted_policy_succeeds_on_sampled_objects(robot, category, skill):
    rates = {
        oid: episode_success(robot, oid, skill, episodes=4, seed=0) for oid in sample_objects(category, 3)
    }
    assert all(rate >= PASS_RATE for rate in rates.values()), rates
