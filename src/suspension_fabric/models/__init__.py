"""Models: the Gillissen-Wilson fabric model and its modification, the fabric-model and
stress-relation interfaces with their plug-ins, fits to the simulation, predictions, the G-W
stress relation, the held-out benchmarks of both, and every model on every protocol.

Imports only :mod:`suspension_fabric.io` and :mod:`suspension_fabric.analysis`.
"""
