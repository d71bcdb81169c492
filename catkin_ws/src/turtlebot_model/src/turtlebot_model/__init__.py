"""The TurtleBot 2 / Kobuki facts every layer shares (one home each).

* :mod:`turtlebot_model.kobuki`: the base's dimensions and limits.
* :mod:`turtlebot_model.geometry`: yaw from a quaternion, angle wrapping, wrap-safe differences.
* :mod:`turtlebot_model.cloud`: PCL's packed XYZRGB point layout.
"""
