"""Snakemake: Fig. 3, the stress in startup shear (rule figure_stress_startup)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting import figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fig = figures.figure_stress_startup(
        pd.read_csv(sm.input.stress), pd.read_csv(sm.input.predictions), pd.read_csv(sm.input.relation)
    )
    print(figures.save_figure(fig, Path(sm.output.pdf).with_suffix("")))
