"""Decomposers: nodes that turn agents' actions into robot commands (thesis 5.3, 6.3)."""
