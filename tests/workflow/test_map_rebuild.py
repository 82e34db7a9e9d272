"""The map over the state point rebuilt from the campaign's committed datasets (config/campaign.yaml
with config/map.yaml, data/campaign), as docs/map.md shows it: no simulation job, every point the
campaign config runs, and the Markdown summary the page includes (docs/generated/map_summary.md)
equal to the one the rebuild writes.

A point's rows of the summary depend on its own dataset alone, except for the claims table's Holm
brackets, which adjust over every cell of the map at once. CI rebuilds three points (the dilute
corner, the paper's point and the densest frictional point: a minute) and compares their rows with
the committed ones, the Holm brackets left out; the whole map (15 points, four minutes on 2 cores)
runs with ``pytest -m full_rebuild``, which compares the whole fragment."""

import re
import shutil

import pandas as pd
import pytest

from quoted_numbers import fragment_problems
from suspension_fabric.study.campaign import campaign_points
from suspension_fabric.study.config import load_config
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

MAP_CONFIG = ["--configfile", "config/campaign.yaml", "config/map.yaml"]
SUMMARY = "results/map/tables/map_summary.md"
#: The points CI rebuilds, and how the summary's first column names them
CI_POINTS = {"phi0.40_mu0": "0.40, 0", "phi0.45_mu0.5": "0.45, 0.5", "phi0.55_mu1": "0.55, 1"}
_HOLM = re.compile(r" \(Holm: [a-z]+\)")


def rebuild_map(tmp_path, *points):
    """The map rebuilt in a copy of the workflow from data/campaign (``points``: only those), after a
    dry run that plans no simulation job; the rebuild's folder."""
    workdir = copy_workflow(tmp_path)
    shutil.copytree(REPO / "data" / "campaign", workdir / "data" / "campaign")
    subset = ["--config", f"campaign={{points: [{', '.join(points)}]}}"] if points else []
    plan = snakemake(workdir, "-n", *MAP_CONFIG, *subset, "--", SUMMARY)
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}, rules
    result = snakemake(workdir, *MAP_CONFIG, *subset, "--", SUMMARY, timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    return workdir


def rows_of(summary: str, label: str) -> list[str]:
    """The summary's table rows of one point (first cell ``label``), Holm brackets removed."""
    return [_HOLM.sub("", line) for line in summary.splitlines() if line.startswith(f"| {label} |")]


def test_three_points_of_the_map_rebuild_from_their_datasets_as_the_docs_show_them(tmp_path):
    workdir = rebuild_map(tmp_path, *CI_POINTS)
    table = pd.read_csv(workdir / "results/map/tables/map.csv")
    assert sorted(table["point"]) == sorted(CI_POINTS)
    made, committed = (workdir / SUMMARY).read_text(), (REPO / "docs/generated/map_summary.md").read_text()
    for label in CI_POINTS.values():
        mine, theirs = rows_of(made, label), rows_of(committed, label)
        assert len(mine) == len(theirs) == 2, (label, mine, theirs)  # the state row and the claims row
        for made_row, committed_row in zip(mine, theirs):
            problems = fragment_problems(made_row, committed_row)
            assert not problems, (label, problems)


@pytest.mark.full_rebuild
def test_the_map_rebuilds_from_the_committed_datasets_as_the_docs_show_it(tmp_path):
    workdir = rebuild_map(tmp_path)
    campaign = load_config(REPO / "config" / "campaign.yaml")
    table = pd.read_csv(workdir / "results/map/tables/map.csv")
    simulated = table[~table["steady"].str.startswith("not run")]
    assert sorted(simulated["point"]) == sorted(campaign_points(campaign))
    assert set(table["point"]) - set(simulated["point"]) == set(campaign["campaign"]["not_run"])
    problems = fragment_problems((workdir / SUMMARY).read_text(), (REPO / "docs/generated/map_summary.md").read_text())
    assert not problems, problems
