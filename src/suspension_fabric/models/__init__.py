"""Models: the Gillissen-Wilson fabric model and its modification, the fabric-model and
stress-relation interfaces with their plug-ins, fits to the simulation, predictions, the G-W
stress relation, and the held-out benchmarks of both.

Imports only :mod:`suspension_fabric.io` and :mod:`suspension_fabric.analysis`.
"""
