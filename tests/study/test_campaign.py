"""The campaign over the state point (suspension_fabric.study.campaign, state_map): the grid of studies a
config expands into, the map's statistics and anchor against values worked out by hand, and a
real Snakemake run of a two-point campaign whose map is rebuilt from its exported datasets."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import yaml

from suspension_fabric.evaluation.state_map import bgp_viscosities, map_table, steady_state_drift
from suspension_fabric.reporting.map_page import map_display_table
from suspension_fabric.study.campaign import campaign_points, point_name, study_configs
from suspension_fabric.study.config import ConfigError, load_config, validate_config
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, job_counts, snakemake

BASE = {"study": "grid", "seeds": [1, 2], "angles_deg": [0, 90], "forces": {"kn": 1.25e8}}


def campaign(**section):
    return validate_config({**BASE, "campaign": {"phi": [0.40, 0.45], "mu": [0.0, 0.5], **section}})


def test_a_campaign_is_one_study_per_point_of_the_grid():
    points = campaign_points(campaign())
    assert list(points) == ["phi0.40_mu0", "phi0.40_mu0.5", "phi0.45_mu0", "phi0.45_mu0.5"]
    study = points["phi0.45_mu0"]
    assert study["study"] == "grid/phi0.45_mu0" and study["particles"]["phi"] == 0.45 and study["forces"]["mu"] == 0.0
    assert study["forces"]["kn"] == 1.25e8 and study["seeds"] == [1, 2] and study["campaign"] is None
    assert list(study_configs(campaign())) == [f"grid/{name}" for name in points]
    single = validate_config(dict(BASE))
    assert study_configs(single) == {"grid": single}


@pytest.mark.parametrize(
    ("config_file", "points", "points_in_the_map"),
    [
        ("campaign_engine_iii_points.yaml", ["phi0.53_mu1", "phi0.55_mu1"], ["phi0.53_mu1", "phi0.55_mu1"]),
        ("engine_rule_points.yaml", ["phi0.55_mu0.5", "phi0.53_mu0", "phi0.45_mu1"], ["phi0.55_mu0.5", "phi0.53_mu0"]),
    ],
)
def test_a_config_that_made_points_is_the_campaign_with_those_points_selected(config_file, points, points_in_the_map):
    """Each benchmarks/configs file that made points of data/campaign selects them from the campaign, and
    the points of it the map has are the same studies as in config/campaign.yaml, whose engine the rule
    chooses (run.engine: rule) where these set it by hand, so that the map's points come from one config."""
    campaign_config = load_config(REPO / "config" / "campaign.yaml")
    selected = load_config(REPO / "benchmarks" / "configs" / config_file)
    assert selected["campaign"]["points"] == points
    assert {key: selected["campaign"][key] for key in ("phi", "mu")} == {
        key: campaign_config["campaign"][key] for key in ("phi", "mu")
    }

    def as_made(study):
        # the results folder and who chose the engine aside: the simulations and the analysis
        return {
            **{key: value for key, value in study.items() if key != "study"},
            "run": {key: value for key, value in study["run"].items() if key != "engine"},
        }

    studies = {
        name.split("/")[-1]: as_made(study)
        for name, study in study_configs(selected).items()
        if name.split("/")[-1] in points_in_the_map
    }
    assert len(studies) == len(points_in_the_map)
    assert studies == {
        name.split("/")[-1]: as_made(study)
        for name, study in study_configs(campaign_config).items()
        if name.split("/")[-1] in studies
    }


def test_overrides_subsets_and_points_not_run():
    config = campaign(
        overrides={"phi0.45_mu0.5": {"forces": {"kn": 5e8}, "run": {"dt": 2.5e-5}}},
        points=["phi0.45_mu0.5", "phi0.40_mu0"],
        not_run={"phi0.40_mu0": "too dear"},
        datasets="data/grid",
    )
    points = campaign_points(config)
    assert list(points) == ["phi0.45_mu0.5"]
    assert points["phi0.45_mu0.5"]["forces"]["kn"] == 5e8 and points["phi0.45_mu0.5"]["run"]["dt"] == 2.5e-5
    assert points["phi0.45_mu0.5"]["forces"]["mu"] == 0.5  # the override merges, key by key
    assert points["phi0.45_mu0.5"]["dataset"] == "data/grid/phi0.45_mu0.5"
    assert point_name(0.4, 1.0) == "phi0.40_mu1" and point_name(0.525, 0.25) == "phi0.53_mu0.25"


