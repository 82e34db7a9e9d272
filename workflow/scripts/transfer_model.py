"""Snakemake: the transfer model over a campaign's points, each point held out in turn, and the fit on
every point as a model file (rule transfer_model)."""

import pandas as pd

from suspension_fabric.evaluation import model_transfer
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.study.campaign import study_configs
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    studies = study_configs(sm.config)
    points = [
        model_transfer.map_point(
            name,
            studies[study],
            pd.read_csv(sm.input.startup_runs[k]),
            pd.read_csv(sm.input.rotation_runs[k]),
            read_fits(sm.input.fits[k]),
            sm.params.window,
        )
        for k, (name, study) in enumerate(sm.params.points.items())
    ]
    scores, folds = model_transfer.leave_one_point_out(points)
    table = model_transfer.point_table(scores, points, sm.params.level)
    table.to_csv(sm.output.points, index=False)
    folds.to_csv(sm.output.folds, index=False)
    with open(sm.output.summary, "w") as out:
        out.write(model_transfer.points_markdown(table, folds, sm.params.required))
    fit = model_transfer.fit_transfer(points)
    model_transfer.write_transfer_file(sm.output.model, fit, points, sm.params.datasets or "simulated here")
    print(folds.drop(columns="terms").to_string(index=False))
    print(table.to_string(index=False))
