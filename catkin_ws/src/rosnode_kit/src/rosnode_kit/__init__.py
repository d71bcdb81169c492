"""rosnode_kit: generic rospy node helpers (parameters, guards, watches), no agent code."""
