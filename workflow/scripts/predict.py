"""Snakemake: model predictions at the simulated strains and angles plus a polar grid (rule predict)."""

import pandas as pd

from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    predictions = model_vs_simulation.predict_on_simulation_grids(
        read_fits(sm.input.fits),
        resolve_models(sm.params.models),
        pd.read_csv(sm.input.startup),
        pd.read_csv(sm.input.rotation),
        sm.params.startup_strain,
        sm.params.polar_step,
    )
    predictions.to_csv(sm.output[0], index=False)
    print(f"{len(predictions)} rows")
