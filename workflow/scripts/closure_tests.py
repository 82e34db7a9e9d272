"""Snakemake: each closure of <nnnn> against the measured fourth moment, per seed, after the
startup and after each rotation, and the figure of the implied direction distributions (rule
closure_tests)."""

from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import closure_tests
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting.closure_figures import figure_closures
from suspension_fabric.reporting.figures import save_figure
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    startup = pd.concat([tables.read_fabric_table(p, moments=True) for p in sm.input.startup], ignore_index=True)
    rotation = pd.concat([tables.read_fabric_table(p, moments=True) for p in sm.input.rotation], ignore_index=True)
    steady = closure_tests.seed_window_errors(closure_tests.frame_errors(startup), sm.params.steady_window)
    after = closure_tests.seed_window_errors(closure_tests.frame_errors(rotation), (0.0, sm.params.window))
    per_seed = pd.concat([steady.assign(protocol="startup"), after.assign(protocol="rotation")])
    per_seed.to_csv(sm.output.per_seed, index=False)
    table = pd.concat(
        [
            closure_tests.closure_error_table(steady, sm.params.level).assign(protocol="startup"),
            closure_tests.closure_error_table(after, sm.params.level).assign(protocol="rotation"),
        ],
        ignore_index=True,
    )
    table.to_csv(sm.output.table, index=False)
    print(table[table["measure"] == "drive"].to_string(index=False))
    recorded = rotation.dropna(subset=list(tables.MOMENT_COLUMNS))
    frames = recorded[np.isclose(recorded["strain"], sm.params.snapshot_strain, atol=1e-6)]
    snapshots = frames.groupby("theta")[[*tables.VALUE_COLUMNS, *tables.MOMENT_COLUMNS, "strain"]].mean().reset_index()
    fig = figure_closures(table[table["protocol"] == "rotation"], snapshots, sm.params.window, sm.params.level)
    print(save_figure(fig, Path(sm.output.pdf).with_suffix("")))
