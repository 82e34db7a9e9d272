"""Snakemake: the response to a change of flow direction at each point of a flow-curve campaign, each
rotated run against its seed's theta = 0 run; the table, its Markdown fragment and the figure
(rule direction_response)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.evaluation import direction_response
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting.direction_response_figures import figure_direction_response
from suspension_fabric.reporting.direction_response_fragments import direction_response_summary
from suspension_fabric.reporting.figures import save_figure
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    points = {
        name: {**point, "stress": pd.read_csv(stress), "fabric": pd.read_csv(fabric)}
        for (name, point), stress, fabric in zip(sm.params.points.items(), sm.input.stress_runs, sm.input.fabric_runs)
    }
    per_seed = pd.concat(
        [
            direction_response.per_seed_responses(point["stress"], point["fabric"]).assign(
                point=name, label=point["label"], target=point["target"]
            )
            for name, point in points.items()
        ],
        ignore_index=True,
    )
    table = direction_response.response_table(per_seed.drop(columns="target"), sm.params.level)
    ordered = sorted(points, key=lambda name: points[name]["target"])
    labels = {name: point["label"] for name, point in points.items()}
    comparisons = direction_response.neighbour_comparisons(per_seed, ordered, labels, sm.params.level)
    per_seed.to_csv(sm.output.seeds, index=False)
    table.to_csv(sm.output.table, index=False)
    comparisons.to_csv(sm.output.comparisons, index=False)
    with open(sm.output.summary, "w") as out:
        out.write(direction_response_summary(table, comparisons, sm.params.level))
    figure = figure_direction_response({points[name]["label"]: points[name] for name in ordered}, sm.params.level)
    save_figure(figure, str(Path(sm.output.figure_png).with_suffix("")))
    print(table.to_string())
    print(comparisons.to_string())
