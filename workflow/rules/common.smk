# Shared names: the studies of this config, their output roots, and the lists the aggregate rules expand.
# One config is one study, or a campaign of studies (one per state point, suspension_fabric.study.campaign):
# every rule carries the {study} wildcard and reads its settings from STUDIES[study].
import re
from pathlib import Path

from suspension_fabric.code_version import CodeVersions
from suspension_fabric.study.campaign import is_flow_curve_campaign, study_configs
from suspension_fabric.study.config import (
    angle_label,
    check_complete_study,
    simulation_settings,
    study_protocols,
    study_run_tree,
)
from suspension_fabric.io.protocols import protocol_runs
from suspension_fabric.models.fabric_models import load_model
from suspension_fabric.simulation.lammps import PACK_FILES, RUN_FILES
from suspension_fabric.simulation.lammps.plugin import plugin_version
from suspension_fabric.io.resources import PLUGIN_LIBRARY_NAME

STUDIES = study_configs(config, CONFIG_SOURCES)
RESULTS = "results/{study}"
# The plugin is no rule's output: a segment builds it if missing or stale (once, under a lock) and
# is rerun for its version (a params value), a hash of its sources' contents and the compile flags,
# never their paths or file times. A moved or re-cloned checkout, even without build/, reruns nothing.
PLUGIN = {"library": f"build/plugin/{PLUGIN_LIBRARY_NAME}", "version": plugin_version()}
FIGURE_NAMES = ["fig1_startup", "fig2_rotation"]
STRESS_FIGURE_NAMES = ["fig3_stress", "fig4_stress_rotation"]
# The config keys that change a simulation's outputs (others, like the failure bounds, the
# restart interval or the MPI rank count, never rerun a finished simulation).
SIMULATION_SETTINGS = {name: simulation_settings(study) for name, study in STUDIES.items()}
SIMULATED_STUDIES = [name for name, study in STUDIES.items() if not study["dataset"]]
# The flow histories of each study (the paper's family and the config's protocols) and their
# runs, a tree: each run continues from its parent's checkpoint (suspension_fabric.io.protocols).
PROTOCOLS = {name: study_protocols(study) for name, study in STUDIES.items()}
RUN_TREES = {name: study_run_tree(study) for name, study in STUDIES.items()}
ALL_RUNS = sorted({run for tree in RUN_TREES.values() for run in tree})
DATASET_STUDIES = [name for name, study in STUDIES.items() if study["dataset"]]


# Every rule's `code` param: a hash of its script and of the package code and data it runs
# (suspension_fabric.code_version), so that editing that code reruns the rule's jobs and nothing
# else. Contents only, so a moved or re-cloned checkout reruns nothing; computed once per run and
# cached in the run's .snakemake folder (in its working directory: the importer's for a module).
_CODE_VERSIONS = CodeVersions(cache=".snakemake/code_versions.json")
# This file's folder, the checkout's workflow/rules, to which the `script:` paths are relative
# (workflow.basedir is the main Snakefile's folder: the importer's when this workflow is a module).
_RULES_DIR = Path(workflow.snakefile).parent
# The simulations' post-run overlap check searches neighbours with the fabric analysis: it accepts
# or refuses a finished run, never changes one, so editing the analysis reruns no simulation.
SIMULATION_CHECKS = ["suspension_fabric.analysis.fabric", "suspension_fabric.analysis.fabric_reference"]


def code_version(script, ignore=()):
    """A params value: the code version of a rule's script, given as in its `script:` line."""
    return _CODE_VERSIONS.version(_RULES_DIR / script, ignore)


def study_pattern(names):
    return "|".join(re.escape(name) for name in names)


wildcard_constraints:
    study=study_pattern(STUDIES),
    seed=r"\d+",
    angle=r"m?[0-9.]+(e[-+]?\d+)?",
    run=study_pattern(ALL_RUNS),
    protocol=r"[A-Za-z][A-Za-z0-9_]*",


def setting(*keys):
    """A params function: the value at keys (e.g. "run", "startup_strain") of the job's study."""

    def value(wildcards):
        found = STUDIES[wildcards.study]
        for key in keys:
            found = found[key]
        return found

    return value


