"""Snakemake: the map table over a campaign's state points and its report page (rule campaign_map)."""

import json

import pandas as pd

from suspension_fabric.reporting import report_tables, state_map
from suspension_fabric.study.campaign import study_configs
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    studies = study_configs(sm.config)
    rows = []
    for k, (point, study) in enumerate(sm.params.points.items()):
        rows.append(
            state_map.point_row(
                point,
                studies[study],
                pd.read_csv(sm.input.steady[k]),
                pd.read_csv(sm.input.stress_steady[k]),
                json.loads(open(sm.input.fits[k]).read()),
                pd.read_csv(sm.input.verdicts[k]),
                pd.read_csv(sm.input.startup_runs[k]),
                pd.read_csv(sm.input.stress_runs[k]),
                sm.params.level,
            )
        )
    table = state_map.map_table(rows, sm.params.not_run)
    table.to_csv(sm.output.table, index=False)
    report_tables.write_map_page(table, sm.output.page)
    print(table[["point", "steady", "n12", "Z", "eta_r", "Pi", "gw_beta", "modified_beta", "modified_A"]].to_string())
