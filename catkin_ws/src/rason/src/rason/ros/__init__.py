"""rason.ros: the bridge layer, Jason agents hosted as ROS nodes (thesis ch. 5)."""
