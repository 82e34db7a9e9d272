"""Snakemake: G-W's error after a rotation taken apart into the closure's and the dynamics' (and the
stress relation's N1, N2, Pi into the fabric's, the closure's and the relation's) (rule
error_decomposition)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.stress import read_stress_csv
from suspension_fabric.evaluation import error_decomposition as decomposition
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    startup = pd.concat([tables.read_fabric_table(p, moments=True) for p in sm.input.startup], ignore_index=True)
    rotation = pd.concat([tables.read_fabric_table(p, moments=True) for p in sm.input.rotation], ignore_index=True)
    if decomposition.has_fourth_moment(startup) and decomposition.has_fourth_moment(rotation):
        scores, stress = decomposition.decompose(
            startup,
            rotation,
            read_stress_csv(sm.input.stress_startup),
            read_stress_csv(sm.input.stress_rotation),
            sm.params.phi,
            sm.params.steady_window,
            sm.params.window,
        )
        fabric_table = decomposition.decomposition_table(scores, sm.params.level)
        stress_table = decomposition.stress_decomposition_table(stress, sm.params.level)
    else:
        print("the runs predate the fourth moment: empty tables")
        scores, stress, fabric_table, stress_table = (pd.DataFrame() for _ in range(4))
    scores.to_csv(sm.output.per_seed, index=False)
    stress.to_csv(sm.output.stress_per_seed, index=False)
    fabric_table.to_csv(sm.output.table, index=False)
    stress_table.to_csv(sm.output.stress, index=False)
    summary = decomposition.summary_markdown(fabric_table, stress_table, scores)
    Path(sm.output.summary).write_text(summary)
    print(summary)
