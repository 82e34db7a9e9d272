rule report_tables:
    """fits.json, the steady state and the model-error summary as captioned HTML tables for the report."""
    input:
        fits=rules.fit_models.output[0],
        steady=rules.aggregate_startup.output.steady,
        errors=rules.model_errors.output.summary,
    output:
        fits=report(f"{RESULTS}/tables/fits.html", caption="../report/table_fits.rst", category="Tables"),
        steady=report(
            f"{RESULTS}/tables/steady_state.html", caption="../report/table_steady_state.rst", category="Tables"
        ),
        errors=report(
            f"{RESULTS}/tables/model_errors_summary.html",
            caption="../report/table_model_errors.rst",
            category="Tables",
        ),
    params:
        code=code_version("../scripts/report_tables.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/report_tables.log",
    script:
        "../scripts/report_tables.py"


rule report_stress:
    """The stress: steady state, G-W stress relation fits and errors, viscosity transients, as an HTML table page."""
    input:
        steady=rules.aggregate_stress_startup.output.steady,
        relation=rules.stress_relation.output.fits,
        summary=rules.stress_relation.output.summary,
        transients=rules.stress_relation.output.transients,
    output:
        report(f"{RESULTS}/tables/stress.html", caption="../report/table_stress.rst", category="Tables"),
    params:
        code=code_version("../scripts/report_stress.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/report_stress.log",
    script:
        "../scripts/report_stress.py"


rule report_protocols:
    """The protocols' results as a Markdown fragment written from the leaderboards (the docs include the
    committed dataset's)."""
    input:
        leaderboard=rules.benchmark_protocols.output.leaderboard,
        stress_leaderboard=rules.benchmark_protocols.output.stress_leaderboard,
        states=rules.aggregate_protocols.output.states,
        stress_states=rules.aggregate_stress_protocols.output.states,
        runs=rules.aggregate_protocols.output.runs,
        stress_runs=rules.aggregate_stress_protocols.output.runs,
    output:
        summary=f"{RESULTS}/tables/protocol_summary.md",
        drift=f"{RESULTS}/tables/protocol_drift.csv",
    params:
        reference=setting("verdicts", "models", "reference"),
        relations=setting("models", "stress"),
        protocols=protocol_segments,
        level=setting("verdicts", "level"),
        code=code_version("../scripts/report_protocols.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/report_protocols.log",
    script:
        "../scripts/report_protocols.py"