def test_a_flow_curve_axis_names_its_points_and_sets_its_key():
    """campaign.critical_load_rate or campaign.critical_load_stress adds a third axis: points
    phi<phi>_mu<mu>_rate<rate> or _stress<stress>, each with its forces key; both at once are refused."""
    rates = campaign_points(campaign(mu=[1.0], critical_load_rate=[0.1]))
    assert (
        list(rates)[0] == "phi0.40_mu1_rate0.1" and rates["phi0.40_mu1_rate0.1"]["forces"]["critical_load_rate"] == 0.1
    )
    stresses = campaign_points(campaign(mu=[1.0], critical_load_stress=[0.05, 0.2]))
    assert list(stresses) == [
        "phi0.40_mu1_stress0.05",
        "phi0.40_mu1_stress0.2",
        "phi0.45_mu1_stress0.05",
        "phi0.45_mu1_stress0.2",
    ]
    assert stresses["phi0.45_mu1_stress0.2"]["forces"]["critical_load_stress"] == 0.2
    assert stresses["phi0.45_mu1_stress0.2"]["forces"]["critical_load_rate"] is None
    with pytest.raises(ConfigError, match="'campaign.critical_load_rate' and 'campaign.critical_load_stress' exclude"):
        campaign_points(campaign(mu=[1.0], critical_load_rate=[0.1], critical_load_stress=[0.1]))


def test_a_shape_window_needs_three_imposed_values_inside_it():
    """campaign.shape_window measures a curve's slope and curvature over its points inside [low, high]:
    a window holding two stresses, or a grid without a flow-curve axis, is refused naming the key."""
    three = campaign(mu=[1.0], critical_load_stress=[0.05, 0.1, 0.2], shape_window=[0.05, 0.2])
    assert len(campaign_points(three)) == 6
    for refused in (
        campaign(mu=[1.0], critical_load_stress=[0.05, 0.1, 0.2], shape_window=[0.06, 0.2]),
        campaign(mu=[1.0], shape_window=[0.05, 0.2]),
    ):
        with pytest.raises(ConfigError, match=r"'campaign.shape_window' .* needs 3 or more"):
            campaign_points(refused)


@pytest.mark.parametrize(
    "section, message",
    [
        ({"points": ["phi0.47_mu0"]}, "config key 'campaign.points': 'phi0.47_mu0' is not a point"),
        ({"overrides": {"phi0.4_mu0": {}}}, "config key 'campaign.overrides': 'phi0.4_mu0' is not a point"),
        (
            {"not_run": {"phi0.40_mu0": "x", "phi0.40_mu0.5": "x", "phi0.45_mu0": "x", "phi0.45_mu0.5": "x"}},
            "config key 'campaign.points': no point left",
        ),
        (
            {"overrides": {"phi0.45_mu0": {"run": {"startup_strain": 1.0}}}},
            "campaign point phi0.45_mu0 .*config key 'analysis.steady_window'",
        ),
        ({"overrides": {"phi0.45_mu0": {"run": {"dt": 1.0e-3}}}}, "campaign point phi0.45_mu0 .*config key 'run.dt'"),
    ],
)
def test_bad_campaigns_name_the_point_and_key(section, message):
    with pytest.raises(ConfigError, match=message):
        campaign_points(campaign(**section))


def test_bad_campaign_sections_are_schema_errors():
    with pytest.raises(ConfigError, match="config key 'campaign.phi.0'"):
        validate_config({**BASE, "campaign": {"phi": [0.8], "mu": [0.0]}})
    with pytest.raises(ConfigError, match="config key 'campaign'"):
        validate_config({**BASE, "campaign": {"phi": [0.4]}})


def test_bgp_law_at_hand_worked_points():
    """BGP 2011: J = (phi_m / phi - 1)^2, Pi = 1 / J, eta_r = mu(J) / J with
    mu(J) = mu1 + (mu2 - mu1) / (1 + J0 / J) + J + 5/2 phi_m J^(1/2).
    At phi = 0.45 (phi_m = 0.585): J^(1/2) = 0.3, J = 0.09, Pi = 11.11,
    mu = 0.32 + 0.38 / (1 + 0.005 / 0.09) + 0.09 + 2.5 * 0.585 * 0.3 = 1.20875, eta_r = 13.43."""
    eta_r, pressure = bgp_viscosities([0.45])
    assert pressure[0] == pytest.approx(1 / 0.09, rel=1e-12)
    assert eta_r[0] == pytest.approx((0.32 + 0.38 / (1 + 0.005 / 0.09) + 0.09 + 2.5 * 0.585 * 0.3) / 0.09, rel=1e-12)
    assert eta_r[0] == pytest.approx(13.43, abs=0.01)
    # diverges at phi_m as (phi_m - phi)^-2: Pi (phi_m - phi)^2 -> phi_m^2
    eta_r, pressure = bgp_viscosities([0.585 - 1e-6])
    assert pressure[0] * 1e-12 == pytest.approx(0.585**2, rel=1e-4)
    with pytest.raises(ValueError, match="phi_m"):
        bgp_viscosities([0.6])


