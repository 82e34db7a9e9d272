"""Snakemake: startup shear or shear rotation of one seed (rules startup and rotate)."""
from pathlib import Path

from suspension_fabric.lammps import ForceModel, run_rotation, run_startup
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    run, checks = sm.params.run, sm.config["run"]
    forces = ForceModel(plugin=sm.input.plugin, integrator=run["integrator"],
                        solver_tol=run["solver_tol"], **sm.params.forces)
    common = dict(
        strain_total=sm.params.strain, force_model=forces, dt=run["dt"], dump_strain=run["dump_strain"],
        table_strain=run["table_strain"], thermo_strain=run["thermo_strain"],
        restart_strain=run["restart_strain"], max_overlap=checks["max_overlap"],
        max_stress_jitter=checks["max_stress_jitter"], ranks=checks["mpi_ranks"],
        overwrite=True,  # Snakemake decided this job must run; the old folder goes only on success
    )
    output_dir = Path(sm.output.trajectory).parent
    if "theta_deg" in sm.params.keys():
        result = run_rotation(output_dir, sm.input.checkpoint, sm.params.theta_deg, **common)
    else:
        result = run_startup(output_dir, sm.input.data, **common)
    print(f"reached strain {result.strain} (steps {result.first_step}-{result.last_step}), "
          f"largest overlap {result.max_overlap:.3g} d, {result.wall_time:.1f} s")