def plugin_files(kind):
    """An input function: the files of the study's user-defined plug-ins of models.<kind> (entries
    'file.py:NAME' and model files 'model.json'), so that editing one reruns what depends on it."""

    def files(wildcards):
        specs = STUDIES[wildcards.study]["models"][kind]
        files = [spec.rpartition(":")[0] for spec in specs if spec.rpartition(":")[0].endswith(".py")]
        return files + [spec for spec in specs if spec.endswith(".json")]

    return files


def compared_models(wildcards):
    """A params function: {role: config entry} of the two models the claims compare (verdicts.models
    names them by key among models.fabric), so that changing the other models reruns no claim."""
    study = STUDIES[wildcards.study]
    by_key = {load_model(spec).key: spec for spec in study["models"]["fabric"]}
    return {role: by_key[key] for role, key in study["verdicts"]["models"].items()}


def compared_model_files(wildcards):
    """An input function: the files of the compared models that are user plug-ins or model files."""
    specs = list(compared_models(wildcards).values())
    locations = [spec.rpartition(":")[0] for spec in specs]
    return [location for location in locations if location.endswith(".py")] + [s for s in specs if s.endswith(".json")]


def seed_runs(path):
    """An input function: path (with {seed} and, for rotations, {angle}) for every seed and angle of the study."""

    def files(wildcards):
        study = STUDIES[wildcards.study]
        angles = [angle_label(a) for a in study["angles_deg"]]
        return expand(path, study=wildcards.study, seed=study["seeds"], angle=angles)

    return files


def angle_value(wildcards):
    study = STUDIES[wildcards.study]
    return {angle_label(a): a for a in study["angles_deg"]}[wildcards.angle]


def study_targets(study):
    """Every figure and table of one study (the stress ones when its runs recorded the stress)."""
    targets = [
        *rules.figure_startup.output,
        *rules.figure_rotation.output,
        *rules.fit_models.output,
        rules.model_errors.output.table,
        *rules.benchmark_models.output,
        *rules.closure_tests.output,
        *rules.discover_model.output,
        *rules.nested_selection.output,
        *rules.report_tables.output,
        *rules.verdicts.output,
        *rules.figure_claims.output,
    ]
    if study not in STRESSLESS_STUDIES:
        targets += [
            *rules.figure_stress_startup.output,
            *rules.figure_stress_rotation.output,
            *rules.stress_relation.output,
            *rules.benchmark_stress_relations.output,
            *rules.report_stress.output,
            *rules.error_decomposition.output,
        ]
        targets += rules.summary_fragments.output
        if STUDIES[study]["verdicts"]["comparisons"]:
            targets += rules.compare_datasets.output
    if STUDIES[study]["protocols"]:
        targets += [*rules.aggregate_protocols.output]
        if study not in STRESSLESS_STUDIES:
            targets += [*rules.aggregate_stress_protocols.output, *rules.benchmark_protocols.output]
            targets += rules.report_protocols.output
            if STUDIES[study]["models"]["transfer"]:
                targets += rules.transfer_protocols.output
            targets += expand(rules.figure_protocol.output, protocol=list(STUDIES[study]["protocols"]), allow_missing=True)
    if not STUDIES[study]["dataset"]:
        # every run's record a target too: Snakemake deletes it when the run's rerun starts, and plans
        # a job for a missing target, not for a missing file under outputs that are up to date
        targets += expand(rules.pack.output.report, seed=STUDIES[study]["seeds"], allow_missing=True)
        targets += expand(
            rules.shear_segment.output.run_complete, seed=STUDIES[study]["seeds"], run=list(RUN_TREES[study]), allow_missing=True
        )
    return expand(targets, study=study)


def all_targets(wildcards):
    """The input function of the default target, every output of every study. What only the full set
    needs (two seeds, two angles) is checked here, still before any job, so one seed runs single targets."""
    if is_flow_curve_campaign(config):
        return CAMPAIGN_TARGETS  # flow curves: each point a steady state, not a rotation study
    for study in STUDIES.values():
        check_complete_study(study, CONFIG_SOURCES)
    targets = [path for name in STUDIES for path in study_targets(name)]
    return targets + (CAMPAIGN_TARGETS if config["campaign"] else [])


