"""Contact classes as (contype, conaffinity) bit pairs.

The robot never collides with itself (as the reference G1; cheaper, and the hand cannot self-intersect in the
tasks), robot geoms touch world geoms, and world geoms
(objects, stage, ground) touch the robot and each other.
"""

ROBOT_BIT = 1
WORLD_BIT = 2

ROBOT_CONTACT = (ROBOT_BIT, WORLD_BIT)
WORLD_CONTACT = (WORLD_BIT, ROBOT_BIT | WORLD_BIT)
