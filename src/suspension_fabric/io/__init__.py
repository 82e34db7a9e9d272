"""Files: where the project's data files live, the study schema and its defaults, flow histories
(protocols and the tree of their runs), and the formats of what a run writes (LAMMPS dumps, the
stress table, the run record).

The lowest stage: it imports nothing else of the package.
"""
