"""Snakemake: random packing for one seed (rule pack)."""

from pathlib import Path

from suspension_fabric.simulation.lammps import pack
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    p = sm.params.particles
    result = pack(
        Path(sm.output.data).parent,
        n_particles=p["n"],
        phi=p["phi"],
        seed=int(sm.wildcards.seed),
        split=p["split"],
        fraction_large=p["fraction_large"],
        d_small=p["d_small"],
        d_large=p["d_large"],
        overwrite=True,  # Snakemake decided this job must run; the old folder goes only on success
    )
    print(
        f"packing: phi = {result.phi}, largest overlap = {result.max_overlap}, "
        f"{result.n_small} small + {result.n_large} large, {result.wall_time:.1f} s"
    )
