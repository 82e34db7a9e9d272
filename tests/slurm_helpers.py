"""The SLURM tests' cluster check and the study run on the cluster.

The study on SLURM spends most of its three minutes waiting on the scheduler's accounting, not
computing, so conftest.py starts it in the background as soon as the tests are collected (when a
test asks for it) and tests/workflow/test_slurm.py collects it; without a cluster nothing starts.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import signal
import subprocess
import tempfile
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path

import pytest

from workflow_helpers import SNAKEMAKE, TEST_CONFIG, copy_workflow

ENABLE = 'to run them: eval "$(bash envs/slurm_cluster.sh up)" (as root; starts a local cluster)'
PROFILE = ["--workflow-profile", "profiles/slurm"]
#: Where conftest.py keeps the background run of the study (``config.stash``).
SLURM_STUDY = pytest.StashKey()


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


@dataclass
class SlurmRun:
    """The cluster command of docs/workflow.md, running (no --cores: each job's threads are its own)."""

    workdir: Path
    process: subprocess.Popen
    started: datetime
    log_path: Path

    @classmethod
    def start(cls, workdir: Path, *args: str) -> SlurmRun:
        started = datetime.now() - timedelta(minutes=1)
        log_path = workdir / "snakemake_on_slurm.log"
        with open(log_path, "w") as log:
            process = subprocess.Popen(
                [str(SNAKEMAKE), *TEST_CONFIG, *PROFILE, *args], cwd=workdir, stdout=log, stderr=subprocess.STDOUT
            )
        return cls(workdir, process, started, log_path)

    def wait(self, timeout: float = 1800) -> tuple[int, str]:
        """(return code, Snakemake's log) once the run ends."""
        return self.process.wait(timeout=timeout), self.log_path.read_text()

    def stop(self) -> None:
        """Interrupt a run still going (Snakemake cancels its SLURM jobs), then kill it."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                self.process.kill()


def start_study_on_slurm() -> SlurmRun:
    """The whole test study on the cluster, in a fresh copy of the workflow."""
    return SlurmRun.start(copy_workflow(Path(tempfile.mkdtemp(prefix="slurm_study_"))))
