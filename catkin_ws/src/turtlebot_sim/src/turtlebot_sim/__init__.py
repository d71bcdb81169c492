"""turtlebot_sim."""
