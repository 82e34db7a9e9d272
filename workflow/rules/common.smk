# Shared names: output root, run directories, and the lists the aggregate rules expand.
from suspension_fabric.config import angle_label, simulation_settings
from suspension_fabric.lammps import PACK_FILES, RUN_FILES
from suspension_fabric.lammps.plugin import plugin_sources
from suspension_fabric.resources import PLUGIN_LIBRARY_NAME

RESULTS = f"results/{config['study']}"
SEEDS = config["seeds"]
ANGLES = [angle_label(a) for a in config["angles_deg"]]
ANGLE_VALUE = dict(zip(ANGLES, config["angles_deg"]))
PLUGIN_LIBRARY = f"build/plugin/{PLUGIN_LIBRARY_NAME}"
PLUGIN_SOURCES = [str(path) for path in plugin_sources()]
FIGURES = expand(f"{RESULTS}/figures/{{name}}.{{ext}}", name=["fig1_startup", "fig2_rotation"], ext=["pdf", "png"])
STRESS_FIGURES = expand(
    f"{RESULTS}/figures/{{name}}.{{ext}}", name=["fig3_stress", "fig4_stress_rotation"], ext=["pdf", "png"]
)
# The config keys that change a simulation's outputs (others, like the failure bounds, the
# restart interval or the MPI rank count, never rerun a finished simulation).
SIMULATION_SETTINGS = simulation_settings(config)


wildcard_constraints:
    seed=r"\d+",
    angle=r"m?[0-9.]+(e[-+]?\d+)?",


def run_outputs(run_dir, files=RUN_FILES):
    return {role: f"{run_dir}/{name}" for role, name in files.items()}


# For conda users only (--sdm conda); the tested installation is pip (envs/bootstrap.sh).
CONDA_ENV = "../../envs/environment.yml"
