"""rason."""
