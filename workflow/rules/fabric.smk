rule fabric_table:
    """Near-contact fabric per dumped frame of one run, in the paper frame of its shear."""
    input:
        dump=f"{RESULTS}/seed{{seed}}/{{run}}/trajectory.dump",
        marker=f"{RESULTS}/seed{{seed}}/{{run}}/run_complete.json",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/fabric.csv",
    wildcard_constraints:
        study=study_pattern(SIMULATED_STUDIES),
        run=r"startup|rotation_theta[^/]+",
    params:
        eps=setting("analysis", "eps"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/fabric_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/fabric_table.py"


rule stress_table:
    """Stress per dumped frame of one run: symmetric parts in the paper frame of its shear, units eta_f gammadot."""
    input:
        table=f"{RESULTS}/seed{{seed}}/{{run}}/stress.txt",
        marker=f"{RESULTS}/seed{{seed}}/{{run}}/run_complete.json",
        fabric=f"{RESULTS}/seed{{seed}}/{{run}}/fabric.csv",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/stress.csv",
    wildcard_constraints:
        study=study_pattern(SIMULATED_STUDIES),
        run=r"startup|rotation_theta[^/]+",
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/stress_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/stress_table.py"
