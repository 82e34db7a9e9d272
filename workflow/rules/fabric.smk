rule fabric_table:
    """Near-contact fabric per dumped frame of one run, in the frame of its current flow."""
    input:
        dump=f"{RESULTS}/seed{{seed}}/{{run}}/trajectory.dump",
        marker=f"{RESULTS}/seed{{seed}}/{{run}}/run_complete.json",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/fabric.csv",
    wildcard_constraints:
        study=study_pattern(SIMULATED_STUDIES),
    params:
        eps=setting("analysis", "eps"),
        code=code_version("../scripts/fabric_table.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/fabric_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/fabric_table.py"


rule stress_table:
    """Stress per dumped frame of one run: symmetric parts in the frame of its current flow, units eta_f gammadot."""
    input:
        table=f"{RESULTS}/seed{{seed}}/{{run}}/stress.txt",
        marker=f"{RESULTS}/seed{{seed}}/{{run}}/run_complete.json",
        fabric=f"{RESULTS}/seed{{seed}}/{{run}}/fabric.csv",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/stress.csv",
    wildcard_constraints:
        study=study_pattern(SIMULATED_STUDIES),
    params:
        code=code_version("../scripts/stress_table.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/stress_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/stress_table.py"
