"""Snakemake: the fabric-model benchmark on held-out rotation angles and its leaderboard (rule benchmark_models)."""

from suspension_fabric.analysis import tables
from suspension_fabric.models import model_benchmark, model_vs_simulation
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.reporting import report_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = model_vs_simulation.read_fits(sm.input.fits)
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
        level=sm.params.level,
    )
    board.to_csv(sm.output.leaderboard, index=False)
    parameters.to_csv(sm.output.parameters, index=False)
    print(report_tables.write_leaderboard_page(board, parameters, sm.output.page, sm.params.level))
    print(parameters.to_string(index=False))
