rule figure_startup:
    """Paper Fig. 1: fabric versus strain in startup shear, simulation vs G-W and modified."""
    input:
        fits=rules.fit_models.output[0],
        predictions=rules.predict.output[0],
        startup=rules.aggregate_startup.output.aggregate,
    output:
        pdf=f"{RESULTS}/figures/fig1_startup.pdf",
        png=report(f"{RESULTS}/figures/fig1_startup.png", caption="../report/fig1.rst", category="Figures"),
    params:
        code=code_version("../scripts/figure_startup.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_startup.log",
    script:
        "../scripts/figure_startup.py"


rule figure_rotation:
    """Paper Fig. 2: polar maps of <nn>'_12 and <nn>'_23 over angle and strain after rotation."""
    input:
        fits=rules.fit_models.output[0],
        predictions=rules.predict.output[0],
        rotation=rules.aggregate_rotation.output.aggregate,
    output:
        pdf=f"{RESULTS}/figures/fig2_rotation.pdf",
        png=report(f"{RESULTS}/figures/fig2_rotation.png", caption="../report/fig2.rst", category="Figures"),
    params:
        code=code_version("../scripts/figure_rotation.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_rotation.log",
    script:
        "../scripts/figure_rotation.py"


rule figure_stress_startup:
    """Fig. 3: startup eta_r (with its parts), N1 and N2, simulation vs the G-W stress relation."""
    input:
        stress=rules.aggregate_stress_startup.output.aggregate,
        relation=rules.stress_relation.output.fits,
        predictions=rules.stress_relation.output.predictions,
    output:
        pdf=f"{RESULTS}/figures/fig3_stress.pdf",
        png=report(f"{RESULTS}/figures/fig3_stress.png", caption="../report/fig3.rst", category="Figures"),
    params:
        code=code_version("../scripts/figure_stress_startup.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_stress_startup.log",
    script:
        "../scripts/figure_stress_startup.py"


rule figure_stress_rotation:
    """Fig. 4: polar maps of sigma'_12 and sigma'_23 after rotation; viscosity minimum and recovery per angle."""
    input:
        stress=rules.aggregate_stress_rotation.output.aggregate,
        steady=rules.aggregate_stress_startup.output.steady,
        predictions=rules.stress_relation.output.predictions,
        transients=rules.stress_relation.output.transients,
    output:
        pdf=f"{RESULTS}/figures/fig4_stress_rotation.pdf",
        png=report(
            f"{RESULTS}/figures/fig4_stress_rotation.png", caption="../report/fig4.rst", category="Figures"
        ),
    params:
        code=code_version("../scripts/figure_stress_rotation.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_stress_rotation.log",
    script:
        "../scripts/figure_stress_rotation.py"


rule figure_protocol:
    """One of the study's own protocols: <nn>, Z and eta_r against the strain since rest, simulation
    (seed mean and standard error) against every fabric model fitted on the startup's steady state."""
    input:
        fits=rules.fit_models.output[0],
        fabric=rules.aggregate_protocols.output.aggregate,
        stress=rules.aggregate_stress_protocols.output.aggregate,
        predictions=rules.benchmark_protocols.output.predictions,
    output:
        pdf=f"{RESULTS}/figures/protocol_{{protocol}}.pdf",
        png=report(f"{RESULTS}/figures/protocol_{{protocol}}.png", caption="../report/protocol.rst", category="Protocols"),
    params:
        segments=lambda wildcards: [s.as_dict() for s in own_protocols(wildcards.study)[wildcards.protocol].segments],
        code=code_version("../scripts/figure_protocol.py"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_protocol_{{protocol}}.log",
    script:
        "../scripts/figure_protocol.py"
