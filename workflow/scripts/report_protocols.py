"""Snakemake: the protocols' results as a Markdown fragment (rule report_protocols)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.stress_relations import resolve_relations
from suspension_fabric.reporting.protocol_report import summary_markdown
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    text = summary_markdown(
        pd.read_csv(sm.input.leaderboard),
        pd.read_csv(sm.input.stress_leaderboard),
        pd.concat([pd.read_csv(sm.input.states), pd.read_csv(sm.input.stress_states)], ignore_index=True),
        sm.params.level,
        reference=sm.params.reference,
        reference_relation=next(iter(resolve_relations(sm.params.relations))),
    )
    Path(sm.output[0]).write_text(text)
    print(text)
