"""Snakemake: one segment of a flow history for one seed (rule shear_segment)."""

from pathlib import Path

from suspension_fabric.io.protocols import Segment
from suspension_fabric.simulation.lammps import RUN_FILES, ForceModel, ShearSettings, run_segment
from suspension_fabric.simulation.lammps.plugin import install_plugin
from suspension_fabric.simulation.lammps.rundir import COMPLETION_MARKER, restore_marker
from suspension_fabric.workflow_io import job_study_config, logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    run_dir = Path(sm.output.trajectory).parent
    # what this job asks for, recorded with the run: a rerun asking for the same finished run keeps it
    asked = {"workflow_params": {key: getattr(sm.params, key) for key in ("settings", "segment", "plugin", "code")}}
    data_files = [name for name in RUN_FILES.values() if name != COMPLETION_MARKER]
    if restore_marker(run_dir, asked, data_files):
        print(f"{run_dir} already holds the finished run these settings ask for: kept, nothing simulated")
    else:
        study = job_study_config(sm)
        history = tuple(Segment(**fields) for fields in sm.params.segment["history"])
        install_plugin(sm.params.plugin["library"])  # built if missing or stale
        source = {"data_file": sm.input.data} if "data" in sm.input.keys() else {"restart_file": sm.input.checkpoint}
        result = run_segment(
            run_dir,
            history[-1],
            **source,
            index=sm.params.segment["index"],
            history=history,
            force_model=ForceModel.from_config(study, plugin=sm.params.plugin["library"]),
            settings=ShearSettings.from_config(study),
            overwrite=True,  # Snakemake decided this job must run; the old folder goes only on success
            record=asked,
        )
        print(
            f"reached strain {result.strain} (steps {result.first_step}-{result.last_step}) in "
            f"{result.segments} launch(es), largest overlap {result.max_overlap:.3g} d, {result.wall_time:.1f} s"
        )
