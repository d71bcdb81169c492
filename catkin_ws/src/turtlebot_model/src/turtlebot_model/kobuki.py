"""Kobuki base dimensions (Yujin's data sheet / kobuki_description), in metres."""

#: Radius of each drive wheel.
WHEEL_RADIUS = 0.035
#: Distance between the two drive wheels' contact points.
WHEEL_SEPARATION = 0.230
#: Width of a drive wheel.
WHEEL_WIDTH = 0.021
#: Radius of the round body.
BODY_RADIUS = 0.177
#: Height of the body's bottom and top above the floor.
BODY_BOTTOM, BODY_TOP = 0.02, 0.11
#: Radius of the caster wheels.
CASTER_RADIUS = 0.0175
