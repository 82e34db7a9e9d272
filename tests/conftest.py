"""Shared fixtures: the session's one real run of the test study (config/test.yaml), and the same
study on a SLURM cluster, started in the background when a test asks for it (slurm_helpers.py).
The suite runs on two pytest-xdist workers (pyproject.toml, addopts): each is run once for the
whole session all the same, in the folder the workers share."""

import json
import shutil

import pytest
from filelock import FileLock

from slurm_helpers import find_cluster, start_study_on_slurm, study_on_slurm
from workflow_helpers import TEST_CONFIG, copy_workflow, session_folder, snakemake

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
    if hasattr(config, "workerinput"):
        # A pytest-xdist worker (each collects the same order; --dist loadfile hands out whole modules
        # in it): the modules that run real workflows first, then those that run LAMMPS, then the
        # rest, so that the last modules, which one worker may run while the other has finished, are
        # short ones. A stable sort: the order within a module and among modules of a kind stays.
        weight = {}
        for item in items:
            kind = 2 if item.get_closest_marker("workflow") else 1 if item.get_closest_marker("lammps") else 0
            weight[item.path] = max(weight.get(item.path, 0), kind)
        items.sort(key=lambda item: -weight[item.path])


@pytest.fixture(scope="session")
def study(tmp_path_factory):
    """The whole test study, run for real once per test session (never change it in a test).

    Under pytest-xdist the first worker to ask runs it and the others wait for it (a file lock);
    each worker then takes a copy of its own (file times kept), as the tests run Snakemake in it
    (dry runs, reports) and two such runs in one folder at once would meet each other's lock."""
    folder = session_folder(tmp_path_factory)
    shared, outcome = folder / "study", folder / "study.json"
    with FileLock(folder / "study.lock"):
        if not outcome.is_file():
            shutil.rmtree(shared, ignore_errors=True)  # left by an attempt that raised (a timeout)
            result = snakemake(copy_workflow(shared), *TEST_CONFIG)
            outcome.write_text(json.dumps({"returncode": result.returncode, "stderr": result.stderr[-4000:]}))
    result = json.loads(outcome.read_text())
    assert result["returncode"] == 0, result["stderr"]
    if folder == tmp_path_factory.getbasetemp():
        return shared  # no pytest-xdist: this process is the session
    workdir = tmp_path_factory.mktemp("workflow") / "study"
    shutil.copytree(shared, workdir, symlinks=True)
    return workdir


@pytest.fixture
def finished_study(study, tmp_path):
    """A copy of the finished test study (file times kept) that a test may change."""
    workdir = tmp_path / "checkout"
    shutil.copytree(study, workdir, symlinks=True)
    return workdir


def pytest_collection_finish(session):
    """Start the study on the cluster now, so that its scheduler waits overlap the other tests
    (under pytest-xdist each worker collects; the first to get here starts it)."""
    wanted = any("slurm_study" in getattr(item, "fixturenames", ()) for item in session.items)
    if wanted and not session.config.option.collectonly and isinstance(find_cluster(), tuple):
        start_study_on_slurm(session.config)


def pytest_sessionfinish(session):
    if hasattr(session.config, "workerinput"):
        return  # a pytest-xdist worker: the controller stops the run, once every worker has finished
    run = study_on_slurm(session.config)
    if run is not None:
        run.stop()
        if session.testsfailed:
            print(f"\nthe study on SLURM is kept in {run.workdir}")
        else:
            shutil.rmtree(run.workdir, ignore_errors=True)
