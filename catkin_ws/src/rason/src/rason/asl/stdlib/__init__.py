"""The standard library of internal actions (Jason's ``jason.stdlib``), one function each,
registered by name with :func:`rason.asl.ia.internal_action` (which says how to write one).

Importing this package registers them all; :mod:`rason.asl.ia` does it on the first look-up
of an action, so the interpreter's modules never import it.
"""

from . import comm, containers, control, core, extra, goals, lists, strings  # noqa: F401  (registration)
