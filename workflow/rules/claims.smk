# The paper's claims decided per seed (docs/verdict_statistics.md): rule claims computes every
# seed's statistics under every choice; rule verdicts decides, adds the comparison datasets and
# writes the tables and the report page.
import os

from suspension_fabric.study.config import ConfigError, check_comparison
from suspension_fabric.study.dataset import read_dataset, run_names

COMPARISON_FILES = {}  # per study: every fabric table of the datasets it is compared with
for _study, _config in STUDIES.items():
    if _config["verdicts"]["comparisons"]:
        # imported here: the claims module costs half a second of scipy on every workflow load
        from suspension_fabric.evaluation.claims import study_choices

        # the labels share the tables' columns with the study and its verdict choices
        _choices = study_choices(_config["verdicts"]["window"], _config["run"]["rotation_strain"])
        _taken = [_study, *(choice.name for choice in _choices)]
    for _label, _folder in _config["verdicts"]["comparisons"].items():  # named early: stops before any job
        if not os.path.isfile(os.path.join(_folder, "dataset.json")):
            raise CONFIG_SOURCES.locate(ConfigError(
                f"config key 'verdicts.comparisons': '{_label}' names {_folder}, which holds no "
                "dataset.json (a reference dataset folder, suspension_fabric.study.dataset)"))
        try:
            check_comparison(_config, _label, read_dataset(_folder)["config"], taken=_taken,
                             stress=_study not in STRESSLESS_STUDIES)
        except ConfigError as _error:
            raise CONFIG_SOURCES.locate(_error) from None
    COMPARISON_FILES[_study] = [
        f"{folder}/{name}/fabric.csv"
        for folder in _config["verdicts"]["comparisons"].values()
        for name in run_names(read_dataset(folder)["config"])
    ]


rule claims:
    """Per seed: own steady state, fits and predictions under each choice; the claims' statistics per angle."""
    input:
        startup=rules.aggregate_startup.output.runs,
        rotation=rules.aggregate_rotation.output.runs,
        model_files=compared_model_files,
    output:
        statistics=f"{RESULTS}/tables/claims_statistics.csv",
        values=f"{RESULTS}/tables/claims_values.csv",
        fits=f"{RESULTS}/tables/claims_seed_fits.csv",
    params:
        phi=setting("particles", "phi"),
        steady_window=setting("analysis", "steady_window"),
        startup_strain=setting("run", "startup_strain"),
        rotation_strain=setting("run", "rotation_strain"),
        window=setting("verdicts", "window"),
        compared=compared_models,
        code=code_version("../scripts/claims.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/claims.log",
    script:
        "../scripts/claims.py"


rule verdicts:
    """Each claim decided on a t-interval over seeds; per angle, range edges, the choices table; description."""
    input:
        fits=rules.fit_models.output[0],
        runs=rules.aggregate_rotation.output.runs,
        predictions=rules.predict.output[0],
        statistics=rules.claims.output.statistics,
        values=rules.claims.output.values,
        comparisons=lambda wildcards: COMPARISON_FILES[wildcards.study],
        model_files=compared_model_files,
    output:
        verdicts=f"{RESULTS}/tables/verdicts.csv",
        per_angle=f"{RESULTS}/tables/claims_per_angle.csv",
        edges=f"{RESULTS}/tables/claims_range_edges.csv",
        choices=f"{RESULTS}/tables/verdict_choices.csv",
        recovery=f"{RESULTS}/tables/recovery_table.csv",
        rms=f"{RESULTS}/tables/rotation_rms_errors.csv",
        overshoot=f"{RESULTS}/tables/overshoot_table.csv",
        page=report(f"{RESULTS}/tables/verdicts.html", caption="../report/table_verdicts.rst", category="Tables"),
    params:
        comparisons=setting("verdicts", "comparisons"),
        level=setting("verdicts", "level"),
        window=setting("verdicts", "window"),
        compared=compared_models,
        code=code_version("../scripts/verdicts.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/verdicts.log",
    script:
        "../scripts/verdicts.py"


rule figure_claims:
    """Fig. 5: D12, E23, the paired MSE difference and X12 per angle, simulation (t-interval) and models."""
    input:
        statistics=rules.claims.output.statistics,
    output:
        pdf=f"{RESULTS}/figures/fig5_claims.pdf",
        png=report(f"{RESULTS}/figures/fig5_claims.png", caption="../report/fig5.rst", category="Figures"),
    params:
        level=setting("verdicts", "level"),
        code=code_version("../scripts/figure_claims.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_claims.log",
    script:
        "../scripts/figure_claims.py"


rule compare_datasets:
    """The study against its comparison datasets: steady quantities and viscosity deficits per seed, t- and Welch intervals."""
    input:
        startup=rules.aggregate_startup.output.runs,
        stress_startup=rules.aggregate_stress_startup.output.runs,
        stress_rotation=rules.aggregate_stress_rotation.output.runs,
        comparisons=lambda wildcards: COMPARISON_FILES[wildcards.study],
        model_files=compared_model_files,
    output:
        f"{RESULTS}/tables/dataset_comparison.csv",
    params:
        comparisons=setting("verdicts", "comparisons"),
        n=setting("particles", "n"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/compare_datasets.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/compare_datasets.log",
    script:
        "../scripts/compare_datasets.py"


rule summary_fragments:
    """The results the docs and the README quote, as Markdown: the fits and steady state, the
    verdicts under each analysis choice and on each comparison dataset, the headline
    (suspension_fabric.reporting.summary_fragments); the leaderboards of fabric models and stress
    relations (reporting.leaderboard_fragments); per rotation angle the peak of <nn>'_12 and the
    viscosity's dip (reporting.rotation_fragments)."""
    input:
        fits=rules.fit_models.output[0],
        steady=rules.aggregate_startup.output.steady,
        stress_steady=rules.aggregate_stress_startup.output.steady,
        verdicts=rules.verdicts.output.verdicts,
        choices=rules.verdicts.output.choices,
        stress_board=rules.benchmark_stress_relations.output.leaderboard,
        stress_parameters=rules.benchmark_stress_relations.output.parameters,
        leaderboard=rules.benchmark_models.output.leaderboard,
        parameters=rules.benchmark_models.output.parameters,
        predictions=rules.predict.output[0],
        rotation=rules.aggregate_rotation.output.aggregate,
        viscosity=rules.stress_relation.output.transients,
    output:
        fits=f"{RESULTS}/tables/fits_summary.md",
        choices=f"{RESULTS}/tables/verdict_choices.md",
        headline=f"{RESULTS}/tables/headline.md",
        verdicts=f"{RESULTS}/tables/verdict_table.md",
        parameters=f"{RESULTS}/tables/model_parameters.md",
        leaderboard=f"{RESULTS}/tables/leaderboard.md",
        stress_board=f"{RESULTS}/tables/stress_leaderboard.md",
        peaks=f"{RESULTS}/tables/rotation_peaks.md",
        viscosity=f"{RESULTS}/tables/viscosity_transients.md",
    params:
        label=lambda wildcards: (
            f"{wildcards.study}: N = {STUDIES[wildcards.study]['particles']['n']}, "
            f"{len(STUDIES[wildcards.study]['seeds'])} seeds"
        ),
        datasets=lambda wildcards: list(STUDIES[wildcards.study]["verdicts"]["comparisons"]),
        window=setting("verdicts", "window"),
        code=code_version("../scripts/summary_fragments.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/summary_fragments.log",
    script:
        "../scripts/summary_fragments.py"
