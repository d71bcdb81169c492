"""Offline tooling for rason_vision: synthetic scenes, rendered scenarios, recorded bags."""
