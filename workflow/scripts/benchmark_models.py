"""Snakemake: the fabric-model benchmark on held-out rotation angles and its leaderboard (rule benchmark_models)."""

from pathlib import Path

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_benchmark, model_targets
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.leaderboard_pages import write_leaderboard_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = read_fits(sm.input.fits)
    curves = model_benchmark.seed_curves(
        tables.read_fabric_table(sm.input.startup_runs),
        tables.read_fabric_table(sm.input.rotation_runs),
        sm.params.window,
        sm.params.steady_window,
    )
    models = resolve_models(sm.params.models)
    board, parameters, held_out = model_benchmark.leaderboard(
        models,
        fits["models"],
        curves,
        fits["phi"],
        sm.params.startup_strain,
        sm.params.folds,
        reference=sm.params.reference,
        level=sm.params.level,
        study=sm.wildcards.study,
    )
    board.to_csv(sm.output.leaderboard, index=False)
    parameters.to_csv(sm.output.parameters, index=False)
    print(write_leaderboard_page(board, parameters, sm.output.page, sm.params.level))
    print(parameters.to_string(index=False))
    targets = model_targets.scorecard(
        models,
        held_out,
        curves,
        fits["phi"],
        fits["targets"],
        sm.params.steady_window,
        reference=sm.params.reference,
        level=sm.params.level,
    )
    targets.to_csv(sm.output.targets, index=False)
    notes = model_targets.found_here(sm.params.models, models, sm.wildcards.study)
    summary = model_targets.scorecard_markdown(targets, models[sm.params.reference].label, notes)
    Path(sm.output.targets_summary).write_text(summary)
    print(summary)
