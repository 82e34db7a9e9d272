"""Snakemake: a run's fabric or stress table from the reference dataset (rule import_run_table)."""
from pathlib import Path

from suspension_fabric.dataset import import_run_table
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    print(import_run_table(Path(sm.input.record).parent, sm.params.run, f"{sm.wildcards.table}.csv", sm.output[0]))
