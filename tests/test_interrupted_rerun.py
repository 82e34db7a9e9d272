"""An interrupted rerun loses nothing: a setting changed, the rerun of the affected simulations
started and stopped (Ctrl-C, or the whole process group killed as when a session or a batch job
ends), and every finished run and every table is still there, byte for byte, and still the one
its metadata describes. Real Snakemake and LAMMPS on a copy of the finished test study.

Snakemake deletes a job's outputs when the job starts; the simulations' outputs carry the
`update` flag (workflow/rules/common.smk, run_outputs), so the finished run stays in place and
the runner replaces its folder only once the new run has finished."""

import hashlib
import os
import shutil
import signal
import subprocess
import time

import pytest

from workflow_helpers import SNAKEMAKE, TEST_CONFIG, dry_run_jobs, snakemake

pytestmark = pytest.mark.workflow

# long enough that no rotation can finish before the interrupt (the test study's take ~0.1 s per 0.1 strain)
SLOW_ROTATIONS = "run={rotation_strain: 200.0}"
ROTATIONS = {f"seed={s}, run=rotation_theta{a}" for s in (1, 2) for a in (0, 90)}


def digests(workdir):
    """sha256 of every file under results/ but the job logs (Snakemake rewrites a started job's log)
    and the runner's hidden work folders (the interrupted runs' resume state)."""
    root = workdir / "results"
    return {
        str(path.relative_to(root)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(root.rglob("*"))
        if path.is_file() and not any(part == "logs" or part.startswith(".") for part in path.relative_to(root).parts)
    }


def start_and_interrupt(workdir, signum):
    """Start the rerun with rotations that cannot finish; once both cores run one (their partial
    folders exist), send ``signum`` to Snakemake's whole process group, as Ctrl-C in a terminal does."""
    process = subprocess.Popen(
        [str(SNAKEMAKE), "--cores", "2", *TEST_CONFIG, "--config", SLOW_ROTATIONS],
        cwd=workdir,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    try:
        while len(list((workdir / "results/test").glob("seed*/.rotation_theta*.partial/segment*"))) < 2:
            assert process.poll() is None, process.communicate()[0][-3000:]
            assert time.monotonic() < deadline, "the rotations did not start within 120 s"
            time.sleep(0.2)
        time.sleep(1.0)  # inside LAMMPS
    finally:
        os.killpg(process.pid, signum)
    output = process.communicate(timeout=120)[0]
    assert process.returncode != 0, output[-3000:]
    return output


@pytest.fixture
def finished(study, tmp_path):
    workdir = tmp_path / "checkout"
    shutil.copytree(study, workdir, symlinks=True)
    return workdir


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGKILL], ids=["ctrl-c", "killed"])
def test_an_interrupted_rerun_keeps_every_finished_run_and_table(finished, signum):
    before = digests(finished)
    start_and_interrupt(finished, signum)
    if signum == signal.SIGKILL:  # nobody removed Snakemake's lock
        shutil.rmtree(finished / ".snakemake/locks", ignore_errors=True)
    assert digests(finished) == before

    # the changed setting still reruns the rotations (their params differ) and what follows them
    result = snakemake(finished, *TEST_CONFIG, "--config", SLOW_ROTATIONS, "-n")
    assert result.returncode == 0, result.stderr[-3000:]
    planned = {job["wildcards"] for job in dry_run_jobs(result.stdout) if job["rule"] == "shear_segment"}
    assert planned == ROTATIONS

    # without the change the old runs are the study's: no output is missing or out of date; the
    # interrupted jobs run again only because Snakemake reruns a job it started and did not finish
    result = snakemake(finished, *TEST_CONFIG, "-n")
    assert result.returncode == 0, result.stderr[-3000:]
    reasons = [job["reason"] for job in dry_run_jobs(result.stdout) if job["rule"] == "shear_segment"]
    assert all(reason == "Forced execution" for reason in reasons), reasons
    assert "Missing output files" not in result.stdout
