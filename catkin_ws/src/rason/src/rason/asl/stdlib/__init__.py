"""The standard library of internal actions (Jason's ``jason.stdlib``), one function each,
registered by name with :func:`rason.asl.ia.internal_action` (which says how to write one).

Importing one of :data:`MODULES` registers its actions; :mod:`rason.asl.ia` imports ``core``
on the first look-up of an action and the others on the first look-up ``core`` cannot answer,
so the interpreter's modules never import them and an agent that only prints needs ``core``
alone. Importing this package itself registers nothing.
"""

#: the modules of the library, each registering its actions when imported
MODULES = ("core", "comm", "containers", "control", "extra", "goals", "lists", "strings")
