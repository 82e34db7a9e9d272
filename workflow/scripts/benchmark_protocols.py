"""Snakemake: every fabric model and stress relation on each of the study's own protocols (rule
benchmark_protocols)."""

import pandas as pd

from suspension_fabric.analysis.protocol_tables import read_protocol_table
from suspension_fabric.evaluation import protocol_benchmark, stress_benchmark
from suspension_fabric.io.fit_provenance import check_provenance, seen_seeds
from suspension_fabric.io.protocols import protocols_from_params
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import load_model, resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.models.sparse_fabric import model_file_source
from suspension_fabric.models.stress_relations import resolve_relations
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = read_fits(sm.input.fits)
    steady = stress_benchmark.read_stress_curves(
        sm.input.startup_runs,
        sm.input.rotation_runs,
        sm.input.stress_startup_runs,
        sm.input.stress_rotation_runs,
        sm.params.window,
        sm.params.steady_window,
    )
    steady_fabric = steady.steady_fabric.mean(axis=0)
    protocols = protocols_from_params(sm.params.protocols)
    runs = read_protocol_table(sm.input.protocol_runs)
    stress_runs = read_protocol_table(sm.input.stress_protocol_runs)
    curves = {name: protocol_benchmark.protocol_curves(p, runs, stress_runs) for name, p in protocols.items()}
    models = resolve_models(sm.params.models)
    fitted = pd.read_csv(sm.input.model_parameters)
    check_provenance(fitted, sm.input.model_parameters)
    sources = {load_model(spec).key: model_file_source(spec) for spec in sm.params.models if spec.endswith(".json")}
    # each fit's values, and its jackknife errors and correlations, propagated into the scores' intervals
    mode_parameters, parameter_errors, parameter_correlations = protocol_benchmark.parameters_by_mode(fitted)
    board, predictions = protocol_benchmark.fabric_protocol_leaderboard(
        models,
        mode_parameters,
        curves,
        fits["phi"],
        float(steady_fabric[0, 1]),
        seen=seen_seeds(fitted, sources),
        reference=sm.params.reference,
        level=sm.params.level,
        parameter_errors=parameter_errors,
        parameter_correlations=parameter_correlations,
    )
    fitted_on = fitted.groupby(["model", "mode"])["fitted_on"].first()
    board.insert(3, "fitted_on", [fitted_on[key] for key in zip(board["model"], board["mode"])])
    board.to_csv(sm.output.leaderboard, index=False)
    predictions.to_csv(sm.output.predictions, index=False)
    relations = resolve_relations(sm.params.relations)
    stress_board = protocol_benchmark.stress_protocol_leaderboard(
        relations,
        pd.read_csv(sm.input.relation_parameters),
        steady_fabric,
        steady.steady[["lubrication_12", "contact_12", "eta_r"]].mean().to_dict(),
        curves,
        steady.phi,
        seen=set(pd.read_csv(sm.input.startup_runs)["seed"]),  # the relations are fitted on this study's steady state
        reference=next(iter(relations)),
        level=sm.params.level,
    )
    stress_board.to_csv(sm.output.stress_leaderboard, index=False)
    shown = board[board["component"] == protocol_benchmark.ALL_COMPONENTS]
    print(shown.drop(columns=["label", "component"]).to_string(index=False))
    print(stress_board[stress_board["quantity"] == "eta_r"].drop(columns="label").to_string(index=False))
