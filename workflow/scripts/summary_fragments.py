"""Snakemake: the Markdown fragments the docs and the README quote (rule summary_fragments)."""

import json
from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.reporting import leaderboard_fragments, rotation_fragments
from suspension_fabric.reporting.summary_fragments import (
    choices_table,
    fits_paragraph,
    headline_paragraph,
    verdict_table,
)
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fits = json.loads(Path(sm.input.fits).read_text())
    steady = pd.read_csv(sm.input.steady)
    stress_steady = pd.read_csv(sm.input.stress_steady)
    verdicts = pd.read_csv(sm.input.verdicts)
    choices = pd.read_csv(sm.input.choices)
    stress_board = pd.read_csv(sm.input.stress_board)
    Path(sm.output.fits).write_text(fits_paragraph(fits, steady, stress_steady))
    Path(sm.output.choices).write_text(choices_table(choices))
    Path(sm.output.headline).write_text(headline_paragraph(fits, verdicts, stress_board, sm.params.label))
    Path(sm.output.verdicts).write_text(verdict_table(choices, sm.params.label, sm.params.datasets))
    Path(sm.output.parameters).write_text(leaderboard_fragments.parameters_table(pd.read_csv(sm.input.parameters)))
    Path(sm.output.leaderboard).write_text(leaderboard_fragments.held_out_table(pd.read_csv(sm.input.leaderboard)))
    Path(sm.output.stress_board).write_text(
        leaderboard_fragments.stress_table(stress_board, pd.read_csv(sm.input.stress_parameters))
    )
    peaks = rotation_fragments.peak_ratios(
        pd.read_csv(sm.input.predictions),
        pd.read_csv(sm.input.rotation),
        fits["targets"]["n12"]["mean"],
        sm.params.window,
    )
    labels = {key: model["label"] for key, model in fits["models"].items()}
    Path(sm.output.peaks).write_text(rotation_fragments.peak_table(peaks, labels))
    Path(sm.output.viscosity).write_text(rotation_fragments.viscosity_table(pd.read_csv(sm.input.viscosity)))
