# The map over a campaign's state points (suspension_fabric.evaluation.state_map): one row per point from its
# own study's tables, then the map figures. Every map output depends on every point's rules.
from suspension_fabric.reporting.map_figures import MAP_FIGURES

CAMPAIGN_RESULTS = f"results/{config['study']}"
POINTS = {name.split("/", 1)[1]: name for name in STUDIES}  # point name -> its study
MAP_FIGURE_NAMES = list(MAP_FIGURES)


rule campaign_map:
    """The map table: per point the steady fabric, Z, stress, fits, steady-state check and claim
    statistics; its report page and its Markdown summary for the docs (docs/generated/map_summary.md)."""
    input:
        steady=per_point(rules.aggregate_startup.output.steady),
        stress_steady=per_point(rules.aggregate_stress_startup.output.steady),
        fits=per_point(rules.fit_models.output[0]),
        verdicts=per_point(rules.verdicts.output.verdicts),
        startup_runs=per_point(rules.aggregate_startup.output.runs),
        stress_runs=per_point(rules.aggregate_stress_startup.output.runs),
    output:
        table=f"{CAMPAIGN_RESULTS}/tables/map.csv",
        page=report(f"{CAMPAIGN_RESULTS}/tables/map.html", caption="../report/table_map.rst", category="Map"),
        summary=f"{CAMPAIGN_RESULTS}/tables/map_summary.md",
    params:
        points=POINTS,
        not_run=config["campaign"]["not_run"],
        level=config["verdicts"]["level"],
        code=code_version("../scripts/campaign_map.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/campaign_map.log",
    script:
        "../scripts/campaign_map.py"


rule campaign_figures:
    """Map figures: model parameters, steady fabric and Z, eta_r and Pi with the BGP anchor, model errors, against phi."""
    input:
        rules.campaign_map.output.table,
    output:
        **{f"{name}_pdf": f"{CAMPAIGN_RESULTS}/figures/{name}.pdf" for name in MAP_FIGURE_NAMES},
        **{
            f"{name}_png": report(
                f"{CAMPAIGN_RESULTS}/figures/{name}.png", caption="../report/map_figures.rst", category="Map"
            )
            for name in MAP_FIGURE_NAMES
        },
    params:
        level=config["verdicts"]["level"],
        code=code_version("../scripts/campaign_figures.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/campaign_figures.log",
    script:
        "../scripts/campaign_figures.py"


rule transfer_model:
    """A fabric model fitted over the map's points at once (suspension_fabric.evaluation.model_transfer):
    each point predicted by a fit on the others, against G-W; the model fitted on every point as a file
    other studies score (models.transfer)."""
    input:
        startup_runs=per_point(rules.aggregate_startup.output.runs),
        rotation_runs=per_point(rules.aggregate_rotation.output.runs),
        fits=per_point(rules.fit_models.output[0]),
    output:
        points=f"{CAMPAIGN_RESULTS}/tables/transfer_points.csv",
        folds=f"{CAMPAIGN_RESULTS}/tables/transfer_folds.csv",
        summary=f"{CAMPAIGN_RESULTS}/tables/transfer_points.md",
        model=f"{CAMPAIGN_RESULTS}/tables/transfer_model.json",
    params:
        points=POINTS,
        datasets=config["campaign"]["datasets"],
        required=config["campaign"]["transfer_points_required"],
        window=config["verdicts"]["window"],
        level=config["verdicts"]["level"],
        code=code_version("../scripts/transfer_model.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/transfer_model.log",
    script:
        "../scripts/transfer_model.py"


rule flow_curve:
    """Flow curves of a campaign over critical-load rates or stresses (campaign.critical_load_rate or
    campaign.critical_load_stress): per point and
    seed the steady stress, contacts and frictional fraction against sigma / sigma_0, their t-intervals,
    each curve's Wyart-Cates onset stress, thickening exponents and shape (campaign.shape_window), the Wyart-Cates viscosity fitted over the curves of each
    friction coefficient, a Markdown fragment for the docs and the figure."""
    input:
        stress_runs=per_point(rules.aggregate_stress_startup.output.runs),
        frictionless=frictionless_datasets,
    output:
        table=f"{CAMPAIGN_RESULTS}/tables/flow_curve.csv",
        seeds=f"{CAMPAIGN_RESULTS}/tables/flow_curve_seeds.csv",
        onsets=f"{CAMPAIGN_RESULTS}/tables/flow_curve_onsets.csv",
        exponents=f"{CAMPAIGN_RESULTS}/tables/flow_curve_exponents.csv",
        shape=f"{CAMPAIGN_RESULTS}/tables/flow_curve_shape.csv",
        wyart_cates=f"{CAMPAIGN_RESULTS}/tables/flow_curve_wyart_cates.csv",
        frictionless=f"{CAMPAIGN_RESULTS}/tables/flow_curve_frictionless.csv",
        summary=f"{CAMPAIGN_RESULTS}/tables/flow_curve_summary.md",
        figure_pdf=f"{CAMPAIGN_RESULTS}/figures/flow_curve.pdf",
        figure_png=report(
            f"{CAMPAIGN_RESULTS}/figures/flow_curve.png", caption="../report/flow_curve.rst", category="Flow curves"
        ),
    params:
        points={
            name: {
                "phi": STUDIES[study]["particles"]["phi"],
                "mu": STUDIES[study]["forces"]["mu"],
                "rate_ratio": STUDIES[study]["forces"]["critical_load_rate"],
                "stress_ratio": STUDIES[study]["forces"]["critical_load_stress"],
                "eta_f": STUDIES[study]["forces"]["eta_f"],
                "d_small": STUDIES[study]["particles"]["d_small"],
            }
            for name, study in POINTS.items()
        },
        steady_window=config["analysis"]["steady_window"],
        shape_window=config["campaign"]["shape_window"],
        level=config["verdicts"]["level"],
        code=code_version("../scripts/flow_curve.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/flow_curve.log",
    script:
        "../scripts/flow_curve.py"


rule direction_response:
    """The response to a change of flow direction at each point of a flow-curve campaign whose angles
    go beyond 0: each rotated run against the same seed's run at theta = 0 over windows of strain
    after the change (eta_r, frictional fraction, contacts, <nn>_12), Holm over the table, the points
    compared with Welch's interval, a Markdown fragment and the figure."""
    input:
        stress_runs=per_point(rules.aggregate_stress_rotation.output.runs),
        fabric_runs=per_point(rules.aggregate_rotation.output.runs),
    output:
        table=f"{CAMPAIGN_RESULTS}/tables/direction_response.csv",
        seeds=f"{CAMPAIGN_RESULTS}/tables/direction_response_seeds.csv",
        comparisons=f"{CAMPAIGN_RESULTS}/tables/direction_response_comparisons.csv",
        summary=f"{CAMPAIGN_RESULTS}/tables/direction_response_summary.md",
        figure_pdf=f"{CAMPAIGN_RESULTS}/figures/direction_response.pdf",
        figure_png=report(
            f"{CAMPAIGN_RESULTS}/figures/direction_response.png",
            caption="../report/direction_response.rst",
            category="Flow curves",
        ),
    params:
        points={
            name: {
                "label": point_label(study),
                "target": STUDIES[study]["forces"]["critical_load_stress"]
                or STUDIES[study]["forces"]["critical_load_rate"],
            }
            for name, study in POINTS.items()
        },
        level=config["verdicts"]["level"],
        code=code_version("../scripts/direction_response.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/direction_response.log",
    script:
        "../scripts/direction_response.py"


rule direction_models:
    """Fabric models after a change of flow direction at each point of a flow-curve campaign whose
    angles go beyond 0 (suspension_fabric.evaluation.direction_models): each model fitted on the
    point's startup steady state and scored after each change against no transient, then between
    the points; Holm over each table; a Markdown fragment."""
    input:
        startup_runs=per_point(rules.aggregate_startup.output.runs),
        rotation_runs=per_point(rules.aggregate_rotation.output.runs),
        fits=per_point(rules.fit_models.output[0]),
    output:
        seeds=f"{CAMPAIGN_RESULTS}/tables/direction_models_seeds.csv",
        skill=f"{CAMPAIGN_RESULTS}/tables/direction_models.csv",
        comparison=f"{CAMPAIGN_RESULTS}/tables/direction_models_comparison.csv",
        summary=f"{CAMPAIGN_RESULTS}/tables/direction_models_summary.md",
    params:
        points={
            name: {
                "label": point_label(study),
                "target": STUDIES[study]["forces"]["critical_load_stress"]
                or STUDIES[study]["forces"]["critical_load_rate"],
                "models": STUDIES[study]["models"]["fabric"],
                "startup_strain": STUDIES[study]["run"]["startup_strain"],
                "rotation_strain": STUDIES[study]["run"]["rotation_strain"],
                "steady_window": STUDIES[study]["analysis"]["steady_window"],
            }
            for name, study in POINTS.items()
        },
        window=config["verdicts"]["window"],
        level=config["verdicts"]["level"],
        code=code_version("../scripts/direction_models.py"),
    conda:
        CONDA_ENV
    log:
        f"{CAMPAIGN_RESULTS}/logs/direction_models.log",
    script:
        "../scripts/direction_models.py"


if is_flow_curve_campaign(config):
    # flow curves: every point's startup and continuation tables and the curves (no map: the points
    # share their (phi, mu)); with angles beyond 0, the response to the change of direction
    CAMPAIGN_TARGETS = [
        *rules.flow_curve.output,
        *per_point(rules.aggregate_rotation.output.runs),
        *per_point(rules.aggregate_stress_rotation.output.runs),
        *per_point(rules.aggregate_startup.output.steady),
    ]
    if any(theta != 0 for theta in config["angles_deg"]):
        CAMPAIGN_TARGETS += [*rules.direction_response.output, *rules.direction_models.output]
else:
    CAMPAIGN_TARGETS = [*rules.campaign_map.output, *rules.campaign_figures.output]
    if config["campaign"]["transfer_model"]:
        CAMPAIGN_TARGETS += [*rules.transfer_model.output]
