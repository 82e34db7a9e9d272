"""The committed reference dataset (data/reference, exported from config/paper.yaml) and the
study that rebuilds the paper's figures and the stress figures from it (config/reference.yaml):
no simulation job in its plan, every run's files present with their recorded checksums, and its
fits equal to the ones recorded with the data."""

from __future__ import annotations

import json
import shutil

import pandas as pd
import pytest

from suspension_fabric.config import load_config
from suspension_fabric.dataset import check_config_matches, has_run_tables, read_dataset, run_names
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

DATASET = REPO / "data" / "reference"


def test_the_dataset_is_complete_and_small():
    record = read_dataset(DATASET)
    config = load_config(REPO / "config" / "reference.yaml")
    check_config_matches(config, record, DATASET)
    assert record["runs_missing"] == [] and record["fits"] is not None
    assert len(record["files"]) == 4 * len(run_names(config))
    assert has_run_tables(record, "fabric.csv") and has_run_tables(record, "stress.csv")
    size = sum(p.stat().st_size for p in DATASET.rglob("*") if p.is_file())
    assert size < 10e6, f"{size / 1e6:.1f} MB"


def test_the_reference_study_rebuilds_the_fits_without_simulating(tmp_path):
    workdir = copy_workflow(tmp_path)
    shutil.copytree(REPO / "data", workdir / "data")  # the reference and the datasets it is compared with
    plan = snakemake(workdir, "--configfile", "config/reference.yaml", "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert not rules & {"build_plugin", "pack", "startup", "rotate", "fabric_table", "stress_table"}, rules
    assert {"stress_relation", "figure_stress_startup", "figure_stress_rotation"} <= rules, rules
    result = snakemake(workdir, "--configfile", "config/reference.yaml", timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    fits = json.loads((workdir / "results/reference/fits.json").read_text())
    recorded = read_dataset(DATASET)["fits"]
    for model, parameter in (("gw", "beta"), ("modified", "beta"), ("modified", "A")):
        assert fits[model][parameter] == pytest.approx(recorded[model][parameter], rel=1e-12)
    assert (workdir / "results/reference/tables/verdicts.csv").is_file()
    choices = pd.read_csv(workdir / "results/reference/tables/verdict_choices.csv")
    assert set(load_config(REPO / "config" / "reference.yaml")["verdicts"]["comparisons"]) <= set(choices["choice"])
    for figure in ("fig3_stress.png", "fig4_stress_rotation.png"):
        assert (workdir / "results/reference/figures" / figure).is_file()
