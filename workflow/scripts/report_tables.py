"""Snakemake: readable HTML tables of fits.json, the steady state and the error summary (rule report_tables)."""

import pandas as pd

from suspension_fabric.models import model_vs_simulation
from suspension_fabric.reporting import report_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = model_vs_simulation.read_fits(sm.input.fits)
    print(report_tables.write_fits_page(fits, sm.output.fits))
    print(report_tables.write_steady_state_page(pd.read_csv(sm.input.steady), sm.output.steady))
    print(
        report_tables.write_error_summary_page(
            pd.read_csv(sm.input.errors), sm.output.errors, model_vs_simulation.model_labels(fits)
        )
    )
