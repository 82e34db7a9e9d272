# Shared names: output root, run directories, and the lists the aggregate rules expand.
import glob

from suspension_fabric.config import angle_label

RESULTS = f"results/{config['study']}"
SEEDS = config["seeds"]
ANGLES = [angle_label(a) for a in config["angles_deg"]]
ANGLE_VALUE = dict(zip(ANGLES, config["angles_deg"]))
PLUGIN_LIBRARY = "build/plugin/libsuspension_fabric_lammps.so"
FIGURES = expand(f"{RESULTS}/figures/{{name}}.{{ext}}", name=["fig1_startup", "fig2_rotation"], ext=["pdf", "png"])
RUN_FILES = ["trajectory.dump", "stress.txt", "checkpoint.rst", "run_complete.json"]


wildcard_constraints:
    seed=r"\d+",
    angle=r"m?[0-9.]+(e[-+]?\d+)?",


# Run settings that change results; the failure bounds, the kn check and the MPI rank count do not,
# so changing them never reruns a finished simulation (the scripts read them from config).
RUN_CHECKS = ("max_overlap", "max_stress_jitter", "max_contact_relaxation_strain", "mpi_ranks")
RUN_SETTINGS = {key: value for key, value in config["run"].items() if key not in RUN_CHECKS}


def run_outputs(run_dir):
    return {name.split(".")[0]: f"{run_dir}/{name}" for name in RUN_FILES}


PLUGIN_SOURCES = sorted(glob.glob("workflow/plugin/*.cpp") + glob.glob("workflow/plugin/*.h"))
# For conda users only (--sdm conda); the tested installation is pip (envs/bootstrap.sh).
CONDA_ENV = "../../envs/environment.yml"
