"""Snakemake: concatenated run table, seed aggregate and, for startup, the steady state of the
fabric or the stress (rules aggregate_startup, aggregate_rotation, aggregate_stress_startup and
aggregate_stress_rotation; params.kind, params.quantity and, for the stress,
params.lubrication_stress)."""

from functools import partial

import pandas as pd

from suspension_fabric.analysis import stress, tables
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

READERS = {
    "fabric": (tables.read_fabric_table, tables.VALUE_COLUMNS),
    "stress": (stress.read_stress_csv, stress.STRESS_VALUE_COLUMNS),
}

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    if sm.params.kind not in ("startup", "rotation"):
        raise ValueError(f"params.kind must be 'startup' or 'rotation', got {sm.params.kind!r}")
    if sm.params.quantity not in READERS:
        raise ValueError(f"params.quantity must be one of {sorted(READERS)}, got {sm.params.quantity!r}")
    read, columns = READERS[sm.params.quantity]
    if sm.params.quantity == "stress":
        read = partial(read, lubrication_stress=sm.params.lubrication_stress)
    runs = pd.concat([read(p) for p in sm.input], ignore_index=True)
    if sm.params.quantity == "stress":  # the stresslets only where the runs recorded them
        columns = stress.recorded_value_columns(runs, f"{len(sm.input)} stress tables ({sm.input[0]} ...)")
    runs.to_csv(sm.output.runs, index=False)
    tables.aggregate_seeds(runs, columns).to_csv(sm.output.aggregate, index=False)
    if sm.params.kind == "startup":
        steady = tables.steady_state(runs, *sm.params.steady_window, value_columns=columns)
        steady.to_csv(sm.output.steady, index=False)
        print(steady.to_string())
