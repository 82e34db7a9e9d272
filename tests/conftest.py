"""Shared fixtures: the session's one real run of the test study (config/test.yaml), and the same
study on a SLURM cluster, started in the background when a test asks for it (slurm_helpers.py)."""

import shutil

import pytest

from slurm_helpers import SLURM_STUDY, find_cluster, start_study_on_slurm
from workflow_helpers import TEST_CONFIG, copy_workflow, snakemake

# The fault suite: bad input and faults, each test marked with how the case ends
# (benchmarks/fault_suite.py counts them by outcome for BENCHMARKS.md).
FAULT_OUTCOMES = {
    "refused": "refused before any job or computation, naming the file or key and what was expected",
    "adapted": "the study adapts to the input and says so",
    "named": "the step that meets the fault fails naming the file and the cause; nothing finished is lost",
    "survived": "a correct run: nothing finished is lost, nothing stale is kept",
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        for mark in item.iter_markers("fault"):
            if len(mark.args) != 1 or mark.args[0] not in FAULT_OUTCOMES:
                raise pytest.UsageError(f"{item.nodeid}: fault marker needs one outcome of {sorted(FAULT_OUTCOMES)}")


@pytest.fixture(scope="session")
def study(tmp_path_factory):
    """The whole test study, run for real once per test session (never change it in a test)."""
    workdir = copy_workflow(tmp_path_factory.mktemp("workflow"))
    result = snakemake(workdir, *TEST_CONFIG)
    assert result.returncode == 0, result.stderr[-4000:]
    return workdir


@pytest.fixture
def finished_study(study, tmp_path):
    """A copy of the finished test study (file times kept) that a test may change."""
    workdir = tmp_path / "checkout"
    shutil.copytree(study, workdir, symlinks=True)
    return workdir


def pytest_collection_finish(session):
    """Start the study on the cluster now, so that its scheduler waits overlap the other tests."""
    wanted = any("slurm_study" in getattr(item, "fixturenames", ()) for item in session.items)
    if wanted and not session.config.option.collectonly and isinstance(find_cluster(), tuple):
        session.config.stash[SLURM_STUDY] = start_study_on_slurm()


def pytest_sessionfinish(session):
    run = session.config.stash.get(SLURM_STUDY, None)
    if run is not None:
        run.stop()
        if session.testsfailed:
            print(f"\nthe study on SLURM is kept in {run.workdir}")
        else:
            shutil.rmtree(run.workdir, ignore_errors=True)
