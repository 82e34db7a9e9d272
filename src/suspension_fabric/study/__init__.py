"""Studies: the study configuration (schema validation and cross-key checks), campaigns over
state points, and reference datasets (a finished study's tables, loaded or rebuilt without
simulating).

Imports the stages below it (io, analysis, simulation, models): validating a config checks its
time step against the simulation's time scales and its model names against the models.
"""
