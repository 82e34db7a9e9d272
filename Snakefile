# Shear-rotation fabric study: LAMMPS simulations -> MDAnalysis fabric -> G-W models -> figures.
# Default study: config/config.yaml; pick another with --configfile config/<name>.yaml.
from suspension_fabric.config import validate_config


# Without --configfile the default study, with any --config overrides on top of it; a study
# given by --configfile is never merged with the default one (absent keys take the schema's
# defaults), and --config overrides it in turn.
if not workflow.overwrite_configfiles:

    configfile: "config/config.yaml"



validate_config(config)  # schema + cross-key checks, before any job; fills defaults


include: "workflow/rules/common.smk"


if config["dataset"]:  # fabric tables from a reference dataset: no simulation

    include: "workflow/rules/dataset.smk"

else:
    STRESS_TABLES = True  # every simulation records the stress parts

    include: "workflow/rules/build.smk"
    include: "workflow/rules/simulate.smk"
    include: "workflow/rules/fabric.smk"


include: "workflow/rules/analyse.smk"
include: "workflow/rules/model.smk"
include: "workflow/rules/claims.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/report.smk"


rule all:
    default_target: True
    input:
        FIGURES,
        f"{RESULTS}/fits.json",
        f"{RESULTS}/tables/model_errors.csv",
        rules.report_tables.output,
        rules.verdicts.output,
        rules.figure_claims.output,
        STRESS_FIGURES if STRESS_TABLES else [],
        rules.stress_relation.output if STRESS_TABLES else [],
        rules.report_stress.output if STRESS_TABLES else [],
