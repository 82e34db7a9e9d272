"""The committed protocols dataset (data/protocols, exported from config/protocols.yaml) and the
study that rebuilds its protocols' tables and figures from it (config/protocols_reference.yaml):
every file with its recorded checksum, the runs of every protocol the rebuild takes present, no
simulation job in its plan, and the results fragment the docs include equal to the one the rebuild
writes."""

from __future__ import annotations

import shutil

import pytest

from quoted_numbers import fragment_problems
from suspension_fabric.reporting.protocol_report import states_markdown
from suspension_fabric.study.config import load_config
from suspension_fabric.study.dataset import _checked_file, check_config_matches, read_dataset, run_names
from workflow_helpers import FLOAT_CONFIGS, REPO, copy_workflow, dry_run_jobs, snakemake

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


# the second floating-point configuration's run takes 80 s: CI runs it for the reference rebuild
# (test_reference.py), whose fits are the flattest; this one's with `-m full_rebuild`
@pytest.mark.parametrize("float_config", ["native", pytest.param("second", marks=pytest.mark.full_rebuild)])
def test_the_rebuild_plans_no_simulation_and_writes_the_documented_results(tmp_path, float_config):
    env = FLOAT_CONFIGS[float_config]()
    workdir = copy_workflow(tmp_path)
    shutil.copytree(DATASET, workdir / "data" / "protocols")
    shutil.copytree(REPO / "data" / "models", workdir / "data" / "models")  # the sparse model it scores
    plan = snakemake(workdir, "--configfile", CONFIG, "-n", env=env)
    assert plan.returncode == 0, (plan.stdout + plan.stderr)[-3000:]
    rules = {job["rule"] for job in dry_run_jobs(plan.stdout + plan.stderr)}
    assert not rules & {"pack", "shear_segment", "fabric_table", "stress_table"}, rules
    assert {"aggregate_protocols", "benchmark_protocols", "figure_protocol", "report_protocols"} <= rules
    target = "results/protocols_reference/tables/protocol_summary.md"
    result = snakemake(workdir, target, "--configfile", CONFIG, timeout=900, env=env)
    assert result.returncode == 0, result.stderr[-3000:]
    committed = (REPO / "docs/generated/protocol_summary.md").read_text()
    problems = fragment_problems((workdir / target).read_text(), committed)
    assert not problems, problems


def test_the_late_state_table_reads_each_difference_after_holm_over_the_list():
    """states_markdown: one row per segment after the startup, each quantity's seed mean with its
    paired difference from the startup's steady state, read "lower" or "higher" where its p-value
    adjusted by Holm over every difference of the list is below 0.05, else "not decided": p = 0.001,
    0.6 and 0.04 over three cells adjust to 0.003, 0.6 and 0.08, so the third, whose interval
    excludes 0, is not decided; the startup's steady values in the first row."""
    import pandas as pd

    cells = {"Z": (-0.2, -0.25, -0.15, 0.001), "eta_r": (0.1, -0.5, 0.7, 0.6), "n12": (0.01, 0.001, 0.02, 0.04)}
    rows = []
    for quantity, (mean, low, high, p) in cells.items():
        rows.append(
            {
                "protocol": "rotary_90",
                "segment": 1,
                "flow_angle_deg": 0.0,
                "turning_deg_per_strain": 90.0,
                "window_low": 2.5,
                "window_high": 5.0,
                "quantity": quantity,
                "mean": {"Z": 3.3, "eta_r": 15.7, "n12": -0.09}[quantity],
                "startup_steady": {"Z": 3.5, "eta_r": 15.6, "n12": -0.1}[quantity],
                "difference": mean,
                "difference_low": low,
                "difference_high": high,
                "difference_p": p,
            }
        )
    lines = states_markdown(pd.DataFrame(rows), 0.95)
    assert "| startup steady state | | 3.5 | -0.1 | 15.6 |" in lines
    assert (
        "| 1: flow at 0 deg, turning 90 deg/strain | 2.5-5 | 3.3 (-0.2 [-0.25, -0.15] lower) | "
        "-0.09 (0.01 [0.001, 0.02] not decided) | 15.7 (0.1 [-0.5, 0.7] not decided) |" in lines
    )
