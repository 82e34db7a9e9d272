"""Snakemake: a campaign's transfer model on each of the study's own protocols against G-W (rule
transfer_protocols)."""

import pandas as pd

from suspension_fabric.analysis.protocol_tables import read_protocol_table
from suspension_fabric.evaluation import model_transfer, protocol_benchmark
from suspension_fabric.io.fit_provenance import check_provenance
from suspension_fabric.io.protocols import protocols_from_params
from suspension_fabric.io.table_provenance import checked_tables
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]), checked_tables(sm):
    fit, source = model_transfer.read_transfer_file(sm.input.model)
    fitted = pd.read_csv(sm.input.model_parameters)
    check_provenance(fitted, sm.input.model_parameters)
    gw = fitted[(fitted["model"] == "gw") & (fitted["mode"] == "steady") & (fitted["parameter"] == "beta")]
    if len(gw) != 1:
        raise ValueError(f"{sm.input.model_parameters}: expected one steady G-W beta, found {len(gw)} rows")
    steady = pd.read_csv(sm.input.steady)
    n12_ss = float(steady.loc[steady["quantity"] == "n12", "mean"].iloc[0])
    runs = read_protocol_table(sm.input.protocol_runs)
    protocols = protocols_from_params(sm.params.protocols)
    curves = {name: protocol_benchmark.protocol_curves(p, runs) for name, p in protocols.items()}
    map_beta = model_transfer.transferred_beta(
        [(p["phi"], p["mu"], p["gw_beta"]) for p in source["points"]], sm.params.phi, sm.params.mu
    )
    table = model_transfer.protocol_table(
        fit, sm.params.phi, sm.params.mu, curves, float(gw["value"].iloc[0]), map_beta, n12_ss, sm.params.level
    )
    table.to_csv(sm.output.table, index=False)
    with open(sm.output.summary, "w") as out:
        out.write(model_transfer.protocols_markdown(table, source))
    print(table.to_string(index=False))
