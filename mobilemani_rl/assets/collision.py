"""Contact classes as (contype, conaffinity) bit pairs.

Robot geoms touch world geoms, world geoms (objects, stage, ground) touch the robot and each other. The robot
does not collide with itself, as the reference G1 (cheaper, and the arm cannot reach itself in the tasks),
except the XHand's palm and fingers, which collide with each other as in the reference XHand (MuJoCo still
skips parent-child pairs, e.g. the two phalanges of a finger).
"""

ROBOT_BIT = 1
WORLD_BIT = 2
HAND_BIT = 4

ROBOT_CONTACT = (ROBOT_BIT, WORLD_BIT)
HAND_CONTACT = (ROBOT_BIT | HAND_BIT, WORLD_BIT | HAND_BIT)
WORLD_CONTACT = (WORLD_BIT, ROBOT_BIT | WORLD_BIT)
