"""Snakemake: fit every model of models.fabric to the simulated steady state, with jackknife errors
over the seeds of the startup runs (rule fit_models)."""

import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import write_fits
from suspension_fabric.workflow_io import job_study_config, logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = model_vs_simulation.fit_steady_state(
        pd.read_csv(sm.input.steady),
        sm.params.phi,
        tables.read_fabric_table(sm.input.runs),
        *sm.params.steady_window,
        models=resolve_models(sm.params.models),
    )
    study = job_study_config(sm)
    fits["provenance"] = {
        "study": study["study"],
        "seeds": study["seeds"],
        "N": study["particles"]["n"],
        "steady_state_table": sm.input.steady,
        "runs_table": sm.input.runs,
    }
    write_fits(fits, sm.output[0])
    for key, entry in fits["models"].items():
        print(
            f"{key}: "
            + ", ".join(
                f"{name} = {value:.4g} ± {entry['errors'][name]:.2g} (jackknife over seeds), "
                f"± {entry['errors_propagated'][name]:.2g} (propagated)"
                for name, value in entry["parameters"].items()
            )
        )
