"""Snakemake: the verdict on each of the paper's claims and the tables behind it (rule verdicts)."""
import pandas as pd

from suspension_fabric import model_vs_simulation, report_tables, verdicts
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    table, details = verdicts.verdict_table(model_vs_simulation.read_fits(sm.input.fits),
                                            pd.read_csv(sm.input.runs), pd.read_csv(sm.input.predictions))
    table.to_csv(sm.output.verdicts, index=False)
    details["recovery"].to_csv(sm.output.recovery, index=False)
    details["rms"].to_csv(sm.output.rms, index=False)
    details["overshoot"].to_csv(sm.output.overshoot, index=False)
    report_tables.write_verdicts_page(table, details["recovery"], sm.output.page)
    print(table[["claim", "value", "error", "verdict"]].to_string(index=False))
