"""Snakemake: model-versus-simulation error table and its summary (rule model_errors)."""
import pandas as pd

from suspension_fabric import study
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = study.read_fits(sm.input.fits)
    predictions = pd.read_csv(sm.input.predictions)
    n12_ss = fits["targets"]["n12"]["mean"]
    errors = pd.concat([
        study.model_errors(pd.read_csv(sm.input.startup), predictions, n12_ss, "startup"),
        study.model_errors(pd.read_csv(sm.input.rotation), predictions, n12_ss, "rotation"),
    ], ignore_index=True)
    errors.to_csv(sm.output.table, index=False)
    summary = study.summarise_errors(errors)
    summary.to_csv(sm.output.summary, index=False)
    print(summary.to_string(index=False))
