"""The committed protocols dataset (data/protocols, exported from config/protocols.yaml) and the
study that rebuilds its protocols' tables and figures from it (config/protocols_reference.yaml):
every file with its recorded checksum, the runs of every protocol the rebuild takes present, no
simulation job in its plan, and the results fragment the docs include equal to the one the rebuild
writes."""

from __future__ import annotations

import shutil

import pytest

from suspension_fabric.study.config import load_config
from suspension_fabric.study.dataset import _checked_file, check_config_matches, read_dataset, run_names
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

DATASET = REPO / "data" / "protocols"
CONFIG = "config/protocols_reference.yaml"


def test_the_dataset_serves_the_rebuild_and_is_small():
    record = read_dataset(DATASET)
    config = load_config(REPO / CONFIG)
    check_config_matches(config, record, DATASET)
    needed = set(run_names(config))
    assert needed <= {key.rsplit("/", 1)[0] for key in record["files"]}
    for key in record["files"]:
        _checked_file(DATASET, record, key)
    size = sum(p.stat().st_size for p in DATASET.rglob("*") if p.is_file())
    assert size < 20e6, f"{size / 1e6:.1f} MB"


def test_the_rebuild_plans_no_simulation_and_writes_the_documented_results(tmp_path):
    workdir = copy_workflow(tmp_path)
    shutil.copytree(DATASET, workdir / "data" / "protocols")
    plan = snakemake(workdir, "--configfile", CONFIG, "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert not rules & {"build_plugin", "pack", "shear_segment", "fabric_table", "stress_table"}, rules
    assert {"aggregate_protocols", "benchmark_protocols", "figure_protocol", "report_protocols"} <= rules
    target = "results/protocols_reference/tables/protocol_summary.md"
    result = snakemake(workdir, target, "--configfile", CONFIG, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    assert (workdir / target).read_text() == (REPO / "docs" / "generated" / "protocol_summary.md").read_text()
