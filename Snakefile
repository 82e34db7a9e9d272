# Shear-rotation fabric study: LAMMPS simulations -> MDAnalysis fabric -> G-W models -> figures.
# Default study: config/config.yaml; pick another with --configfile config/<name>.yaml. A config
# with a `campaign` section runs one study per state point and maps them (config/campaign.yaml).
# Another workflow may import this one as a module with its own config (docs/workflow.md, "Using
# the workflow as a module"; tests/workflow/test_module.py).
from snakemake.utils import min_version

# 9.11 is the first Snakemake whose script file times rerun nothing when the rerun triggers leave out
# "code" (profiles/default; snakemake PR #3707): before it, a re-cloned checkout reran every job. The
# test study, run directly and as a module, was checked with 9.11.0 and with the locked 9.27.1
# (envs/requirements.lock.txt).
min_version("9.11")

import copy
from pathlib import Path

from suspension_fabric.study.config import (
    ConfigError,
    ConfigSources,
    read_config_sources,
    shipped_paths,
    validate_config,
)


DEFAULT_CONFIGFILE = "config/config.yaml"
# This file, and whether it runs as another workflow's module: then its working directory, its
# --configfile and --config are the importer's, and its config is the one the `module` statement
# passes (workflow.basedir is the importing Snakefile's folder then, not this checkout).
SNAKEFILE = Path(workflow.snakefile).resolve()
IMPORTED = SNAKEFILE != Path(workflow.main_snakefile).resolve()

if IMPORTED:
    # No YAML file to read again: the importer's files and --config made this dict (and Snakemake
    # skips the `configfile:` below). Validate a copy, so that the defaults filled in stay here.
    if not isinstance(config, dict) or not config:
        raise ConfigError(
            "the module's config: this workflow imported as a module needs its study's config as "
            "`config:` of the `module` statement (docs/workflow.md, \"Using the workflow as a module\")"
        )
    config = copy.deepcopy(config)
    # relative paths are the importer's (its working directory); a dataset or model file that is
    # not there but in this checkout (data/...) is taken from the checkout
    shipped_paths(config, SNAKEFILE.parent)
    CONFIG_SOURCES = ConfigSources([("the module's config", copy.deepcopy(config))])
else:
    # Snakemake keeps the last of a key repeated in a config file or --config without a word, and
    # names no file or line for a YAML error: read the sources again strictly, the default study
    # before Snakemake does (a --configfile Snakemake cannot parse stops it before this Snakefile runs).
    try:
        CONFIG_SOURCES = read_config_sources(
            workflow.overwrite_configfiles or [DEFAULT_CONFIGFILE], workflow.config_settings.config_args
        )
    except ConfigError as err:
        if Path.cwd().resolve() != SNAKEFILE.parent:  # -s path/to/Snakefile from another folder
            raise ConfigError(
                f"{err}; this workflow's config, data and results are relative to its own folder "
                f"{SNAKEFILE.parent}: run it from there, or add --directory {SNAKEFILE.parent}"
            ) from None
        raise


# Without --configfile the default study, with any --config overrides on top of it; a study
# given by --configfile is never merged with the default one (absent keys take the schema's
# defaults), and --config overrides it in turn.
if not IMPORTED and not workflow.overwrite_configfiles:

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
