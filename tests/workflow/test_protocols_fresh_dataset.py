"""The protocols on fresh seeds (data/protocols_fresh, exported from config/protocols_fresh.yaml) and
the study that rebuilds their tables from it (config/protocols_fresh_reference.yaml): seeds in no
other dataset, every file with its recorded checksum, no simulation in the rebuild's plan, every
protocol score held out (the fits are the reference's, data/models/reference_parameters.csv, which
saw seeds 1-16 only), and the results fragments the docs include (the protocols' and the map's
transfer model's) equal to the rebuild's."""

from __future__ import annotations

import json
import shutil

import pandas as pd
import pytest

from quoted_numbers import fragment_problems
from suspension_fabric.study.config import load_config
from suspension_fabric.study.dataset import _checked_file, check_config_matches, read_dataset, run_names
from workflow_helpers import REPO, copy_workflow, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

DATASET = REPO / "data" / "protocols_fresh"
CONFIG = "config/protocols_fresh_reference.yaml"


def test_its_seeds_are_in_no_other_dataset_and_it_serves_the_rebuild():
    record = read_dataset(DATASET)
    config = load_config(REPO / CONFIG)
    check_config_matches(config, record, DATASET)
    assert record["runs_missing"] == []
    assert set(run_names(config)) <= {key.rsplit("/", 1)[0] for key in record["files"]}
    for key in record["files"]:
        _checked_file(DATASET, record, key)
    others = [path for path in REPO.glob("data/**/dataset.json") if path.parent != DATASET]
    assert len(others) > 10
    for path in others:
        seeds = set(json.loads(path.read_text())["config"]["seeds"])
        assert not seeds & set(record["config"]["seeds"]), path
    size = sum(p.stat().st_size for p in DATASET.rglob("*") if p.is_file())
    assert size < 60e6, f"{size / 1e6:.1f} MB"


def test_the_rebuild_scores_every_protocol_held_out_as_the_docs_show_it(tmp_path):
    workdir = copy_workflow(tmp_path)
    shutil.copytree(DATASET, workdir / "data" / "protocols_fresh")
    shutil.copytree(REPO / "data" / "models", workdir / "data" / "models")
    plan = snakemake(workdir, "--configfile", CONFIG, "-n")
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}, rules
    target = "results/protocols_fresh_reference/tables/protocol_summary.md"
    transfer = "results/protocols_fresh_reference/tables/transfer_protocols.md"
    result = snakemake(workdir, target, transfer, "--configfile", CONFIG, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    board = pd.read_csv(workdir / "results/protocols_fresh_reference/tables/protocol_leaderboard.csv")
    assert board["held_out"].all() and (board["seeds_seen"] == 0).all()
    assert set(board["fitted_on"]) == {"reference"}
    committed = (REPO / "docs/generated/protocol_fresh_summary.md").read_text()
    problems = fragment_problems((workdir / target).read_text(), committed)
    assert not problems, problems
    # the map's transfer model (data/models/transfer_map.json) saw N = 500 packings, none of these seeds
    committed = (REPO / "docs/generated/transfer_protocols.md").read_text()
    problems = fragment_problems((workdir / transfer).read_text(), committed)
    assert not problems, problems
