"""Snakemake: the map figures against phi, one line per mu (rule campaign_figures)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting.map_figures import save_map_figures
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    for path in save_map_figures(pd.read_csv(sm.input[0]), sm.params.level, Path(sm.output[0]).parent):
        print(path)
