"""The case study: two TurtleBots diagnose a hardware fault together (Morais 2015).

``python -m rason_diagnosis`` (``./run.sh demo``) runs one diagnosis end to end in simulation;
:mod:`rason_diagnosis.campaign` runs many; :mod:`rason_diagnosis.paths` finds the agents and
worlds through the ROS package path.
"""
