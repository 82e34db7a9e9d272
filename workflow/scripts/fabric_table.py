"""Snakemake: near-contact fabric table of one run (rule fabric_table)."""

from suspension_fabric.analysis import tables
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    table = tables.run_fabric_table(sm.input.dump, sm.input.marker, seed=int(sm.wildcards.seed), eps=sm.params.eps)
    tables.write_fabric_table(table, sm.output[0])
    print(f"{len(table)} frames, mean Z = {table['Z'].mean():.3f}, measured phi = {table['phi'].iloc[0]:.4f}")
