"""Free objects on their stage: holistic objects rest still, carts roll when pushed and stay put otherwise."""

from __future__ import annotations

import numpy as np
import pytest

from mobilemani_rl.assets.objects import CATALOG, catalog_ids
from mobilemani_rl.assets.objects.checks import push_travel, rest_drift


def test_every_holistic_object_rests_still():
    for oid in catalog_ids("holistic"):
        assert rest_drift(CATALOG[oid], seconds=2.0) < 0.01, oid


@pytest.mark.parametrize("oid", catalog_ids("cart"))
def test_cart_stays_put_and_rolls_both_ways(oid):
    cart = CATALOG[oid]
    assert rest_drift(cart, seconds=2.0) < 0.01
    for direction in (-1.0, 1.0):  # pull toward the robot (-y), push away
        travel = push_travel(cart, np.array([0.0, 0.5 * direction, 0.0]), push_seconds=0.5, coast_seconds=0.5)
        assert travel > 0.2, (direction, travel)
