"""One generator per category: (numpy Generator) -> Design. Sampling is cheap;
`Design.build` makes the spec."""

from collections.abc import Callable

import numpy as np

from mobilemani_rl.assets.objects.generators.appliances import (
    dishwasher,
    fridge,
    microwave,
    oven,
    refrigerator,
    safe,
    washing_machine,
)
from mobilemani_rl.assets.objects.generators.cart import cart
from mobilemani_rl.assets.objects.generators.common import Design
from mobilemani_rl.assets.objects.generators.doors import car, lever_door, round_door, window
from mobilemani_rl.assets.objects.generators.faucet import faucet
from mobilemani_rl.assets.objects.generators.furniture import cabinet, table
from mobilemani_rl.assets.objects.generators.holistic import holistic
from mobilemani_rl.assets.objects.generators.lidded import box, laptop, toilet, trashcan

Generator = Callable[[np.random.Generator], Design]

GENERATORS: dict[str, Generator] = {
    "box": box,
    "toilet": toilet,
    "laptop": laptop,
    "trashcan": trashcan,
    "dishwasher": dishwasher,
    "oven": oven,
    "microwave": microwave,
    "refrigerator": refrigerator,
    "washing_machine": washing_machine,
    "car": car,
    "safe": safe,
    "fridge": fridge,
    "cabinet": cabinet,
    "window": window,
    "lever_door": lever_door,
    "round_door": round_door,
    "faucet": faucet,
    "table": table,
    "cart": cart,
    "holistic": holistic,
}

__all__ = ["GENERATORS", "Design", "Generator"]
