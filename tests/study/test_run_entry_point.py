"""``python -m suspension_fabric.study.run``: the checks Snakemake makes before the Snakefile runs, with the
file, line or key named."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from suspension_fabric.study.config import ConfigError
from suspension_fabric.study.run import nested_config_args, snakemake_arguments


def test_dotted_config_keys_become_one_nested_entry_per_top_level_key():
    args = nested_config_args(["run.startup_strain=0.5", "seeds=[1,2]", "run.dt=1e-4", "analysis.steady_window=[1,2]"])
    assert args[0] == "seeds=[1,2]"
    nested = dict(entry.split("=", 1) for entry in args[1:])
    assert json.loads(nested["run"]) == {"startup_strain": 0.5, "dt": 1e-4}
    assert json.loads(nested["analysis"]) == {"steady_window": [1, 2]}


def test_a_key_under_a_value_given_before_is_refused_by_name():
    with pytest.raises(ConfigError, match="run.dt.x"):
        nested_config_args(["run.dt=1", "run.dt.x=2"])


def test_only_the_config_entries_change_and_every_configfile_is_read(tmp_path):
    good = tmp_path / "good.yaml"
    good.write_text("study: x\n")
    args = ["-n", "--configfile", str(good), "--config", "run.startup_strain=2", "--cores", "1"]
    assert snakemake_arguments(args) == [
        "-n", "--configfile", str(good), "--config", 'run={"startup_strain": 2}', "--cores", "1",
    ]  # fmt: skip


def test_a_yaml_error_in_a_configfile_is_named_with_its_line_before_snakemake_starts(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("study: x\nseeds: [1, 2\n")
    result = subprocess.run(
        [sys.executable, "-m", "suspension_fabric.study.run", "-n", "--configfile", str(bad)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 1
    assert f"{bad}, line 3" in result.stderr and "not valid YAML" in result.stderr


def test_the_snakefile_run_from_another_folder_says_where_its_files_are(tmp_path):
    from workflow_helpers import REPO

    snakemake = Path(sys.executable).with_name("snakemake")
    result = subprocess.run(
        [str(snakemake), "-s", str(REPO / "Snakefile"), "-n"], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    assert result.returncode != 0
    message = result.stdout + result.stderr
    assert f"relative to the working directory {tmp_path}" in message
    assert f"--directory {REPO}" in message
