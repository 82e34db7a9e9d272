"""The flow curves under critical-load friction rebuilt from their committed datasets
(config/thickening.yaml with config/thickening_reference.yaml, data/thickening), as docs/thickening.md
shows them: no simulation job, every point of the campaign, and the Markdown fragment the page
includes (docs/generated/flow_curve_summary.md) equal to the one the rebuild writes."""

import shutil

import pandas as pd
import pytest

from quoted_numbers import fragment_problems
from suspension_fabric.evaluation import flow_curve
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_layered_config
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

CONFIG = ["--configfile", "config/thickening.yaml", "config/thickening_reference.yaml"]
SUMMARY = "results/thickening_reference/tables/flow_curve_summary.md"


def test_the_flow_curves_rebuild_from_the_committed_datasets_as_the_docs_show_them(tmp_path):
    workdir = copy_workflow(tmp_path)
    shutil.copytree(REPO / "data" / "thickening", workdir / "data" / "thickening")
    for point in (REPO / "data" / "campaign").glob("*_mu0"):  # the Wyart-Cates fit's frictionless points
        shutil.copytree(point, workdir / "data" / "campaign" / point.name)
    plan = snakemake(workdir, "-n", *CONFIG)
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert "flow_curve" in rules and "campaign_map" not in rules, rules
    assert not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}, rules
    # the flow curve's own jobs (43 of the plan's 107): the per-point aggregates it does not read are
    # the rules every study runs, tested there
    result = snakemake(workdir, *CONFIG, "--", SUMMARY, timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    campaign = load_layered_config([REPO / "config/thickening.yaml", REPO / "config/thickening_reference.yaml"])
    table = pd.read_csv(workdir / "results/thickening_reference/tables/flow_curve.csv")
    assert sorted(table["point"]) == sorted(campaign_points(campaign))
    assert (table["n_seeds"] == len(campaign["seeds"])).all()
    problems = fragment_problems(
        (workdir / SUMMARY).read_text(), (REPO / "docs/generated/flow_curve_summary.md").read_text()
    )
    assert not problems, problems


#: The curves at controlled stress (config/<study>.yaml, data/<study>) and their fragments in docs/generated
STRESS_CURVES = {
    "thickening_stress": "thickening_stress_flow_curve_summary.md",
    "thickening_stress_fresh": "thickening_stress_fresh_flow_curve_summary.md",
}


@pytest.mark.parametrize("study", sorted(STRESS_CURVES))
def test_the_flow_curve_at_controlled_stress_rebuilds_from_its_committed_datasets(tmp_path, study):
    """config/<study>.yaml with its reference config: every stress of the grid from data/<study>, no
    simulation, the docs' fragment as committed (the named test's shape line among it)."""
    fragment = STRESS_CURVES[study]
    configs = [f"config/{study}.yaml", f"config/{study}_reference.yaml"]
    workdir = copy_workflow(tmp_path)
    shutil.copytree(REPO / "data" / study, workdir / "data" / study)
    plan = snakemake(workdir, "-n", "--configfile", *configs)
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert "flow_curve" in rules and not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}, rules
    tables = workdir / f"results/{study}_reference/tables"
    summary = f"results/{study}_reference/tables/flow_curve_summary.md"
    result = snakemake(workdir, "--configfile", *configs, "--", summary, timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    campaign = load_layered_config([REPO / config for config in configs])
    table = pd.read_csv(tables / "flow_curve.csv")
    assert sorted(table["point"]) == sorted(campaign_points(campaign))
    assert (table["n_seeds"] == len(campaign["seeds"])).all()
    shape = pd.read_csv(tables / "flow_curve_shape.csv")
    assert set(shape["n_seeds"]) == {len(campaign["seeds"])}
    committed = (REPO / "docs/generated" / fragment).read_text()
    problems = fragment_problems((tables / "flow_curve_summary.md").read_text(), committed)
    assert not problems, problems
    if study == "thickening_stress":
        # docs/thickening.md: the named test's statistic (the curvature through 0.05, 0.1 and 0.2) on
        # seeds 1-4 has an interval containing 0, where their five-point fit lies above 0
        seeds = pd.read_csv(tables / "flow_curve_seeds.csv")
        three = flow_curve.curve_shape(seeds[seeds["target"].isin([0.05, 0.1, 0.2])], [0.05, 0.2])
        curvature = three.set_index("statistic").loc["curvature"]
        assert curvature["low"] < 0 < curvature["high"], curvature
        assert shape.set_index("statistic").loc["curvature", "low"] > 0
