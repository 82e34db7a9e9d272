"""Snakemake: the fabric or the stress along each of a study's own protocols, per seed and
seed-averaged, and the late state of every segment (rules aggregate_protocols and
aggregate_stress_protocols; params.quantity)."""

from pathlib import Path

from suspension_fabric.analysis import stress, tables
from suspension_fabric.analysis.protocol_tables import protocol_tables, segment_states
from suspension_fabric.io.protocols import protocols_from_params
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    root = Path(sm.output.runs).parent.parent
    if sm.params.quantity == "fabric":
        columns = tables.VALUE_COLUMNS

        def read(run, seed):
            return tables.read_fabric_table(root / f"seed{seed}" / run / "fabric.csv")

    elif sm.params.quantity == "stress":

        def read(run, seed):
            return stress.read_stress_csv(root / f"seed{seed}" / run / "stress.csv", sm.params.lubrication_stress)

        columns = stress.recorded_value_columns(
            read(next(iter(sm.params.runs.values()))[0], sm.params.seeds[0]), "stress tables"
        )
    else:
        raise ValueError(f"params.quantity must be 'fabric' or 'stress', got {sm.params.quantity!r}")
    protocols = protocols_from_params(sm.params.protocols)
    runs, aggregate = protocol_tables(protocols, sm.params.runs, read, sm.params.seeds, columns)
    runs.to_csv(sm.output.runs, index=False)
    aggregate.to_csv(sm.output.aggregate, index=False)
    states = segment_states(protocols, runs, columns, sm.params.steady_window, sm.params.level)
    states.to_csv(sm.output.states, index=False)
    for name, group in aggregate.groupby("protocol", sort=False):
        print(f"{name}: {group['segment'].nunique()} segments, strain 0-{group['strain'].max():g}")
