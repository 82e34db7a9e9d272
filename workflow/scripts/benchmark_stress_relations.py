"""Snakemake: stress relations scored on the steady normal stresses and held-out viscosity transients
(rule benchmark_stress_relations)."""

from suspension_fabric.evaluation import stress_benchmark
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.stress_relations import resolve_relations
from suspension_fabric.reporting.leaderboard_pages import write_stress_leaderboard_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    curves = stress_benchmark.read_stress_curves(
        sm.input.startup_runs,
        sm.input.rotation_runs,
        sm.input.stress_startup_runs,
        sm.input.stress_rotation_runs,
        sm.params.window,
        sm.params.steady_window,
    )
    relations = resolve_relations(sm.params.relations)
    # paired differences from the first relation of models.stress
    board, parameters = stress_benchmark.relation_leaderboard(
        relations, curves, sm.params.folds, reference=next(iter(relations)), level=sm.params.level
    )
    board.to_csv(sm.output.leaderboard, index=False)
    parameters.to_csv(sm.output.parameters, index=False)
    print(write_stress_leaderboard_page(board, parameters, sm.output.page, sm.params.level))
    print(board.to_string(index=False), parameters.to_string(index=False), sep="\n\n")
