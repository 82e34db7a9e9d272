"""Snakemake: the verdict on each of the paper's claims, per angle, at the range edges, under each
choice and comparison dataset, and the descriptive tables (rule verdicts)."""

import pandas as pd

from suspension_fabric.evaluation import claims, verdicts
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.verdicts_page import write_verdicts_page
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    level = sm.params.level
    fits = read_fits(sm.input.fits)
    compared = claims.Compared.from_specs(sm.params.compared)
    values = pd.read_csv(sm.input.values)
    by_choice = {choice: rows for choice, rows in values.groupby("choice", sort=False)}
    for label, folder in sm.params.comparisons.items():
        by_choice[label] = claims.evaluate_dataset(folder, sm.params.window, compared)
    primary = by_choice["primary"]
    statistics = pd.read_csv(sm.input.statistics)
    decided = claims.claim_table(primary, level, compared.labels)
    table = verdicts.verdict_table(fits, decided, compared)
    table.to_csv(sm.output.verdicts, index=False)
    per_angle = claims.per_angle_table(primary, statistics[statistics["choice"] == "primary"], level)
    per_angle.to_csv(sm.output.per_angle, index=False)
    edges = claims.range_edge_table(primary, level)
    edges.to_csv(sm.output.edges, index=False)
    choices = claims.choices_table(by_choice, level, compared.labels)
    choices.to_csv(sm.output.choices, index=False)
    details = verdicts.descriptive_tables(
        fits, pd.read_csv(sm.input.runs), pd.read_csv(sm.input.predictions), compared, level
    )
    for key in ("recovery", "rms", "overshoot"):
        details[key].to_csv(sm.output[key], index=False)
    write_verdicts_page(table, per_angle, edges, choices, details["recovery"], compared.labels, sm.output.page)
    print(table[["claim", "mean", "low", "high", "verdict"]].to_string(index=False))
    print(choices.pivot(index="claim", columns="choice", values="verdict").to_string())
