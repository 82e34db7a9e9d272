rule figure_startup:
    """Paper Fig. 1: fabric versus strain in startup shear, simulation vs G-W and modified."""
    input:
        fits=rules.fit_models.output[0],
        predictions=rules.predict.output[0],
        startup=rules.aggregate_startup.output.aggregate,
    output:
        pdf=f"{RESULTS}/figures/fig1_startup.pdf",
        png=report(f"{RESULTS}/figures/fig1_startup.png", caption="../report/fig1.rst", category="Figures"),
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
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/figure_rotation.log",
    script:
        "../scripts/figure_rotation.py"
