"""Snakemake: every seed's claim statistics under every choice (rule claims)."""

import pandas as pd

from suspension_fabric.evaluation import claims
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    results = claims.evaluate_study(
        pd.read_csv(sm.input.startup),
        pd.read_csv(sm.input.rotation),
        phi=sm.params.phi,
        steady_window=sm.params.steady_window,
        startup_strain=sm.params.startup_strain,
        rotation_strain=sm.params.rotation_strain,
        window=sm.params.window,
        compared=claims.Compared.from_specs(sm.params.compared),
    )
    for key in ("statistics", "values", "fits"):
        results[key].to_csv(sm.output[key], index=False)
    print(results["fits"].to_string(index=False))
