"""Driving each object's joint (or its free body) to the skill's goal reaches it without self/stage
contact."""

from __future__ import annotations

import pytest

from mobilemani_rl.assets.objects import CATALOG, CATEGORIES, catalog_ids
from mobilemani_rl.assets.objects.checks import sweep

SAMPLE = [catalog_ids(c)[i] for c in CATEGORIES for i in (0, -1)]


def _check(oid: str) -> None:
    obj = CATALOG[oid]
    for skill in obj.skills:
        result = sweep(obj, skill)
        assert result.goal_error < 0.05, (oid, skill, result.goal_error)
        assert not result.collisions, (oid, skill, result.collisions[:3])


@pytest.mark.parametrize("oid", SAMPLE)
def test_sweep_reaches_goal_without_collision_sample(oid):
    _check(oid)


@pytest.mark.slow
def test_sweep_reaches_goal_without_collision_all():
    for oid in CATALOG:
        _check(oid)


def test_grasp_points_are_within_reach():
    """Grasp points (and open goals) between ~0.2 and ~1.25 m above the ground over the stage heights."""
    for oid, obj in CATALOG.items():
        kin, params = obj.kinematics, obj.params
        low_stage = params.init_height
        high_stage = low_stage + (0.5 if params.random_height else 0.0)
        z = [kin.handle_closed[2] - kin.bottom_z, kin.handle_opened[2] - kin.bottom_z]
        assert min(z) + low_stage >= 0.2, oid
        assert max(z) + high_stage <= 1.25, oid
