"""The SLURM tests' cluster check and the study run on the cluster.

The study on SLURM (up to its fits) spends most of its time waiting on the scheduler's accounting,
not computing, so conftest.py starts it in the background as soon as the tests are collected (when a
test asks for it) and tests/workflow/test_slurm.py collects it; without a cluster nothing starts.
Under pytest-xdist the run is started once for the whole session, by the first worker to finish
collecting, and any worker can collect it: its record (``slurm_study.json``) and the run's exit
status are files, in the session's folder shared by the workers and in the run's own.
"""

from __future__ import annotations

import contextlib
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path

import pytest
from filelock import FileLock

from workflow_helpers import RESULTS, SNAKEMAKE, TEST_CONFIG, copy_workflow, session_folder

ENABLE = 'to run them: eval "$(bash envs/slurm_cluster.sh up)" (as root; starts a local cluster)'
PROFILE = ["--workflow-profile", "profiles/slurm"]
#: The record of the background run of the study, in the session's folder (session_folder).
SLURM_STUDY = "slurm_study.json"
#: What the run on the cluster makes: the test study up to its fits, every kind of job that simulates
#: or reduces (packings, segments, fabric and stress tables, aggregates, the fit). The rules after the
#: fits are script jobs of the same kind, and each SLURM job costs two Snakemake starts (the batch
#: script's and its job step's, about 3 s of CPU), which the rest of the study would more than double.
SLURM_STUDY_TARGETS = (
    f"{RESULTS}/fits.json",
    f"{RESULTS}/tables/rotation_aggregate.csv",
    f"{RESULTS}/tables/stress_startup_aggregate.csv",
)
#: The run's shell: Snakemake, then its exit status into a file, written whole (renamed into place).
WRAPPER = '"$@"; status=$?; echo $status > {0}.part && mv {0}.part {0}; exit $status'


def find_cluster() -> tuple[str, str] | str:
    """(account, partition) of a reachable cluster with accounting, else why not and how to get one."""
    missing = [tool for tool in ("sinfo", "sbatch", "sacct") if shutil.which(tool) is None]
    if missing:
        return f"no SLURM here ({', '.join(missing)} not on PATH); {ENABLE}"
    if importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
        return "the SLURM executor plugin is missing: bash envs/bootstrap.sh installs envs/cluster.txt"
    account, partition = os.environ.get("SBATCH_ACCOUNT"), os.environ.get("SBATCH_PARTITION")
    if not (account and partition):
        return f"SBATCH_ACCOUNT and SBATCH_PARTITION are not set; {ENABLE}"
    state = subprocess.run(["sinfo", "-h", "-p", partition, "-o", "%a"], capture_output=True, text=True)
    if state.returncode != 0 or state.stdout.strip() != "up":
        reason = state.stderr.strip().splitlines()[-1:] or ["not up"]
        return f"SLURM partition {partition!r}: {reason[0]}; {ENABLE}"
    accounting = subprocess.run(["sacct", "-n", "-X", "-S", "now"], capture_output=True, text=True)
    if accounting.returncode != 0:
        return f"no SLURM accounting (sacct: {accounting.stderr.strip()}); {ENABLE}"
    return account, partition


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    return True


@dataclass
class SlurmRun:
    """The cluster command of docs/workflow.md, running (no --cores: each job's threads are its
    own), in a process group of its own: a shell that runs Snakemake and then writes its exit
    status, so that a process other than the one that started it can wait for it and stop it."""

    workdir: Path
    pgid: int
    started: datetime

    @property
    def log_path(self) -> Path:
        return self.workdir / "snakemake_on_slurm.log"

    @property
    def status_path(self) -> Path:
        return self.workdir / "snakemake_on_slurm.returncode"

    @classmethod
    def start(cls, workdir: Path, *args: str) -> SlurmRun:
        started = datetime.now() - timedelta(minutes=1)
        run = cls(workdir, 0, started)
        with open(run.log_path, "w") as log:
            process = subprocess.Popen(
                ["bash", "-c", WRAPPER.format(run.status_path.name), "snakemake_on_slurm"]
                + [str(SNAKEMAKE), *TEST_CONFIG, *PROFILE, *args],
                cwd=workdir,
                stdout=log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
        run.pgid = process.pid
        _STARTED[process.pid] = process  # reaped by wait or stop when they run in this process
        return run

    def record(self) -> dict:
        return {"workdir": str(self.workdir), "pgid": self.pgid, "started": self.started.isoformat()}

    @classmethod
    def from_record(cls, record: dict) -> SlurmRun:
        return cls(Path(record["workdir"]), record["pgid"], datetime.fromisoformat(record["started"]))

    def _ended(self) -> bool:
        if self.status_path.is_file():
            return True
        process = _STARTED.get(self.pgid)
        if process is not None and process.poll() is None:
            return False
        return not _group_alive(self.pgid)

    def wait(self, timeout: float = 1800) -> tuple[int, str]:
        """(return code, Snakemake's log) once the run ends."""
        deadline = time.monotonic() + timeout
        while not self.status_path.is_file():
            if self._ended() and not self.status_path.is_file():
                log = self.log_path.read_text()[-4000:]
                raise AssertionError(f"the run on SLURM ended without an exit status:\n{log}")
            if time.monotonic() > deadline:
                raise subprocess.TimeoutExpired(f"snakemake in {self.workdir}", timeout)
            time.sleep(1.0)
        return int(self.status_path.read_text()), self.log_path.read_text()

    def stop(self) -> None:
        """Interrupt a run still going (Ctrl-C to its process group: Snakemake cancels its SLURM
        jobs), then kill it."""
        if self._ended():
            return
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.pgid, signal.SIGINT)
        deadline = time.monotonic() + 60
        while not self._ended():
            if time.monotonic() > deadline:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(self.pgid, signal.SIGKILL)
                break
            time.sleep(0.5)


#: The runs this process started, by process group, so that it reaps the ones it waits for.
_STARTED: dict[int, subprocess.Popen] = {}


def start_study_on_slurm(config: pytest.Config) -> None:
    """The whole test study on the cluster, in a fresh copy of the workflow, started once per
    session (the first of pytest-xdist's workers to get here starts it; the others find it)."""
    folder = session_folder(config._tmp_path_factory)
    with FileLock(folder / f"{SLURM_STUDY}.lock"):
        if not (folder / SLURM_STUDY).is_file():
            workdir = copy_workflow(Path(tempfile.mkdtemp(prefix="slurm_study_")))
            run = SlurmRun.start(workdir, "--", *SLURM_STUDY_TARGETS)
            (folder / SLURM_STUDY).write_text(json.dumps(run.record()))


def study_on_slurm(config: pytest.Config) -> SlurmRun | None:
    """The session's run of the study on the cluster, if started."""
    record = session_folder(config._tmp_path_factory) / SLURM_STUDY
    return SlurmRun.from_record(json.loads(record.read_text())) if record.is_file() else None
