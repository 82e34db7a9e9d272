"""Snakemake: readable HTML tables of fits.json, the steady state and the error summary (rule report_tables)."""

import pandas as pd

from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.fits_page import write_fits_page
from suspension_fabric.reporting.model_errors_page import write_error_summary_page
from suspension_fabric.reporting.steady_state_page import write_steady_state_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = read_fits(sm.input.fits)
    print(write_fits_page(fits, sm.output.fits))
    print(write_steady_state_page(pd.read_csv(sm.input.steady), sm.output.steady))
    print(
        write_error_summary_page(pd.read_csv(sm.input.errors), model_vs_simulation.model_labels(fits), sm.output.errors)
    )
