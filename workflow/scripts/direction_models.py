"""Snakemake: fabric models after a change of flow direction at each point of a flow-curve campaign,
against no transient and between the points; the tables and their Markdown fragment (rule
direction_models)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.evaluation import direction_models, model_benchmark
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fabric_models import resolve_models
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.direction_models_fragments import direction_models_summary, fits_line
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    reach = min(point["rotation_strain"] for point in sm.params.points.values())
    windows = sorted({*(w for w in direction_models.SENSITIVITY_WINDOWS if w <= reach), sm.params.window})
    ordered = sorted(sm.params.points, key=lambda name: sm.params.points[name]["target"])  # unthickened first
    inputs = dict(zip(sm.params.points, zip(sm.input.startup_runs, sm.input.rotation_runs, sm.input.fits)))
    scores, labels, fitted = [], {}, {}
    for name in ordered:
        point = sm.params.points[name]
        startup, rotation, fits_file = inputs[name]
        fits = fitted[name] = read_fits(fits_file)
        curves = model_benchmark.seed_curves(
            tables.read_fabric_table(startup),
            tables.read_fabric_table(rotation),
            max(windows),
            point["steady_window"],
        )
        models = resolve_models(point["models"])
        labels |= {key: model.label for key, model in models.items()}
        scores.append(
            direction_models.point_scores(
                models,
                fits["models"],
                curves,
                fits["phi"],
                point["startup_strain"],
                point["steady_window"],
                name,
                windows,
            )
        )
    scores = pd.concat(scores, ignore_index=True)
    skill = direction_models.skill_table(scores, labels, sm.params.level)
    comparison = direction_models.state_comparison(scores, labels, sm.params.level)
    scores.to_csv(sm.output.seeds, index=False)
    skill.to_csv(sm.output.skill, index=False)
    comparison.to_csv(sm.output.comparison, index=False)
    point_labels = {name: p["label"] for name, p in sm.params.points.items()}
    summary = direction_models_summary(
        skill, comparison, point_labels, sm.params.window, fits_line(fitted, point_labels, labels)
    )
    Path(sm.output.summary).write_text(summary)
    print(summary)
