"""Snakemake: paper Fig. 1 (rule figure_startup)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting import figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fig = figures.figure_startup(
        pd.read_csv(sm.input.startup), pd.read_csv(sm.input.predictions), read_fits(sm.input.fits)
    )
    print(figures.save_figure(fig, Path(sm.output.pdf).with_suffix("")))
