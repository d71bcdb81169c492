"""Nodes and helpers for testing agents and decomposers."""
