"""Snakemake: the G-W stress relation fitted, predicted and compared (rule stress_relation)."""

import pandas as pd

from suspension_fabric.evaluation import stress_model
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = read_fits(sm.input.fits)
    steady = pd.read_csv(sm.input.stress_steady)
    stress_startup = pd.read_csv(sm.input.stress_startup)
    stress_rotation = pd.read_csv(sm.input.stress_rotation)
    relation = stress_model.relation_fits(steady, fits)
    relation.to_csv(sm.output.fits, index=False)
    predicted = stress_model.stress_predictions(
        relation,
        pd.read_csv(sm.input.startup),
        pd.read_csv(sm.input.rotation),
        pd.read_csv(sm.input.predictions),
        fits["phi"],
    )
    predicted.to_csv(sm.output.predictions, index=False)
    sigma12_ss = stress_model.steady_value(steady, "eta_r")[0]
    errors = stress_model.relation_errors(stress_startup, stress_rotation, predicted, sigma12_ss)
    errors.to_csv(sm.output.errors, index=False)
    summary = stress_model.summarise_relation_errors(errors)
    summary.to_csv(sm.output.summary, index=False)
    # the viscosity after a rotation, per seed against that seed's own steady eta_r
    eta_ss_seed = stress_model.seed_steady_viscosity(pd.read_csv(sm.input.stress_startup_runs), sm.params.steady_window)
    rotation_runs = pd.read_csv(sm.input.stress_rotation_runs)
    deficits = stress_model.viscosity_deficits(rotation_runs, eta_ss_seed, sm.params.window)
    deficits.to_csv(sm.output.deficits, index=False)
    transients = stress_model.viscosity_transients(rotation_runs, eta_ss_seed, sm.params.window, sm.params.level)
    transients.to_csv(sm.output.transients, index=False)
    print(relation.to_string(), summary.to_string(), transients.to_string(), sep="\n\n")
