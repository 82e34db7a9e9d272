"""Snakemake: near-contact fabric table of one run (rule fabric_table)."""
import json

from suspension_fabric import tables
from suspension_fabric.fabric import FabricAnalysis
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    marker = json.loads(open(sm.input.marker).read())
    variables = marker["variables"]
    analysis = FabricAnalysis.from_dump(
        sm.input.dump, dt=float(variables["dt"]), shear_rate=float(variables["rate"]),
        shear_start_step=int(marker["results"]["first_step"]),
        flow_angle_deg=float(variables.get("theta_deg", 0.0)), eps=sm.params.eps,
    ).run()
    table = tables.fabric_table(analysis, seed=int(sm.wildcards.seed))
    tables.write_fabric_table(table, sm.output[0])
    print(f"{len(table)} frames, mean Z = {table['Z'].mean():.3f}, measured phi = {table['phi'].iloc[0]:.4f}")
