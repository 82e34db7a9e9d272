"""Shared fixtures: the session's one real run of the test study (config/test.yaml)."""

import pytest

from workflow_helpers import TEST_CONFIG, copy_workflow, snakemake


@pytest.fixture(scope="session")
def study(tmp_path_factory):
    """The whole test study, run for real once per test session (never change it in a test)."""
    workdir = copy_workflow(tmp_path_factory.mktemp("workflow"))
    result = snakemake(workdir, *TEST_CONFIG)
    assert result.returncode == 0, result.stderr[-4000:]
    return workdir
