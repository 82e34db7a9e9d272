"""Snakemake: the stress per dumped frame of one run (rule stress_table)."""

from suspension_fabric.analysis.stress import STRESS_FLOAT_FORMAT, run_stress_table
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.simulation.engine_rule import check_run_stiffness
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    table = run_stress_table(sm.input.table, sm.input.marker, sm.input.fabric)
    check_run_stiffness(table["strain"], table["Pi"], sm.input.marker)
    table.to_csv(sm.output[0], index=False, float_format=STRESS_FLOAT_FORMAT)
    print(table[["strain", "n_rows", "eta_r", "N1", "N2", "Pi"]].describe().to_string())