def _runs(drifts, noise=0.0):
    """Startup runs of several seeds, value 1 + drift * (strain - 2) / 3 over strain [2, 5]."""
    strain = np.linspace(0.0, 5.0, 251)
    rng = np.random.default_rng(3)
    frames = [
        pd.DataFrame(
            {
                "seed": seed,
                "strain": strain,
                "n12": 1.0 + drift * (strain - 2.0) / 3.0 + noise * rng.standard_normal(strain.size),
            }
        )
        for seed, drift in enumerate(drifts, start=1)
    ]
    return pd.concat(frames, ignore_index=True)


def test_steady_state_drift_against_a_known_linear_drift():
    """A linear ramp of total rise r over the window [2, 5]: the half means differ by r / 2."""
    flat = steady_state_drift(_runs([0.0, 0.0, 0.0, 0.0], noise=0.01), "n12", (2.0, 5.0), 1.0)
    assert flat["verdict"] == "steady" and abs(flat["mean"]) < 0.01
    ramp = steady_state_drift(_runs([0.4, 0.42, 0.38, 0.4]), "n12", (2.0, 5.0), 1.0)
    assert ramp["mean"] == pytest.approx(0.2, abs=2e-3) and ramp["verdict"] == "drifting"
    spread = steady_state_drift(_runs([0.4, -0.4, 0.3, -0.3]), "n12", (2.0, 5.0), 1.0)
    assert spread["verdict"] == "not resolved"


def test_map_table_lists_points_not_run_with_their_reason():
    table = map_table(
        [{"point": "phi0.45_mu0.5", "phi": 0.45, "mu": 0.5, "steady": "steady"}], {"phi0.55_mu1": "too dear"}
    )
    assert list(table["point"]) == ["phi0.45_mu0.5", "phi0.55_mu1"]
    assert table.set_index("point").loc["phi0.55_mu1", "steady"] == "not run: too dear"
    assert table.set_index("point").loc["phi0.55_mu1", "phi"] == 0.55


def test_the_map_page_shows_each_point_s_claims_and_the_compared_models_fits():
    """map_display_table: the paired model-error claims (columns "C3'_mean", ...) with interval and
    verdict, and each compared model's parameters under its label."""
    row = {"point": "phi0.45_mu0.5", "phi": 0.45, "mu": 0.5, "steady": "steady", "kn": 1.25e8, "dt": 1e-4}
    row.update({"C3'_mean": -0.02, "C3'_low": -0.03, "C3'_high": -0.01, "C3'_verdict": "refuted"})
    row.update({"challenger_model": "modified G-W (Eq. 2)", "challenger_A": 44.8, "challenger_A_err": 0.3})
    shown = map_display_table(map_table([row], {})).iloc[0]
    assert shown["C3'"] == "-0.020 [-0.030, -0.010] refuted"
    assert shown["modified G-W (Eq. 2) A"] == "44.80 ± 0.30"


