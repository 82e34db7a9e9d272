"""Snakemake: compile the LAMMPS plugin (rule build_plugin) and publish it at the rule's output.

Snakemake deletes the output before the job, so the library is rebuilt when the output is
the repository's own library; a workflow run elsewhere (e.g. the tests) gets a copy and
leaves the repository's library as it is if it is up to date.
"""

from suspension_fabric.simulation.lammps.plugin import install_plugin
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    built = install_plugin(sm.output[0])
    print(f"built {built} -> {sm.output[0]}")
