"""Snakemake: a fabric model found by sparse regression, its terms chosen by held-out error, scored
against the reference model (rule discover_model)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_benchmark, model_discovery, model_targets
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.models.sparse_fabric import sparse_model, write_model_file
from suspension_fabric.workflow_io import job_study_config, logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = read_fits(sm.input.fits)
    startup_runs = tables.read_fabric_table(sm.input.startup_runs)
    rotation_runs = tables.read_fabric_table(sm.input.rotation_runs)
    curves = model_benchmark.seed_curves(startup_runs, rotation_runs, sm.params.window, sm.params.steady_window)
    try:
        found = model_discovery.discover(
            startup_runs,
            rotation_runs,
            curves,
            fits["phi"],
            sm.params.startup_strain,
            sm.params.folds,
            sm.params.steady_window,
            sm.params.level,
        )
    except ValueError as failure:  # e.g. no candidate can be integrated on a tiny study
        found, reason = None, str(failure)
        print(f"no sparse model: {reason}")
    if found is None:
        for name in ("supports", "coefficients", "target", "overshoot", "steady"):
            Path(sm.output[name]).write_text("")
        Path(sm.output.model).write_text("{}\n")
        Path(sm.output.summary).write_text(f"No sparse model was found on this study: {reason}\n")
    else:
        reference = resolve_models(sm.params.models)[sm.params.reference]
        _, predicted = model_benchmark.model_curves(
            reference, fits["models"][reference.key]["parameters"], fits["phi"], curves, sm.params.startup_strain
        )
        target = model_targets.target_table(
            found["held_out"], model_benchmark.seed_errors(predicted, curves), curves, sm.params.level
        )
        model = sparse_model(found["coefficients"], steady_fabric=found["steady_fabric"])
        steady = model_discovery.steady_table(model, curves, fits["targets"], fits["phi"])
        overshoot = model_targets.overshoot_table(
            found["held_out_predicted"], found["steady_fabric"][0, 1], curves, sm.params.steady_window, sm.params.level
        )
        study = job_study_config(sm)
        write_model_file(
            sm.output.model,
            found["coefficients"],
            found["errors"],
            {"study": study["study"], "seeds": study["seeds"], "angles_deg": study["angles_deg"], "phi": fits["phi"]},
            found["steady_fabric"],
        )
        found["supports"].to_csv(sm.output.supports, index=False)
        model_discovery.coefficient_table(found).to_csv(sm.output.coefficients, index=False)
        target.to_csv(sm.output.target, index=False)
        steady.to_csv(sm.output.steady, index=False)
        pd.DataFrame([overshoot]).to_csv(sm.output.overshoot, index=False)
        summary = model_discovery.summary_markdown(found, target, overshoot, steady, reference.label)
        Path(sm.output.summary).write_text(summary)
        print(summary)
