"""Snakemake: the study against its comparison datasets, quantity by quantity (rule compare_datasets)."""

import pandas as pd

from suspension_fabric.evaluation.dataset_comparison import comparison_table, per_seed_statistics
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.study.dataset import read_fabric_runs, read_stress_runs
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    window, steady_window = sm.params.window, sm.params.steady_window
    study = sm.wildcards.study
    per_seed = {
        study: (
            sm.params.n,
            per_seed_statistics(
                pd.read_csv(sm.input.startup),
                pd.read_csv(sm.input.stress_startup),
                pd.read_csv(sm.input.stress_rotation),
                steady_window,
                window,
            ),
        )
    }
    for label, folder in sm.params.comparisons.items():
        record, startup, _ = read_fabric_runs(folder)
        stress = read_stress_runs(folder, record) or (None, None)
        per_seed[label] = (
            record["config"]["particles"]["n"],
            per_seed_statistics(startup, *stress, steady_window, window),
        )
    table = comparison_table(per_seed, study, sm.params.level)
    table.to_csv(sm.output[0], index=False)
    print(table.to_string())
