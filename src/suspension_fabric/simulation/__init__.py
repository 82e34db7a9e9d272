"""Simulation: the force model's time scales and output strides, the engine's rule for its own settings
(engine_rule), and the LAMMPS engine (the
project's plugin, launching and watching ``lmp``, resumable run directories, the public runs).

Imports [`suspension_fabric.io`][suspension_fabric.io] and [`suspension_fabric.analysis`][suspension_fabric.analysis]: a
finished run is checked for overlaps with the same near-contact search the fabric uses.
"""
