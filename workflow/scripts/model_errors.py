"""Snakemake: model-versus-simulation error table and its summary (rule model_errors)."""

import pandas as pd

from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    errors, summary = model_vs_simulation.error_tables(
        read_fits(sm.input.fits),
        pd.read_csv(sm.input.predictions),
        pd.read_csv(sm.input.startup),
        pd.read_csv(sm.input.rotation),
        ratio=(sm.params.compared["reference"], sm.params.compared["challenger"]),
    )
    errors.to_csv(sm.output.table, index=False)
    summary.to_csv(sm.output.summary, index=False)
    print(summary.to_string(index=False))
