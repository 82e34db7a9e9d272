"""Snakemake: the flow curves of a campaign over critical-load rates, their per-seed table, the onset
stress, thickening exponents and shape of each curve, the Wyart-Cates fit and the figure (rule flow_curve)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.evaluation import flow_curve
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting.figures import save_figure
from suspension_fabric.reporting.flow_curve_figures import figure_flow_curve
from suspension_fabric.reporting.flow_curve_fragments import flow_curve_summary
from suspension_fabric.study.dataset import load
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    points = {
        name: {**point, "runs": pd.read_csv(path)}
        for (name, point), path in zip(sm.params.points.items(), sm.input.stress_runs)
    }
    per_seed = flow_curve.per_seed_table(points, sm.params.steady_window)
    table = flow_curve.flow_curve_table(per_seed, sm.params.level)
    onsets = pd.DataFrame(
        [
            {"phi": phi, "mu": mu, "control": control, **flow_curve.onset_stress(rows, sm.params.level)}
            for (phi, mu, control), rows in per_seed.groupby(["phi", "mu", "control"])
        ]
    )
    differences = flow_curve.onset_differences(onsets, sm.params.level)
    onsets = onsets.drop(columns="per_seed")
    frictionless = {}
    for record in sm.input.frictionless:
        loaded = load(Path(record).parent)
        window = loaded.config["analysis"]["steady_window"]
        frictionless[Path(record).parent.name] = (loaded.config["particles"]["phi"], window, loaded.stress_startup)
    frictionless = flow_curve.frictionless_steady(frictionless)
    frictionless.to_csv(sm.output.frictionless, index=False)
    wyart_cates = flow_curve.wyart_cates_fit(per_seed, sm.params.level, frictionless)
    exponents = flow_curve.thickening_exponents(per_seed, sm.params.level)
    exponents.to_csv(sm.output.exponents, index=False)
    shape = flow_curve.curve_shape(per_seed, sm.params.shape_window, sm.params.level)
    shape.to_csv(sm.output.shape, index=False)
    wyart_cates.to_csv(sm.output.wyart_cates, index=False)
    per_seed.to_csv(sm.output.seeds, index=False)
    table.to_csv(sm.output.table, index=False)
    onsets.to_csv(sm.output.onsets, index=False)
    with open(sm.output.summary, "w") as out:
        out.write(
            flow_curve_summary(table, onsets, differences, exponents, wyart_cates, sm.params.level, frictionless, shape)
        )
    save_figure(figure_flow_curve(table, onsets, sm.params.level), str(Path(sm.output.figure_png).with_suffix("")))
    shown = ["point", "rate_ratio", "sigma", "eta_r", "frictional_fraction", "Z_touching", "Z_frictional"]
    print(table[shown].to_string())
    print(onsets.to_string())
    print(wyart_cates.to_string())
