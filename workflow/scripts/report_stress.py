"""Snakemake: the stress tables as a report page (rule report_stress)."""

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting.stress_page import write_stress_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    print(
        write_stress_page(
            pd.read_csv(sm.input.steady),
            pd.read_csv(sm.input.relation),
            pd.read_csv(sm.input.summary),
            pd.read_csv(sm.input.transients),
            sm.output[0],
        )
    )
