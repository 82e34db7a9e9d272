"""Snakemake: the sparse model's held-out error by nested cross-validation with seeds held out
(rule nested_selection)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_benchmark, nested_selection
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    startup_runs = tables.read_fabric_table(sm.input.startup_runs)
    rotation_runs = tables.read_fabric_table(sm.input.rotation_runs)
    curves = model_benchmark.seed_curves(startup_runs, rotation_runs, sm.params.window, sm.params.steady_window)
    if len(curves.seeds) < 2 * nested_selection.SEED_GROUPS:
        comparison, folds = pd.DataFrame(), pd.DataFrame()
    else:
        errors, folds = nested_selection.nested_errors(
            startup_runs,
            rotation_runs,
            curves,
            sm.params.phi,
            sm.params.startup_strain,
            sm.params.folds,
            sm.params.steady_window,
        )
        comparison = nested_selection.nested_comparison(errors, curves, sm.params.level)
    comparison.to_csv(sm.output.comparison, index=False)
    folds.to_csv(sm.output.folds, index=False)
    summary = nested_selection.summary_markdown(comparison, folds)
    Path(sm.output.summary).write_text(summary)
    print(summary)
