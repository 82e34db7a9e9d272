"""Snakemake: Fig. 4, the stress after shear rotations (rule figure_stress_rotation)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.evaluation.stress_model import steady_value
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting import figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    sigma12_ss = steady_value(pd.read_csv(sm.input.steady), "eta_r")[0]
    fig = figures.figure_stress_rotation(
        pd.read_csv(sm.input.stress), pd.read_csv(sm.input.predictions), pd.read_csv(sm.input.transients), sigma12_ss
    )
    print(figures.save_figure(fig, Path(sm.output.pdf).with_suffix("")))
