"""The cooperative fault diagnosis demo (``./run.sh demo``)."""
