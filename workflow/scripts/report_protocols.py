"""Snakemake: the protocols' results as a Markdown fragment (rule report_protocols)."""

from pathlib import Path

import pandas as pd

from suspension_fabric.analysis.protocol_tables import read_protocol_table, segment_drift
from suspension_fabric.analysis.seed_statistics import adjusted_p
from suspension_fabric.io.protocols import protocols_from_params
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.stress_relations import resolve_relations
from suspension_fabric.reporting.protocol_report import STATE_QUANTITIES, summary_markdown
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    protocols = protocols_from_params(sm.params.protocols)
    fabric_runs, stress_runs = read_protocol_table(sm.input.runs), read_protocol_table(sm.input.stress_runs)
    drift = pd.concat(
        [
            segment_drift(protocols, runs, [q for q in STATE_QUANTITIES if q in runs], sm.params.level)
            for runs in (fabric_runs, stress_runs)
        ],
        ignore_index=True,
    )  # the quantities the fragment shows, the family of Holm's adjustment
    if not drift.empty:
        drift["slope_p_holm"] = adjusted_p(drift["slope_p"], "holm")
    drift.to_csv(sm.output.drift, index=False)
    text = summary_markdown(
        pd.read_csv(sm.input.leaderboard),
        pd.read_csv(sm.input.stress_leaderboard),
        pd.concat([pd.read_csv(sm.input.states), pd.read_csv(sm.input.stress_states)], ignore_index=True),
        sm.params.level,
        reference=sm.params.reference,
        reference_relation=next(iter(resolve_relations(sm.params.relations))),
        drift=drift,
    )
    Path(sm.output.summary).write_text(text)
    print(text)
