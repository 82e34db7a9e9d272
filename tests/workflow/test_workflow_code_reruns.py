"""What a moved or re-cloned checkout and an edit of the code rerun (docs/workflow.md, "What reruns a
job"), as dry runs on the finished test study (conftest.py).

Each test copies the study's workflow and results and the package's source tree (src/) with them,
the copy first on PYTHONPATH: the package then lives in the copy as it lives in a checkout it is
installed from in editable mode, so moving the copy moves the package's files, and an edit there
is an edit of the code the workflow runs (never of the repository's). Nothing is run for real.
"""

import os
import shutil
import time

import pytest

from workflow_helpers import REPO, TEST_CONFIG, copy_workflow, dry_run_jobs, job_counts, snakemake

pytestmark = pytest.mark.workflow

SIMULATIONS = {"pack", "shear_segment"}
SEEDS, RUNS = (1, 2), ("startup", "rotation_theta0", "rotation_theta90")
NOTHING = "Nothing to be done"
PARAMS = "Params have changed since last execution"


def with_package(workdir):
    """src/ copied into workdir; the environment in which Python imports the package from there."""
    shutil.copytree(REPO / "src", workdir / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    return {**os.environ, "PYTHONPATH": str(workdir / "src")}


def dry_run(workdir, env, *args):
    result = snakemake(workdir, *TEST_CONFIG, "-n", *args, env=env)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result.stdout + result.stderr


def planned(output):
    return {(job["rule"], job["wildcards"]): job["reason"] for job in dry_run_jobs(output) if job["rule"] != "all"}


@pytest.fixture
def moved(study, tmp_path):
    """The finished study copied to another path (file times kept), its package's source with it."""
    workdir = tmp_path / "elsewhere" / "checkout"
    shutil.copytree(study, workdir, symlinks=True)
    return workdir, with_package(workdir)


def fresh_clone(workdir):
    """The workflow and the package's source as a clone has them: every file new."""
    copy_workflow(workdir)
    env = with_package(workdir)
    now = time.time()
    for path in workdir.rglob("*"):
        os.utime(path, (now, now))
    return env


def copy_in(study, workdir, *names):
    for name in names:
        shutil.copytree(study / name, workdir / name)  # file times kept, as cp -a or rsync -a


@pytest.mark.fault("survived")
def test_a_moved_checkout_plans_no_job(moved):
    """Before: the plugin's sources were the plugin build's inputs by absolute path, so a checkout
    elsewhere changed its set of input files and reran the build and every simulation."""
    workdir, env = moved
    assert NOTHING in dry_run(workdir, env)


@pytest.mark.fault("survived")
def test_a_fresh_clone_with_the_results_copied_in_plans_no_job(study, tmp_path):
    """results/ alone suffices: the scripts' new file times rerun nothing (profiles/default drops
    Snakemake's script-time trigger) and the missing plugin library is not needed."""
    workdir = tmp_path / "clone"
    env = fresh_clone(workdir)
    copy_in(study, workdir, "results")
    assert NOTHING in dry_run(workdir, env)


@pytest.mark.fault("survived")
def test_a_fresh_clone_with_metadata_simulates_only_new_runs(study, tmp_path):
    """With .snakemake/metadata (the record of each job's inputs and params, without which later
    changes go unnoticed) copied in too, and no build/ (the plugin is no job's input: a segment
    builds it when it needs it): nothing planned, and an added angle simulates that angle alone,
    for real: the plugin is built into the clone's build/, and no finished run changes."""
    workdir = tmp_path / "clone"
    env = fresh_clone(workdir)
    copy_in(study, workdir, "results", ".snakemake/metadata")
    assert not (workdir / "build").exists()
    assert NOTHING in dry_run(workdir, env)
    added = ["--config", "angles_deg=[0, 90, 45]"]
    jobs = planned(dry_run(workdir, env, *added))
    simulations = {job for job in jobs if job[0] in SIMULATIONS}
    assert simulations == {("shear_segment", f"seed={s}, run=rotation_theta45") for s in SEEDS}

    finished = {path: path.read_bytes() for path in (workdir / "results/test").glob("seed*/*/*")}
    result = snakemake(workdir, *TEST_CONFIG, *added, env=env)
    assert result.returncode == 0, result.stderr[-3000:]
    assert job_counts(result.stdout + result.stderr)["shear_segment"] == len(SEEDS)
    assert (workdir / "build/plugin/libsuspension_fabric_lammps.so").is_file()
    assert all(path.read_bytes() == content for path, content in finished.items())


@pytest.mark.fault("survived")
def test_an_edit_of_the_fabric_analysis_reruns_the_fabric_tables_and_what_follows(moved):
    """A comment or a docstring changes no code: nothing planned. A new function in
    analysis/fabric.py: every fabric table for its changed params (its code version), and every job
    after them, which is every job but the simulations: their overlap check uses the module, but
    only accepts or refuses a finished run."""
    workdir, env = moved
    fabric = workdir / "src/suspension_fabric/analysis/fabric.py"
    source = fabric.read_text()
    assert source.startswith('r"""Near-contact')
    fabric.write_text(source.replace('r"""Near-contact', 'r"""Near (gap below eps) contact', 1) + "\n# a comment\n")
    assert NOTHING in dry_run(workdir, env)
    fabric.write_text(source + "\n\ndef _unused():\n    return None\n")
    jobs = planned(dry_run(workdir, env))
    tables = {job: reason for job, reason in jobs.items() if job[0] == "fabric_table"}
    assert set(tables) == {("fabric_table", f"seed={s}, run={run}") for s in SEEDS for run in RUNS}
    assert all(reason.startswith(PARAMS) for reason in tables.values()), tables
    everything = planned(dry_run(workdir, env, "--forceall"))
    assert set(jobs) == {job for job in everything if job[0] not in SIMULATIONS}


@pytest.mark.fault("survived")
def test_an_edit_of_a_lammps_input_reruns_the_simulations(moved):
    """segment.lmp edited: the packings and every segment (the packings for their params, the
    segments after them), and everything downstream; the plugin is not rebuilt."""
    workdir, env = moved
    segment = workdir / "src/suspension_fabric/simulation/lammps/inputs/segment.lmp"
    segment.write_text(segment.read_text() + "\nvariable unused_edit equal 0\n")
    jobs = planned(dry_run(workdir, env))
    assert {job for job in jobs if job[0] in SIMULATIONS} == {
        *(("pack", f"seed={s}") for s in SEEDS),
        *(("shear_segment", f"seed={s}, run={run}") for s in SEEDS for run in RUNS),
    }
    assert all(jobs[("pack", f"seed={s}")].startswith(PARAMS) for s in SEEDS)


@pytest.mark.fault("survived")
def test_an_edit_of_the_plugin_reruns_the_segments(moved):
    """A plugin source edited: every segment for its params (the plugin's version); the packings,
    which do not load the plugin, are kept."""
    workdir, env = moved
    header = workdir / "src/suspension_fabric/simulation/lammps/plugin_source/lubrication.h"
    header.write_text(header.read_text() + "\n// edited\n")
    jobs = planned(dry_run(workdir, env))
    assert {job for job in jobs if job[0] in SIMULATIONS} == {
        ("shear_segment", f"seed={s}, run={run}") for s in SEEDS for run in RUNS
    }
    assert all(jobs[("shear_segment", f"seed={s}, run=startup")].startswith(PARAMS) for s in SEEDS)
