"""Files: where the project's data files live, the study schema and its defaults, and the formats
of what a run writes (LAMMPS dumps, the stress table, the run record).

The lowest stage: it imports nothing else of the package.
"""
