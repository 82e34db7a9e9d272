"""Snakemake: a run's fabric table from the reference dataset (rule import_fabric_table)."""
from pathlib import Path

from suspension_fabric.dataset import import_fabric_table
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    print(import_fabric_table(Path(sm.input.record).parent, sm.params.run, sm.output[0]))
