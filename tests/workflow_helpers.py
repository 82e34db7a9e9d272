"""Helpers of the workflow tests: a copy of the workflow in a temporary folder, Snakemake runs,
the parsed dry-run output, and the session's one real run of the test study (conftest.py)."""

import hashlib
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = Path(sys.executable).with_name("snakemake")
TEST_CONFIG = ["--configfile", "config/test.yaml"]
RESULTS = "results/test"


def second_float_config() -> dict[str, str]:
    """The environment of a second floating-point configuration on this machine: OpenBLAS's oldest
    x86_64 kernels (Prescott: SSE3, no FMA) in place of those it picks for the processor, and
    NumPy's dispatched SIMD loops off (baseline only), so that sums and products round as on
    another processor. The rebuilds run under it must print every fragment's digits as committed."""
    from numpy._core._multiarray_umath import __cpu_dispatch__

    env = dict(os.environ, OPENBLAS_CORETYPE="Prescott")
    if __cpu_dispatch__:
        env["NPY_DISABLE_CPU_FEATURES"] = " ".join(__cpu_dispatch__)
    return env


#: The floating-point configurations the rebuild tests run under: the machine's own, and a second.
FLOAT_CONFIGS = {"native": lambda: None, "second": second_float_config}


def session_folder(tmp_path_factory) -> Path:
    """The test session's temporary folder: pytest's base folder, or under pytest-xdist the one that
    holds each worker's base folder, where what one worker makes for the whole session is found by
    the others (conftest.py's study, the docs site)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def snakemake(workdir, *args, timeout=900, env=None):
    """Snakemake in workdir; ``env`` (a dict) replaces the environment, e.g. to add PYTHONPATH."""
    return subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *args], cwd=workdir, capture_output=True, text=True, timeout=timeout, env=env
    )


def job_counts(output: str) -> dict[str, int]:
    """The 'job  count' table that Snakemake prints before running (or in a dry run)."""
    table = output[output.index("job ") :]
    counts = {}
    for line in table.splitlines()[2:]:
        match = re.fullmatch(r"(\w+)\s+(\d+)", line.strip())
        if not match:
            break
        counts[match.group(1)] = int(match.group(2))
    return counts


def copy_workflow(target: Path) -> Path:
    for name in ("config", "workflow", "envs", "profiles"):
        shutil.copytree(REPO / name, target / name, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(REPO / "Snakefile", target / "Snakefile")
    return target


def dry_run_jobs(output: str) -> list[dict]:
    """Jobs of a dry run's output: rule, study, the other wildcards (text) and reason of each."""
    jobs = []
    for block in re.split(r"\n(?=(?:local)?rule \w+:\n)", output):
        match = re.match(r"(?:local)?rule (\w+):\n", block)
        if not match:
            continue
        fields = dict(re.findall(r"^    (\w+): (.*)$", block, flags=re.M))
        # every study rule carries the study's name first (one config may hold several studies)
        study, wildcards = re.fullmatch(r"(?:study=([^,]*)(?:, |$))?(.*)", fields.get("wildcards", "")).groups()
        jobs.append(
            {"rule": match.group(1), "study": study, "wildcards": wildcards, "reason": fields.get("reason", "")}
        )
    return jobs


def result_digests(workdir: Path) -> dict[str, str]:
    """sha256 of every file under results/ but the job logs (Snakemake rewrites a started job's log)
    and the runner's hidden work folders (an unfinished run's resume state)."""
    root = workdir / "results"
    return {
        str(path.relative_to(root)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(root.rglob("*"))
        if path.is_file() and not any(part == "logs" or part.startswith(".") for part in path.relative_to(root).parts)
    }
