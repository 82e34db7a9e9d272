"""Simulation: the force model's time scales and output strides, and the LAMMPS engine (the
project's plugin, launching and watching ``lmp``, resumable run directories, the public runs).

Imports :mod:`suspension_fabric.io` and :mod:`suspension_fabric.analysis`: a finished run is
checked for overlaps with the same near-contact search the fabric uses.
"""
