rule fit_models:
    """Every model of models.fabric fitted to its steady targets (G-W: <nn>_12; modified: <nn>_11 and
    <nn>_12); errors: jackknife over seeds; fits.json in format 2 (suspension_fabric.models.fits_file)."""
    input:
        steady=rules.aggregate_startup.output.steady,
        runs=rules.aggregate_startup.output.runs,
        model_files=plugin_files("fabric"),
    output:
        f"{RESULTS}/fits.json",
    params:
        phi=setting("particles", "phi"),
        steady_window=setting("analysis", "steady_window"),
        models=setting("models", "fabric"),
        code=code_version("../scripts/fit_models.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/fit_models.log",
    script:
        "../scripts/fit_models.py"


rule predict:
    """Every model of models.fabric: startup from the simulated initial fabric, then every rotation angle."""
    input:
        fits=rules.fit_models.output[0],
        startup=rules.aggregate_startup.output.aggregate,
        rotation=rules.aggregate_rotation.output.aggregate,
        model_files=plugin_files("fabric"),
    output:
        f"{RESULTS}/tables/predictions.csv",
    params:
        models=setting("models", "fabric"),
        startup_strain=setting("run", "startup_strain"),
        polar_step=setting("models", "polar_angle_step_deg"),
        code=code_version("../scripts/predict.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/predict.log",
    script:
        "../scripts/predict.py"


rule model_errors:
    """rms and max |model - simulation| / |<nn>_12^ss| per model, angle and component."""
    input:
        fits=rules.fit_models.output[0],
        predictions=rules.predict.output[0],
        startup=rules.aggregate_startup.output.aggregate,
        rotation=rules.aggregate_rotation.output.aggregate,
    output:
        table=f"{RESULTS}/tables/model_errors.csv",
        summary=f"{RESULTS}/tables/model_errors_summary.csv",
    params:
        compared=setting("verdicts", "models"),
        code=code_version("../scripts/model_errors.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/model_errors.log",
    script:
        "../scripts/model_errors.py"


rule stress_relation:
    """G-W stress relation: fit on the steady stress per fabric source, predict startup and rotations, errors;
    the viscosity after a rotation: integrated deficit per seed (own steady eta_r) with its t-interval,
    minimum and recovery strain with seed-bootstrap intervals."""
    input:
        fits=rules.fit_models.output[0],
        predictions=rules.predict.output[0],
        startup=rules.aggregate_startup.output.aggregate,
        rotation=rules.aggregate_rotation.output.aggregate,
        stress_steady=rules.aggregate_stress_startup.output.steady,
        stress_startup=rules.aggregate_stress_startup.output.aggregate,
        stress_rotation=rules.aggregate_stress_rotation.output.aggregate,
        stress_rotation_runs=rules.aggregate_stress_rotation.output.runs,
        stress_startup_runs=rules.aggregate_stress_startup.output.runs,
    output:
        fits=f"{RESULTS}/tables/stress_relation_fits.csv",
        predictions=f"{RESULTS}/tables/stress_predictions.csv",
        errors=f"{RESULTS}/tables/stress_model_errors.csv",
        summary=f"{RESULTS}/tables/stress_model_errors_summary.csv",
        transients=f"{RESULTS}/tables/stress_viscosity_transients.csv",
        deficits=f"{RESULTS}/tables/stress_viscosity_deficit_per_seed.csv",
    params:
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/stress_relation.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/stress_relation.log",
    script:
        "../scripts/stress_relation.py"


rule benchmark_models:
    """Every model of models.fabric scored on held-out rotation angles: steady and global fits, in-sample and
    held-out mean square errors per seed with t-intervals, the paired difference from G-W, AIC; and each
    model against the refined-model targets (held-out error, overshoot, steady state)."""
    input:
        fits=rules.fit_models.output[0],
        startup_runs=rules.aggregate_startup.output.runs,
        rotation_runs=rules.aggregate_rotation.output.runs,
        model_files=plugin_files("fabric"),
    output:
        leaderboard=f"{RESULTS}/tables/leaderboard.csv",
        parameters=f"{RESULTS}/tables/model_parameters.csv",
        page=report(f"{RESULTS}/tables/leaderboard.html", caption="../report/table_leaderboard.rst", category="Tables"),
        targets=f"{RESULTS}/tables/model_targets.csv",
        targets_summary=f"{RESULTS}/tables/model_targets.md",
    params:
        models=setting("models", "fabric"),
        folds=setting("models", "held_out_folds"),
        startup_strain=setting("run", "startup_strain"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        reference=setting("verdicts", "models", "reference"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/benchmark_models.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/benchmark_models.log",
    script:
        "../scripts/benchmark_models.py"


rule benchmark_stress_relations:
    """Every relation of models.stress on each seed's simulated fabric: steady N1, N2, Pi and eta_r after rotation
    on held-out angles, per seed with t-intervals, the paired difference from the G-W relation."""
    input:
        startup_runs=rules.aggregate_startup.output.runs,
        rotation_runs=rules.aggregate_rotation.output.runs,
        stress_startup_runs=rules.aggregate_stress_startup.output.runs,
        stress_rotation_runs=rules.aggregate_stress_rotation.output.runs,
        relation_files=plugin_files("stress"),
    output:
        leaderboard=f"{RESULTS}/tables/stress_leaderboard.csv",
        parameters=f"{RESULTS}/tables/stress_relation_parameters.csv",
        page=report(f"{RESULTS}/tables/stress_leaderboard.html", caption="../report/table_stress_leaderboard.rst",
                    category="Tables"),
    params:
        relations=setting("models", "stress"),
        folds=setting("models", "held_out_folds"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/benchmark_stress_relations.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/benchmark_stress_relations.log",
    script:
        "../scripts/benchmark_stress_relations.py"


rule benchmark_protocols:
    """Every fabric model (both fitting modes of benchmark_models, or of models.parameters_from) and stress
    relation predicting each of the study's own protocols: per-seed errors with t-intervals, the paired
    difference from G-W, and whether any fit saw the scored seeds (held_out)."""
    input:
        fits=rules.fit_models.output[0],
        model_parameters=lambda wildcards: STUDIES[wildcards.study]["models"]["parameters_from"]
        or rules.benchmark_models.output.parameters.format(study=wildcards.study),
        relation_parameters=rules.benchmark_stress_relations.output.parameters,
        startup_runs=rules.aggregate_startup.output.runs,
        rotation_runs=rules.aggregate_rotation.output.runs,
        stress_startup_runs=rules.aggregate_stress_startup.output.runs,
        stress_rotation_runs=rules.aggregate_stress_rotation.output.runs,
        protocol_runs=rules.aggregate_protocols.output.runs,
        stress_protocol_runs=rules.aggregate_stress_protocols.output.runs,
        model_files=plugin_files("fabric"),
        relation_files=plugin_files("stress"),
    output:
        leaderboard=f"{RESULTS}/tables/protocol_leaderboard.csv",
        predictions=f"{RESULTS}/tables/protocol_predictions.csv",
        stress_leaderboard=f"{RESULTS}/tables/protocol_stress_leaderboard.csv",
    params:
        models=setting("models", "fabric"),
        relations=setting("models", "stress"),
        protocols=protocol_segments,
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        reference=setting("verdicts", "models", "reference"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/benchmark_protocols.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/benchmark_protocols.log",
    script:
        "../scripts/benchmark_protocols.py"


rule transfer_protocols:
    """The transfer model of a campaign (models.transfer, rule transfer_model) on each of the study's own
    protocols at the study's (phi, mu), its rate not refitted, against G-W's steady fit (of
    models.parameters_from, or the study's own)."""
    input:
        model=setting("models", "transfer"),
        model_parameters=lambda wildcards: STUDIES[wildcards.study]["models"]["parameters_from"]
        or rules.benchmark_models.output.parameters.format(study=wildcards.study),
        steady=rules.aggregate_startup.output.steady,
        protocol_runs=rules.aggregate_protocols.output.runs,
    output:
        table=f"{RESULTS}/tables/transfer_protocols.csv",
        summary=f"{RESULTS}/tables/transfer_protocols.md",
    params:
        phi=setting("particles", "phi"),
        mu=setting("forces", "mu"),
        protocols=protocol_segments,
        level=setting("verdicts", "level"),
        code=code_version("../scripts/transfer_protocols.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/transfer_protocols.log",
    script:
        "../scripts/transfer_protocols.py"


rule closure_tests:
    """Each closure of <nnnn> (models.closures) against the measured fourth moment, per seed: in the
    steady startup and over the first verdicts.window strain after each rotation; the implied
    direction distributions a short strain after rotations by 90 and 180 degrees."""
    input:
        startup=seed_runs(f"{RESULTS}/seed{{seed}}/startup/fabric.csv"),
        rotation=seed_runs(f"{RESULTS}/seed{{seed}}/rotation_theta{{angle}}/fabric.csv"),
    output:
        table=f"{RESULTS}/tables/closure_errors.csv",
        per_seed=f"{RESULTS}/tables/closure_errors_per_seed.csv",
        pdf=f"{RESULTS}/figures/closures.pdf",
        png=report(f"{RESULTS}/figures/closures.png", caption="../report/closures.rst", category="Figures"),
    params:
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        # the distributions drawn half a strain after the rotation, or at the window's end if sooner
        snapshot_strain=lambda wildcards: min(0.5, STUDIES[wildcards.study]["verdicts"]["window"]),
        code=code_version("../scripts/closure_tests.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/closure_tests.log",
    script:
        "../scripts/closure_tests.py"


rule error_decomposition:
    """G-W's error after a rotation taken apart: integrated with the closure, with the closure's measured
    error removed along each run, and with the measured <nnnn> in its place, per seed; the G-W stress
    relation's N1, N2 and Pi from G-W's fabric, the measured <nn> and the measured <nnnn>."""
    input:
        startup=seed_runs(f"{RESULTS}/seed{{seed}}/startup/fabric.csv"),
        rotation=seed_runs(f"{RESULTS}/seed{{seed}}/rotation_theta{{angle}}/fabric.csv"),
        stress_startup=rules.aggregate_stress_startup.output.runs,
        stress_rotation=rules.aggregate_stress_rotation.output.runs,
    output:
        table=f"{RESULTS}/tables/error_decomposition.csv",
        per_seed=f"{RESULTS}/tables/error_decomposition_per_seed.csv",
        stress=f"{RESULTS}/tables/stress_decomposition.csv",
        stress_per_seed=f"{RESULTS}/tables/stress_decomposition_per_seed.csv",
        summary=f"{RESULTS}/tables/error_decomposition.md",
    params:
        phi=setting("particles", "phi"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/error_decomposition.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/error_decomposition.log",
    script:
        "../scripts/error_decomposition.py"


rule discover_model:
    """A fabric model found by sparse regression (weak form, sequentially thresholded least squares) on the
    startup and the rotations, its terms chosen by held-out error over folds of angles; scored against
    G-W fitted on the steady state, with the target of half G-W's held-out error net of the noise."""
    input:
        fits=rules.fit_models.output[0],
        startup_runs=rules.aggregate_startup.output.runs,
        rotation_runs=rules.aggregate_rotation.output.runs,
        model_files=plugin_files("fabric"),
    output:
        model=f"{RESULTS}/sparse_model.json",
        supports=f"{RESULTS}/tables/sparse_model_supports.csv",
        coefficients=f"{RESULTS}/tables/sparse_model_coefficients.csv",
        target=f"{RESULTS}/tables/sparse_model_target.csv",
        overshoot=f"{RESULTS}/tables/sparse_model_overshoot.csv",
        steady=f"{RESULTS}/tables/sparse_model_steady.csv",
        summary=f"{RESULTS}/tables/sparse_model.md",
    params:
        models=setting("models", "fabric"),
        folds=setting("models", "held_out_folds"),
        startup_strain=setting("run", "startup_strain"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        reference=setting("verdicts", "models", "reference"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/discover_model.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/discover_model.log",
    script:
        "../scripts/discover_model.py"


rule nested_selection:
    """The sparse model's held-out error by nested cross-validation: seeds held out as well as angles,
    its terms found and chosen inside each outer fold, G-W and the order-1 search under the same
    protocol (suspension_fabric.evaluation.nested_selection)."""
    input:
        startup_runs=rules.aggregate_startup.output.runs,
        rotation_runs=rules.aggregate_rotation.output.runs,
    output:
        comparison=f"{RESULTS}/tables/sparse_model_nested.csv",
        folds=f"{RESULTS}/tables/sparse_model_nested_folds.csv",
        summary=f"{RESULTS}/tables/sparse_model_nested.md",
    params:
        phi=setting("particles", "phi"),
        folds=setting("models", "held_out_folds"),
        startup_strain=setting("run", "startup_strain"),
        steady_window=setting("analysis", "steady_window"),
        window=setting("verdicts", "window"),
        level=setting("verdicts", "level"),
        code=code_version("../scripts/nested_selection.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/nested_selection.log",
    script:
        "../scripts/nested_selection.py"
