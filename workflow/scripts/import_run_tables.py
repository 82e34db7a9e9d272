"""Snakemake: every run's fabric (and stress) table of a study from its reference dataset
(rule import_run_tables), each file's SHA-256 checked."""

from pathlib import Path

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.study.dataset import import_run_table, read_dataset
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    folder = Path(sm.input[0]).parent
    record = read_dataset(folder)
    for (run, table), target in zip(sm.params.runs, sm.output):
        Path(target).parent.mkdir(parents=True, exist_ok=True)
        import_run_table(folder, run, table, target, record)
    print(f"{len(sm.output)} tables from {folder}, SHA-256 and values checked against the record")