@pytest.mark.workflow
def test_a_campaign_runs_by_the_study_rules_and_its_map_rebuilds_from_its_datasets(tmp_path):
    """Two points of the test study's size (phi 0.40, 0.45 at mu 0.5) and a third not run:
    every point runs the study's rules the map needs and the map has a row each; --config picks a subset;
    the exported datasets rebuild the same map with no simulation job."""
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((REPO / "config" / "test.yaml").read_text())
    config.update(
        study="tcamp",
        campaign={
            "phi": [0.40, 0.45],
            "mu": [0.5, 1.0],
            "not_run": {"phi0.45_mu1": "test of a point not run"},
            "points": ["phi0.40_mu0.5", "phi0.45_mu0.5", "phi0.45_mu1"],
        },
    )
    (workdir / "config" / "tcamp.yaml").write_text(yaml.safe_dump(config))
    subset = snakemake(
        workdir, "-n", "--configfile", "config/tcamp.yaml", "--config", "campaign={points: [phi0.45_mu0.5]}"
    )
    assert subset.returncode == 0, subset.stderr[-3000:]
    jobs = dry_run_jobs(subset.stdout)
    assert {job["study"] for job in jobs if job["rule"] == "pack"} == {"tcamp/phi0.45_mu0.5"}
    # the map's target (its table and figures) rather than every point's report: the study's own
    # rules are tested whole by test_workflow.py
    result = snakemake(workdir, "campaign_figures", "--configfile", "config/tcamp.yaml", timeout=1200)
    assert result.returncode == 0, result.stderr[-3000:]
    # the map needs no rotation stress: those runs lack their stress.csv, and are not exported without it
    early = subprocess.run(
        [
            sys.executable,
            "-m",
            "suspension_fabric.study.dataset",
            "export",
            "--config",
            "config/tcamp.yaml",
            "--to",
            "data/early",
            "--without-raw-stress",
        ],
        cwd=workdir,
        capture_output=True,
        text=True,
    )
    assert early.returncode == 0, early.stderr[-3000:]
    assert (
        "data/early/phi0.45_mu0.5: 2 runs exported, 4 missing (no run_complete.json, fabric.csv or "
        "stress.csv yet, e.g. seed1/rotation_theta0)"
    ) in early.stdout
    points = ("phi0.40_mu0.5", "phi0.45_mu0.5")
    result = snakemake(
        workdir,
        *(f"results/tcamp/{point}/tables/stress_rotation_aggregate.csv" for point in points),
        "--configfile",
        "config/tcamp.yaml",
        timeout=1200,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    table = pd.read_csv(workdir / "results/tcamp/tables/map.csv").set_index("point")
    assert list(table.index) == ["phi0.40_mu0.5", "phi0.45_mu0.5", "phi0.45_mu1"]
    assert table.loc["phi0.45_mu1", "steady"] == "not run: test of a point not run"
    for point in points:
        steady = pd.read_csv(workdir / f"results/tcamp/{point}/tables/steady_state.csv").set_index("quantity")
        assert table.loc[point, "n12"] == pytest.approx(steady.loc["n12", "mean"], rel=1e-12)
        assert table.loc[point, "phi"] == float(point[3:7]) and table.loc[point, "n"] == 40
    assert table.loc["phi0.45_mu0.5", "Z"] > table.loc["phi0.40_mu0.5", "Z"]  # denser, more contacts
    # the fits of the two models the claims compare (verdicts.models), by role
    point = table.loc["phi0.45_mu0.5"]
    assert (point["reference_model"], point["challenger_model"]) == ("G-W (Eq. 1)", "modified G-W (Eq. 2)")
    assert point["challenger_A_over_beta"] == pytest.approx(point["challenger_A"] / point["challenger_beta"])
    for name in ("map_models", "map_fabric", "map_rheology", "map_model_errors"):
        assert (workdir / f"results/tcamp/figures/{name}.png").stat().st_size > 10_000
    export = subprocess.run(
        [
            sys.executable,
            "-m",
            "suspension_fabric.study.dataset",
            "export",
            "--config",
            "config/tcamp.yaml",
            "--to",
            "data/tcamp",
            "--without-raw-stress",
        ],
        cwd=workdir,
        capture_output=True,
        text=True,
    )
    assert export.returncode == 0, export.stderr[-3000:]
    assert "data/tcamp/phi0.45_mu0.5: 6 runs exported, 0 missing" in export.stdout
    (workdir / "config" / "tmap.yaml").write_text("study: tmap\ncampaign:\n  datasets: data/tcamp\n")
    # the map's table alone: the figures drawn from it were checked above
    rebuilt_map = "results/tmap/tables/map.csv"
    plan = snakemake(workdir, "-n", rebuilt_map, "--configfile", "config/tcamp.yaml", "config/tmap.yaml")
    assert plan.returncode == 0, plan.stdout[-3000:]
    counts = job_counts(plan.stdout)
    assert {rule: count for rule, count in counts.items() if rule.startswith("import")} == {
        "import_run_tables_0": 1,
        "import_run_tables_1": 1,
    }  # one job per point
    assert not set(counts) & {"pack", "shear_segment", "fabric_table", "stress_table"}
    rebuilt = snakemake(workdir, rebuilt_map, "--configfile", "config/tcamp.yaml", "config/tmap.yaml")
    assert rebuilt.returncode == 0, rebuilt.stderr[-3000:]
    again = pd.read_csv(workdir / rebuilt_map).set_index("point")
    numbers = table.select_dtypes("number").columns
    pd.testing.assert_frame_equal(again[numbers], table[numbers], rtol=1e-9)
