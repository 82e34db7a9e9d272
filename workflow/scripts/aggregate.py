"""Snakemake: concatenated run table, seed aggregate and, for startup, the steady state
(rules aggregate_startup and aggregate_rotation; params.kind)."""
import pandas as pd

from suspension_fabric import tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    if sm.params.kind not in ("startup", "rotation"):
        raise ValueError(f"params.kind must be 'startup' or 'rotation', got {sm.params.kind!r}")
    runs = pd.concat([tables.read_fabric_table(p) for p in sm.input], ignore_index=True)
    tables.write_fabric_table(runs, sm.output.runs)
    tables.aggregate_seeds(runs).to_csv(sm.output.aggregate, index=False)
    if sm.params.kind == "startup":
        steady = tables.steady_state(runs, *sm.params.steady_window)
        steady.to_csv(sm.output.steady, index=False)
        print(steady.to_string())
