"""The scripted reference policy on a fixed sample of train objects (3 per category), both robots.

A (robot, category, skill) passes when every sampled object succeeds in >= 60 % of 4 seeded episodes.
One row is a known failure, marked xfail so that the report shows it (XFAIL, or XPASS on a lucky draw): the
XHand picks holistic/0018 in 0.5-0.625 of 8 episodes over three seeds, the row's 2/3 objects in
docs/results/fidelity.md (its low stage, where the five-finger grasp lets round objects slip).
"""

from __future__ import annotations

import pytest

from mobilemani_rl.assets.objects import CATEGORIES, get_object
from mobilemani_rl.scripted.table import PASS_RATE, episode_success, sample_objects

KNOWN_FAILURES = {("xhand", "holistic", "pick"): "holistic/0018 below 0.6 (docs/results/fidelity.md)"}
CASES = [
    pytest.param(
        robot,
        category,
        skill,
        id=f"{robot}-{category}-{skill}",
        marks=[pytest.mark.xfail(reason=KNOWN_FAILURES[robot, category, skill])]
        if (robot, category, skill) in KNOWN_FAILURES
        else [],
    )
    for robot in ("g1", "xhand")
    for category in CATEGORIES
    for skill in get_object(sample_objects(category, 1)[0]).skills
]


@pytest.mark.slow
@pytest.mark.parametrize(("robot", "category", "skill"), CASES)
def test_scripted_policy_succeeds_on_sampled_objects(robot, category, skill):
    rates = {
        oid: episode_success(robot, oid, skill, episodes=4, seed=0) for oid in sample_objects(category, 3)
    }
    assert all(rate >= PASS_RATE for rate in rates.values()), rates
