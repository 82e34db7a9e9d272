# Shear-rotation fabric study: LAMMPS simulations -> MDAnalysis fabric -> G-W models -> figures.
# Default study: config/config.yaml; pick another with --configfile config/<name>.yaml. A config
# with a `campaign` section runs one study per state point and maps them (config/campaign.yaml).
from suspension_fabric.study.config import read_config_sources, validate_config


DEFAULT_CONFIGFILE = "config/config.yaml"
# Snakemake keeps the last of a key repeated in a config file or --config without a word, and names
# no file or line for a YAML error: read the sources again strictly, the default study before
# Snakemake does (a --configfile Snakemake cannot parse stops it before this Snakefile runs).
CONFIG_SOURCES = read_config_sources(
    workflow.overwrite_configfiles or [DEFAULT_CONFIGFILE], workflow.config_settings.config_args
)


# Without --configfile the default study, with any --config overrides on top of it; a study
# given by --configfile is never merged with the default one (absent keys take the schema's
# defaults), and --config overrides it in turn.
if not workflow.overwrite_configfiles:

    configfile: DEFAULT_CONFIGFILE


# schema + cross-key checks, before any job; fills defaults; errors name the file that set the key
validate_config(config, sources=CONFIG_SOURCES)


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"


STRESSLESS_STUDIES = []  # studies on datasets exported before the stress parts were recorded
if DATASET_STUDIES:  # fabric tables from reference datasets: no simulation for these studies

    include: "workflow/rules/dataset.smk"


if SIMULATED_STUDIES:

    include: "workflow/rules/simulate.smk"
    include: "workflow/rules/fabric.smk"


include: "workflow/rules/analyse.smk"
include: "workflow/rules/model.smk"
include: "workflow/rules/claims.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/report.smk"


if config["campaign"]:

    include: "workflow/rules/campaign.smk"


rule all:
    default_target: True
    input:
        all_targets,
