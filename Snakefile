# Shear-rotation fabric study: LAMMPS simulations -> MDAnalysis fabric -> G-W models -> figures.
# Default study: config/config.yaml; pick another with --configfile config/<name>.yaml. A config
# with a `campaign` section runs one study per state point and maps them (config/campaign.yaml).
from suspension_fabric.config import validate_config


# Without --configfile the default study, with any --config overrides on top of it; a study
# given by --configfile is never merged with the default one (absent keys take the schema's
# defaults), and --config overrides it in turn.
if not workflow.overwrite_configfiles:

    configfile: "config/config.yaml"



validate_config(config)  # schema + cross-key checks, before any job; fills defaults


include: "workflow/rules/common.smk"


STRESSLESS_STUDIES = []  # studies on datasets exported before the stress parts were recorded
if DATASET_STUDIES:  # fabric tables from reference datasets: no simulation for these studies

    include: "workflow/rules/dataset.smk"


if SIMULATED_STUDIES:

    include: "workflow/rules/build.smk"
    include: "workflow/rules/simulate.smk"
    include: "workflow/rules/fabric.smk"


include: "workflow/rules/analyse.smk"
include: "workflow/rules/model.smk"
include: "workflow/rules/claims.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/report.smk"


if config["campaign"]:

    include: "workflow/rules/campaign.smk"


def study_targets(study):
    """Every figure and table of one study (the stress ones when its runs recorded the stress)."""
    targets = [
        *rules.figure_startup.output,
        *rules.figure_rotation.output,
        *rules.fit_models.output,
        rules.model_errors.output.table,
        *rules.report_tables.output,
        *rules.verdicts.output,
        *rules.figure_claims.output,
    ]
    if study not in STRESSLESS_STUDIES:
        targets += [
            *rules.figure_stress_startup.output,
            *rules.figure_stress_rotation.output,
            *rules.stress_relation.output,
            *rules.report_stress.output,
        ]
    return expand(targets, study=study)


rule all:
    default_target: True
    input:
        [study_targets(study) for study in STUDIES],
        CAMPAIGN_TARGETS if config["campaign"] else [],
