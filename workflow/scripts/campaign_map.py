"""Snakemake: the map table over a campaign's state points, its report page and its Markdown summary
(rule campaign_map)."""

import pandas as pd

from suspension_fabric.evaluation import state_map
from suspension_fabric.evaluation.claims import ROLES
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.models.fits_file import read_fits
from suspension_fabric.reporting.map_fragments import map_summary
from suspension_fabric.reporting.map_page import write_map_page
from suspension_fabric.study.campaign import study_configs
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    studies = study_configs(sm.config)
    rows = []
    for k, (point, study) in enumerate(sm.params.points.items()):
        rows.append(
            state_map.point_row(
                point,
                studies[study],
                pd.read_csv(sm.input.steady[k]),
                pd.read_csv(sm.input.stress_steady[k]),
                read_fits(sm.input.fits[k]),
                pd.read_csv(sm.input.verdicts[k]),
                pd.read_csv(sm.input.startup_runs[k]),
                pd.read_csv(sm.input.stress_runs[k]),
                sm.params.level,
            )
        )
    table = state_map.map_table(rows, sm.params.not_run, sm.params.level)
    table.to_csv(sm.output.table, index=False)
    write_map_page(table, sm.output.page)
    with open(sm.output.summary, "w") as out:
        out.write(map_summary(table, sm.params.level))
    fitted = [column for column in table.columns if column.endswith("_err") and column.split("_")[0] in ROLES]
    print(table[["point", "steady", "n12", "Z", "eta_r", "Pi", *(c[: -len("_err")] for c in fitted)]].to_string())
