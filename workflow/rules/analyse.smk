rule aggregate_startup:
    """Seed means and standard errors of startup shear; its steady state (the fit targets)."""
    input:
        seed_runs(f"{RESULTS}/seed{{seed}}/startup/fabric.csv"),
    output:
        runs=f"{RESULTS}/tables/startup_runs.csv",
        aggregate=f"{RESULTS}/tables/startup_aggregate.csv",
        steady=f"{RESULTS}/tables/steady_state.csv",
    params:
        kind="startup",
        quantity="fabric",
        steady_window=setting("analysis", "steady_window"),
        code=code_version("../scripts/aggregate.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_startup.log",
    script:
        "../scripts/aggregate.py"


rule aggregate_rotation:
    """Seed means and standard errors per angle and post-rotation strain."""
    input:
        seed_runs(f"{RESULTS}/seed{{seed}}/rotation_theta{{angle}}/fabric.csv"),
    output:
        runs=f"{RESULTS}/tables/rotation_runs.csv",
        aggregate=f"{RESULTS}/tables/rotation_aggregate.csv",
    params:
        kind="rotation",
        quantity="fabric",
        code=code_version("../scripts/aggregate.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_rotation.log",
    script:
        "../scripts/aggregate.py"


rule aggregate_stress_startup:
    """Seed means and standard errors of the stress in startup shear; its steady state."""
    input:
        seed_runs(f"{RESULTS}/seed{{seed}}/startup/stress.csv"),
    output:
        runs=f"{RESULTS}/tables/stress_startup_runs.csv",
        aggregate=f"{RESULTS}/tables/stress_startup_aggregate.csv",
        steady=f"{RESULTS}/tables/stress_steady_state.csv",
    params:
        kind="startup",
        quantity="stress",
        steady_window=setting("analysis", "steady_window"),
        lubrication_stress=setting("analysis", "lubrication_stress"),
        code=code_version("../scripts/aggregate.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_stress_startup.log",
    script:
        "../scripts/aggregate.py"


rule aggregate_stress_rotation:
    """Seed means and standard errors of the stress per angle and post-rotation strain."""
    input:
        seed_runs(f"{RESULTS}/seed{{seed}}/rotation_theta{{angle}}/stress.csv"),
    output:
        runs=f"{RESULTS}/tables/stress_rotation_runs.csv",
        aggregate=f"{RESULTS}/tables/stress_rotation_aggregate.csv",
    params:
        kind="rotation",
        quantity="stress",
        lubrication_stress=setting("analysis", "lubrication_stress"),
        code=code_version("../scripts/aggregate.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_stress_rotation.log",
    script:
        "../scripts/aggregate.py"


rule aggregate_protocols:
    """The fabric along each of the study's own protocols (config key `protocols`): every segment's
    run joined per seed, the seed means, in the frame of the current flow, and the late state of
    every segment against the startup's steady state."""
    input:
        protocol_run_files("fabric.csv"),
    output:
        runs=f"{RESULTS}/tables/protocol_runs.csv",
        aggregate=f"{RESULTS}/tables/protocol_aggregate.csv",
        states=f"{RESULTS}/tables/protocol_states.csv",
    params:
        quantity="fabric",
        steady_window=setting("analysis", "steady_window"),
        level=setting("verdicts", "level"),
        runs=lambda wildcards: protocol_run_names(wildcards.study),
        protocols=protocol_segments,
        seeds=setting("seeds"),
        code=code_version("../scripts/aggregate_protocols.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_protocols.log",
    script:
        "../scripts/aggregate_protocols.py"


rule aggregate_stress_protocols:
    """The stress along each of the study's own protocols, as rule aggregate_protocols."""
    input:
        protocol_run_files("stress.csv"),
    output:
        runs=f"{RESULTS}/tables/stress_protocol_runs.csv",
        aggregate=f"{RESULTS}/tables/stress_protocol_aggregate.csv",
        states=f"{RESULTS}/tables/stress_protocol_states.csv",
    params:
        quantity="stress",
        steady_window=setting("analysis", "steady_window"),
        level=setting("verdicts", "level"),
        runs=lambda wildcards: protocol_run_names(wildcards.study),
        protocols=protocol_segments,
        seeds=setting("seeds"),
        lubrication_stress=setting("analysis", "lubrication_stress"),
        code=code_version("../scripts/aggregate_protocols.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/aggregate_stress_protocols.log",
    script:
        "../scripts/aggregate_protocols.py"
