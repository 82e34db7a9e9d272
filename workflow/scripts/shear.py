"""Snakemake: startup shear or shear rotation of one seed (rules startup and rotate; params.kind)."""

from pathlib import Path

from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, run_rotation, run_startup
from suspension_fabric.workflow_io import job_study_config, logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    study = job_study_config(sm)
    common = dict(
        strain_total=sm.params.strain,
        force_model=ForceModel.from_config(study, plugin=sm.input.plugin),
        settings=ShearSettings.from_config(study),
        overwrite=True,  # Snakemake decided this job must run; the old folder goes only on success
    )
    output_dir = Path(sm.output.trajectory).parent
    if sm.params.kind == "rotation":
        result = run_rotation(output_dir, sm.input.checkpoint, sm.params.theta_deg, **common)
    elif sm.params.kind == "startup":
        result = run_startup(output_dir, sm.input.data, **common)
    else:
        raise ValueError(f"params.kind must be 'startup' or 'rotation', got {sm.params.kind!r}")
    print(
        f"reached strain {result.strain} (steps {result.first_step}-{result.last_step}) in "
        f"{result.segments} segment(s), largest overlap {result.max_overlap:.3g} d, {result.wall_time:.1f} s"
    )
