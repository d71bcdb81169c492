"""rason_vision."""
