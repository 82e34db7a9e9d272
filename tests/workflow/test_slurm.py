"""The study on a real SLURM cluster through Snakemake's SLURM executor: docs/workflow.md's cluster
command (profiles/slurm, account and partition from SBATCH_ACCOUNT and SBATCH_PARTITION) on the
test study up to its fits, checked against SLURM's accounting (sacct) and against a local run; and one
simulation on two MPI ranks as a two-task SLURM job.

Needs a cluster; on a machine without one these tests skip. As root on Debian,
`eval "$(bash envs/slurm_cluster.sh up)"` starts a single-node cluster on this machine and exports
the two variables (`.ci/run` does so); `bash envs/slurm_cluster.sh down` stops it.
"""

import re
import subprocess
from collections import Counter
from datetime import datetime
from pathlib import Path

import pytest

from slurm_helpers import SLURM_STUDY_TARGETS, SlurmRun, find_cluster, study_on_slurm
from workflow_helpers import RESULTS, copy_workflow, job_counts

pytestmark = [pytest.mark.slurm, pytest.mark.workflow]

SACCT_FIELDS = ["JobIDRaw", "State", "Account", "Partition", "AllocCPUS", "Comment", "SubmitLine"]


@pytest.fixture(scope="module")
def cluster():
    """(account, partition) of a reachable cluster with accounting, else skip saying how."""
    found = find_cluster()
    if isinstance(found, str):
        pytest.skip(found)
    return found


def finished(run: SlurmRun) -> str:
    """Snakemake's log of a run on the cluster, once it has succeeded."""
    returncode, log = run.wait()
    assert returncode == 0, log[-4000:]
    return log


def started_jobs(output: str) -> list[tuple[bool, str, str]]:
    """(local, rule, Snakemake job id) of every job the log says was started."""
    return [
        (bool(local), rule, jobid)
        for local, rule, jobid in re.findall(
            r"^(local)?rule (\w+):\n(?:    .*\n)*?    jobid: (\d+)$", output, flags=re.M
        )
    ]


def sbatch_submissions(output: str) -> list[tuple[str, str]]:
    """(Snakemake job id, SLURM job id) of every submission, from the executor's log lines."""
    return re.findall(r"^Job (\d+) has been submitted with SLURM jobid (\d+)", output, flags=re.M)


def sacct_jobs(output: str, started: datetime) -> dict[str, dict]:
    """SLURM's accounting record of every job of this Snakemake run (the executor names every
    job after the run's id and puts the rule and wildcards in its comment)."""
    run_id = re.search(r"SLURM run ID: (\S+)", output).group(1)
    table = subprocess.run(
        [
            "sacct",
            "-X",
            "-P",
            "-n",
            "--name",
            run_id,
            "-S",
            started.strftime("%Y-%m-%dT%H:%M:%S"),
            "-o",
            ",".join(SACCT_FIELDS),
        ],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rows = [dict(zip(SACCT_FIELDS, line.split("|", len(SACCT_FIELDS) - 1))) for line in table.splitlines()]
    return {row["JobIDRaw"]: row for row in rows}


def rule_of(comment: str) -> str:
    return re.fullmatch(r"rule_(\w+?)(?:_wildcards_.*)?", comment).group(1)


@pytest.fixture(scope="module")
def slurm_study(cluster, request):
    """The test study on the cluster: the run conftest.py started in the background at collection."""
    run = study_on_slurm(request.config)
    assert run is not None, "conftest.py starts the study on SLURM when the tests are collected"
    log = finished(run)
    return run.workdir, log, sacct_jobs(log, run.started)


def test_every_job_of_the_study_ran_as_a_completed_slurm_job(cluster, slurm_study):
    """Every job of the study up to its fits (slurm_helpers.SLURM_STUDY_TARGETS) went through sbatch
    exactly once, under the account and partition from the environment, and sacct reports each
    COMPLETED."""
    account, partition = cluster
    _, log, sacct = slurm_study
    jobs = started_jobs(log)
    counts = job_counts(log)
    assert counts.pop("total") == len(jobs) and Counter(rule for _, rule, _ in jobs) == counts
    assert not [rule for local, rule, _ in jobs if local]
    remote = {jobid: rule for local, rule, jobid in jobs if not local}
    submissions = sbatch_submissions(log)
    assert sorted(job for job, _ in submissions) == sorted(remote), "not every job submitted once"
    assert set(sacct) == {slurm_id for _, slurm_id in submissions}, "sbatch jobs missing from sacct"
    assert {row["State"] for row in sacct.values()} == {"COMPLETED"}
    assert {(row["Account"], row["Partition"]) for row in sacct.values()} == {(account, partition)}
    assert Counter(rule_of(row["Comment"]) for row in sacct.values()) == Counter(remote.values())
    assert {"pack", "shear_segment", "fabric_table", "stress_table", "aggregate_rotation", "fit_models"} <= set(
        remote.values()
    )


def test_slurm_results_equal_a_local_run(slurm_study, request):
    """fits.json and every table the run made equal those of the local run of the same config and
    seeds (the session's `study`) to the bit: each LAMMPS run is serial and deterministic."""
    workdir, _, _ = slurm_study
    # Requested only now: a session fixture as argument would run before the cluster check.
    on_slurm, local = workdir / RESULTS, request.getfixturevalue("study") / RESULTS
    tables = sorted(path.name for path in (on_slurm / "tables").glob("*.csv"))
    assert {Path(target).name for target in SLURM_STUDY_TARGETS if Path(target).parent.name == "tables"} <= set(tables)
    for name in ["fits.json"] + [f"tables/{table}" for table in tables]:
        assert (on_slurm / name).read_bytes() == (local / name).read_bytes(), name


def test_two_mpi_ranks_run_as_one_two_task_slurm_job(cluster, tmp_path):
    """run.mpi_ranks = 2 with the default engine (fix hydro/implicit/sf split over the ranks):
    one SLURM job of 2 tasks x 1 core on one node, in which LAMMPS runs on a 2-rank grid."""
    node_cpus = subprocess.run(
        ["sinfo", "-h", "-p", cluster[1], "-o", "%c"], capture_output=True, text=True, check=True
    ).stdout.split()
    if max(int(cpus.rstrip("+")) for cpus in node_cpus) < 2:
        pytest.skip("no node of the partition has 2 cores")
    workdir = copy_workflow(tmp_path)
    target = f"{RESULTS}/seed1/startup/run_complete.json"
    run = SlurmRun.start(
        workdir,
        "--config",
        "seeds=[1]",
        "run={mpi_ranks: 2}",
        "--",
        target,
    )
    sacct = sacct_jobs(finished(run), run.started)
    startup = [row for row in sacct.values() if rule_of(row["Comment"]) == "shear_segment"]
    assert len(startup) == 1
    job = startup[0]
    assert job["State"] == "COMPLETED"
    assert job["AllocCPUS"] == "2"
    for option in ("--ntasks=2", "--cpus-per-task=1", "--nodes=1"):
        assert option in job["SubmitLine"].split(), option
    log = (workdir / RESULTS / "seed1/startup/log.lammps").read_text()
    grid = re.search(r"(\d+) by (\d+) by (\d+) MPI processor grid", log)
    assert grid and int(grid[1]) * int(grid[2]) * int(grid[3]) == 2, grid
    assert re.search(r"CPU use with 2 MPI tasks", log)
