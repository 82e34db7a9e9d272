"""Snakemake: the fabric-model benchmark on held-out rotation angles and its leaderboard (rule benchmark_models)."""

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import model_benchmark
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.leaderboard_pages import write_leaderboard_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = read_fits(sm.input.fits)
    curves = model_benchmark.seed_curves(
        tables.read_fabric_table(sm.input.startup_runs),
        tables.read_fabric_table(sm.input.rotation_runs),
        sm.params.window,
        sm.params.steady_window,
    )
    board, parameters = model_benchmark.leaderboard(
        resolve_models(sm.params.models),
        fits["models"],
        curves,
        fits["phi"],
        sm.params.startup_strain,
        sm.params.folds,
        reference=sm.params.reference,
        level=sm.params.level,
    )
    board.to_csv(sm.output.leaderboard, index=False)
    parameters.to_csv(sm.output.parameters, index=False)
    print(write_leaderboard_page(board, parameters, sm.output.page, sm.params.level))
    print(parameters.to_string(index=False))
