"""Snakemake: Fig. 5, the quantities the shear-rotation claims rest on, per angle (rule figure_claims)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting import figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    statistics = pd.read_csv(sm.input.statistics)
    fig = figures.figure_claims(statistics[statistics["choice"] == "primary"], sm.params.level)
    print(figures.save_figure(fig, Path(sm.output.pdf).with_suffix("")))
