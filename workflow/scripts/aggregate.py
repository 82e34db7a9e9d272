"""Snakemake: concatenated run table, seed aggregate and, for startup, the steady state."""
import pandas as pd

from suspension_fabric import tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    runs = pd.concat([tables.read_fabric_table(p) for p in sm.input], ignore_index=True)
    tables.write_fabric_table(runs, sm.output.runs)
    tables.aggregate_seeds(runs).to_csv(sm.output.aggregate, index=False)
    if "steady" in sm.output.keys():
        steady = tables.steady_state(runs, *sm.params.steady_window)
        steady.to_csv(sm.output.steady, index=False)
        print(steady.to_string())
