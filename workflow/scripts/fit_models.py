"""Snakemake: fit G-W and the modified model to the simulated steady state (rule fit_models)."""
import pandas as pd

from suspension_fabric import model_vs_simulation
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    fits = model_vs_simulation.fit_steady_state(pd.read_csv(sm.input.steady), sm.params.phi)
    fits["provenance"] = {"study": sm.config["study"], "seeds": sm.config["seeds"],
                          "N": sm.config["particles"]["n"], "steady_state_table": sm.input.steady}
    model_vs_simulation.write_fits(fits, sm.output[0])
    print(f"G-W beta = {fits['gw']['beta']:.4g}; modified beta = {fits['modified']['beta']:.4g}, "
          f"A = {fits['modified']['A']:.4g}")