def per_point(path):
    """Path (a study output with {study}) for every study of the config: a campaign's points."""
    return [path.format(study=study) for study in STUDIES]


def run_outputs(run_dir, files=RUN_FILES):
    """A simulation's output files. The data are flagged `update`: Snakemake leaves them in place
    while their rerun goes (it deletes a job's outputs when the job starts), and the runner replaces
    the folder only when the new run has finished, so an interrupted or failed rerun loses nothing.
    The completion marker is not: Snakemake deletes it, so a run whose rerun did not finish is
    planned again, whatever Snakemake recorded for the failed job; a rerun that asks for exactly the
    finished run puts the marker back from its kept copy instead of simulating (workflow/scripts/shear.py).
    A packing's report plays the marker's part for its data."""
    return {
        role: f"{run_dir}/{name}" if role in RUN_RECORDS else update(f"{run_dir}/{name}")
        for role, name in files.items()
    }


RUN_RECORDS = {"run_complete", "report"}  # the roles of RUN_FILES and PACK_FILES that say a run finished


# For conda users only (--sdm conda); the tested installation is pip (envs/bootstrap.sh).
CONDA_ENV = "../../envs/environment.yml"


def own_protocols(study):
    """The study's protocols beyond the paper's family (config key `protocols`)."""
    return {name: PROTOCOLS[study][name] for name in STUDIES[study]["protocols"]}


def protocol_segments(wildcards):
    """A params function: the study's own protocols as {name: [segment fields, ...]}
    (suspension_fabric.io.protocols.protocols_from_params reads them back)."""
    return {name: [s.as_dict() for s in p.segments] for name, p in own_protocols(wildcards.study).items()}


def protocol_run_names(study):
    """{protocol: the names of its runs, one per segment} for the study's own protocols."""
    tree = RUN_TREES[study]
    return {name: list(protocol_runs(p, tree)) for name, p in own_protocols(study).items()}


def protocol_run_files(filename):
    """An input function: ``filename`` of every run of every own protocol of the study, per seed."""

    def files(wildcards):
        runs = sorted({run for names in protocol_run_names(wildcards.study).values() for run in names})
        return expand(f"results/{{study}}/seed{{seed}}/{{run}}/{filename}", study=wildcards.study,
                      seed=STUDIES[wildcards.study]["seeds"], run=runs)

    return files


def segment_source(wildcards):
    """The run's start: the seed's packing for a first segment, else the checkpoint (and completion
    marker) of its parent run, the segment before it in the flow history."""
    node = RUN_TREES[wildcards.study][wildcards.run]
    if node.parent is None:
        return {"data": rules.pack.output.data.format(study=wildcards.study, seed=wildcards.seed)}
    parent = f"results/{wildcards.study}/seed{wildcards.seed}/{node.parent}"
    return {"checkpoint": f"{parent}/checkpoint.rst", "marker": f"{parent}/run_complete.json"}


def segment_of(wildcards):
    """The run's segment, its index and flow history (suspension_fabric.io.protocols.RunNode)."""
    node = RUN_TREES[wildcards.study][wildcards.run]
    return {"index": node.index, "history": [segment.as_dict() for segment in node.history]}


def frictionless_datasets(wildcards):
    """An input function: the record of each dataset at mu = 0 in campaign.frictionless_datasets (the
    f = 0 points of the Wyart-Cates fit), none without that key."""
    folder = (config["campaign"] or {}).get("frictionless_datasets")
    return sorted(str(p) for p in Path(folder).glob("*_mu0/dataset.json")) if folder else []


def point_label(study):
    """How a flow curve's point is named in tables and legends: phi and the imposed rate or stress."""
    forces, phi = STUDIES[study]["forces"], STUDIES[study]["particles"]["phi"]
    if forces["critical_load_stress"] is not None:
        return f"φ {phi:g}, σ/σ₀ {forces['critical_load_stress']:g}"
    if forces["critical_load_rate"] is not None:
        return f"φ {phi:g}, γ̇/γ̇₀ {forces['critical_load_rate']:g}"
    return f"φ {phi:g}, μ {forces['mu']:g}"
