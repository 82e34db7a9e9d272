"""Snakemake: the Markdown fragments the docs and the README quote (rule summary_fragments)."""

import json
from pathlib import Path

import pandas as pd

from suspension_fabric.reporting.summary_fragments import choices_table, fits_paragraph, headline_paragraph
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = json.loads(Path(sm.input.fits).read_text())
    steady = pd.read_csv(sm.input.steady)
    stress_steady = pd.read_csv(sm.input.stress_steady)
    verdicts = pd.read_csv(sm.input.verdicts)
    choices = pd.read_csv(sm.input.choices)
    stress_board = pd.read_csv(sm.input.stress_board)
    Path(sm.output.fits).write_text(fits_paragraph(fits, steady, stress_steady))
    Path(sm.output.choices).write_text(choices_table(choices))
    Path(sm.output.headline).write_text(headline_paragraph(fits, verdicts, stress_board, sm.params.label))
