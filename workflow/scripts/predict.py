"""Snakemake: model predictions at the simulated strains and angles plus a polar grid (rule predict)."""
import numpy as np
import pandas as pd

from suspension_fabric import study
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = study.read_fits(sm.input.fits)
    startup, rotation = pd.read_csv(sm.input.startup), pd.read_csv(sm.input.rotation)
    thetas = np.sort(rotation["theta"].unique())
    low = -180.0 if thetas.min() < 0 else 0.0
    polar = np.arange(low, 180.0 + 1e-9, sm.params.polar_step)
    predictions = study.predict(
        fits, study.initial_fabric(startup), np.sort(startup["strain"].unique()), sm.params.startup_strain,
        thetas, np.sort(rotation[rotation["theta"] == thetas[0]]["strain"].unique()), extra_thetas_deg=polar,
    )
    predictions.to_csv(sm.output[0], index=False)
    print(f"{len(predictions)} rows")
