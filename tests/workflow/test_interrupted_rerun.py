"""An interrupted rerun loses nothing: a setting changed, the rerun of the affected simulations
started and stopped (Ctrl-C, or the whole process group killed as when a session or a batch job
ends), and every finished run and every table is still there, byte for byte, and still the one
its metadata describes. Real Snakemake and LAMMPS on a copy of the finished test study.

Snakemake deletes a job's outputs when the job starts; the simulations' outputs carry the
`update` flag (workflow/rules/common.smk, run_outputs), so the finished run stays in place and
the runner replaces its folder only once the new run has finished."""

import os
import signal
import subprocess
import time

import pytest

from suspension_fabric.simulation.lammps.process import lammps_processes_in
from workflow_helpers import SNAKEMAKE, TEST_CONFIG, dry_run_jobs, result_digests, snakemake

pytestmark = pytest.mark.workflow

# long enough that no rotation can finish before the interrupt, which waits for a second Snakemake
# to start and be refused (several seconds on a loaded machine; the test study's rotations take
# ~0.5 s per strain)
SLOW_ROTATIONS = "run={rotation_strain: 600.0}"
LOCKED = "Directory cannot be locked"
ROTATIONS = {f"seed={s}, run=rotation_theta{a}" for s in (1, 2) for a in (0, 90)}


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
        # as started from a terminal: a test suite run in the background of a shell (nohup ... &)
        # inherits SIGINT ignored, and so would Snakemake and its jobs
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    try:
        while len(list((workdir / "results/test").glob("seed*/.rotation_theta*.partial/segment*"))) < 2:
            assert process.poll() is None, process.communicate()[0][-3000:]
            assert time.monotonic() < deadline, "the rotations did not start within 120 s"
            time.sleep(0.2)
        time.sleep(1.0)  # inside LAMMPS
        # a second Snakemake in the same folder meanwhile is refused by the first one's lock
        second = snakemake(workdir, *TEST_CONFIG)
        assert second.returncode != 0 and LOCKED in second.stderr, second.stderr[-2000:]
    finally:
        os.killpg(process.pid, signum)
        if signum == signal.SIGKILL:
            # LAMMPS runs in process groups of its own; a killed session or batch job takes them too
            for pid in lammps_processes_in(workdir):
                os.killpg(pid, signal.SIGKILL)
    output = process.communicate(timeout=120)[0]
    assert process.returncode != 0, output[-3000:]
    deadline = time.monotonic() + 30
    while lammps_processes_in(workdir):  # Ctrl-C: each runner stops its own
        assert time.monotonic() < deadline, "a LAMMPS run outlived the interrupt"
        time.sleep(0.2)
    return output


def started_runs(workdir):
    """The runs whose rerun had started: Snakemake deleted their completion markers (not flagged
    `update`), so that a rerun that did not finish is planned again whatever it recorded for it."""
    return {
        path.parent
        for path in (workdir / "results/test").glob("seed*/rotation_theta*/trajectory.dump")
        if not (path.parent / "run_complete.json").exists()
    }


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGKILL], ids=["ctrl-c", "killed"])
@pytest.mark.fault("survived")
def test_an_interrupted_rerun_keeps_every_finished_run_and_table(finished_study, signum):
    finished = finished_study
    before = result_digests(finished)
    start_and_interrupt(finished, signum)
    if signum == signal.SIGKILL:  # nobody removed Snakemake's lock: refused, naming the way out
        refused = snakemake(finished, *TEST_CONFIG)
        assert refused.returncode != 0 and LOCKED in refused.stderr and "--unlock" in refused.stderr
        assert snakemake(finished, *TEST_CONFIG, "--unlock").returncode == 0
    started = started_runs(finished)
    assert len(started) == 2  # one per core
    markers = {f"{run.relative_to(finished / 'results')}/run_complete.json" for run in started}
    assert result_digests(finished) == {name: d for name, d in before.items() if name not in markers}

    # the changed setting still reruns the rotations and what follows them
    result = snakemake(finished, *TEST_CONFIG, "--config", SLOW_ROTATIONS, "-n")
    assert result.returncode == 0, result.stderr[-3000:]
    planned = {job["wildcards"] for job in dry_run_jobs(result.stdout) if job["rule"] == "shear_segment"}
    assert planned == ROTATIONS

    # without the change the started runs are asked for as they are: the run puts their markers
    # back from the kept copies and simulates nothing, and every table is byte for byte as before.
    # After Ctrl-C the whole study is asked for, so what follows the restored runs is made again
    # from them; after the kill only the runs' markers (the run folders are already checked byte
    # for byte above, and the analysis of the same runs is the same)
    targets = [] if signum == signal.SIGINT else sorted(f"results/{marker}" for marker in markers)
    result = snakemake(finished, *targets, *TEST_CONFIG)
    assert result.returncode == 0, result.stderr[-3000:]
    logs = [(finished / f"results/test/logs/shear_{run.parent.name}_{run.name}.log").read_text() for run in started]
    assert all("kept, nothing simulated" in log for log in logs), logs
    # what follows the restored runs may be made again, the same (a PDF records its creation time)
    after = {name: digest for name, digest in result_digests(finished).items() if not name.endswith(".pdf")}
    assert after == {name: digest for name, digest in before.items() if not name.endswith(".pdf")}
