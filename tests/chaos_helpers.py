"""A study run to completion while being killed at random moments (tests/workflow/test_chaos.py at
the test size, benchmarks/chaos.py at full size).

Each round starts Snakemake on the study, waits a random time, and SIGKILLs one of three kinds of
victim, drawn at random: the workflow (Snakemake's whole process group, and the LAMMPS runs, which
run in process groups of their own, as when a session or a batch job is killed), one running
LAMMPS simulation, or one running analysis job (a Python job script of the workflow other than a
simulation's runner). Then it waits for Snakemake to stop (after a job's death it finishes the
jobs still running and exits), removes the lock a killed Snakemake leaves (`snakemake --unlock`,
the documented recovery), and starts the next round. After the last kill a final run completes the
study. Every random choice comes from one seeded generator, so a seed replays the same schedule
(the moments the kills land at still depend on the machine's speed).
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import signal
import subprocess
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from suspension_fabric.simulation.lammps.process import lammps_processes_in
from workflow_helpers import SNAKEMAKE

#: The kinds of victim a round draws from.
KINDS = ("workflow", "lammps", "analysis")
#: Job scripts that run a simulation (their process is the runner, not an analysis).
SIMULATION_SCRIPTS = ("shear.py", "pack.py")


@dataclass
class Kill:
    """One round: its kind, the delay drawn (s), what was killed (``victim``: a command, or
    "nothing" when the study finished first) and how Snakemake ended."""

    round: int
    kind: str
    delay: float
    victim: str
    snakemake_exit: int | None


def analysis_processes_in(folder: Path) -> list[tuple[int, str]]:
    """(pid, script name) of the running job scripts of the workflow in ``folder`` that are not
    simulation runners: Snakemake runs each script job as ``python .snakemake/scripts/tmpXXXX.<name>.py``."""
    found = []
    root = str(Path(folder).resolve())
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            cwd = os.readlink(entry / "cwd")
            arguments = [a.decode() for a in (entry / "cmdline").read_bytes().split(b"\0") if a]
        except OSError:
            continue
        scripts = [a for a in arguments if "/.snakemake/scripts/" in a]
        if cwd.startswith(root) and scripts and not scripts[0].endswith(SIMULATION_SCRIPTS):
            found.append((int(entry.name), Path(scripts[0]).name.split(".", 1)[-1]))
    return found


def _start(workdir: Path, arguments: list[str]) -> subprocess.Popen:
    return subprocess.Popen(
        [str(SNAKEMAKE), "--cores", "2", *arguments],
        cwd=workdir,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )


def _kill_workflow(workdir: Path, process: subprocess.Popen) -> None:
    os.killpg(process.pid, signal.SIGKILL)
    for pid in lammps_processes_in(workdir):
        os.killpg(pid, signal.SIGKILL)


def _victim(workdir: Path, kind: str, process: subprocess.Popen, wait: float) -> str | None:
    """Kill one victim of ``kind``, waiting up to ``wait`` s for one to run; its description, or
    None if none ran by then."""
    deadline = time.monotonic() + wait
    while process.poll() is None:
        if kind == "workflow":
            _kill_workflow(workdir, process)
            return "snakemake"
        if kind == "lammps" and (running := lammps_processes_in(workdir)):
            os.killpg(running[0], signal.SIGKILL)
            return "lmp"
        if kind == "analysis" and (jobs := analysis_processes_in(workdir)):
            pid, script = jobs[0]
            os.kill(pid, signal.SIGKILL)
            return script
        if time.monotonic() > deadline:
            return None
        time.sleep(0.05)
    return None


def chaos_run(
    workdir: Path, arguments: list[str], kills: int, seed: int, max_delay: float, timeout: float = 900.0
) -> tuple[list[Kill], int]:
    """Rounds of start-and-kill on the study in ``workdir`` (Snakemake ``arguments``) until
    ``kills`` victims have been killed or the study finished, then a final run; returns the rounds
    and the final run's exit status."""
    rng = random.Random(seed)
    rounds: list[Kill] = []
    landed, started = 0, time.monotonic()
    while landed < kills and time.monotonic() - started < timeout:
        kind, delay = rng.choice(KINDS), rng.uniform(0.5, max_delay)
        process = _start(workdir, arguments)
        try:
            process.wait(timeout=delay)
        except subprocess.TimeoutExpired:
            pass
        victim = _victim(workdir, kind, process, wait=max_delay)
        if victim is None and process.poll() is None:  # no victim of that kind ran: the workflow instead
            kind, victim = "workflow", "snakemake"
            _kill_workflow(workdir, process)
        exit_status = process.wait(timeout=timeout)
        rounds.append(Kill(len(rounds), kind, round(delay, 3), victim or "nothing", exit_status))
        if victim is None:
            break  # the study finished before the kill
        landed += 1
        if kind == "workflow":
            subprocess.run([str(SNAKEMAKE), "--unlock", *arguments], cwd=workdir, capture_output=True, timeout=120)
    final = subprocess.run(
        [str(SNAKEMAKE), "--cores", "2", *arguments], cwd=workdir, capture_output=True, text=True, timeout=timeout
    )
    return rounds, final.returncode


def leftovers(workdir: Path) -> list[str]:
    """The runner's work folders left under results/: unfinished (``.<run>.partial``) or failed
    (``<run>.failed``) runs."""
    root = workdir / "results"
    return sorted(
        str(p.relative_to(root)) for p in root.rglob("*") if p.is_dir() and p.name.endswith((".partial", ".failed"))
    )


def rounds_table(rounds: list[Kill]) -> list[dict]:
    return [asdict(r) for r in rounds]


#: A run record's entries that say when, how long and through which launches the run was made,
#: not what it made: they differ between any two runs of the same study.
RUN_HISTORY = ("finished_utc", "wall_time_s", "segments", "command")


def _relative(value):
    """``value`` with every absolute path inside the study written from its results/ or build/
    folder on (a study copied elsewhere, as pytest-xdist's workers copy the session's study, keeps
    the paths it was made in)."""
    if isinstance(value, dict):
        return {key: _relative(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_relative(item) for item in value]
    if isinstance(value, str) and value.startswith("/"):
        parts = Path(value).parts
        for anchor in ("results", "build"):
            if anchor in parts:
                return str(Path(*parts[parts.index(anchor) :]))
    return value


def _run_record(path: Path) -> str:
    """A run record without its history (`RUN_HISTORY`) and with the study's paths relative to it:
    what the run made and from what."""
    record = {key: value for key, value in json.loads(path.read_text()).items() if key not in RUN_HISTORY}
    return json.dumps(_relative(record), sort_keys=True)


def comparable_digests(workdir: Path) -> dict[str, str]:
    """sha256 of every file under results/ that two runs of the same study must make alike: the
    tables, figures, reports and data, and the run records without their history; not the job
    logs, LAMMPS's own logs (timings) or the runner's hidden work folders."""
    root = workdir / "results"
    digests = {}
    for path in sorted(root.rglob("*")):
        parts = path.relative_to(root).parts
        if not path.is_file() or any(part == "logs" or part.startswith(".") for part in parts):
            continue
        if path.name == "log.lammps":
            continue
        data = _run_record(path).encode() if path.name == "run_complete.json" else path.read_bytes()
        digests[str(path.relative_to(root))] = hashlib.sha256(data).hexdigest()
    return digests


def resumed_runs(workdir: Path) -> dict[str, list[int]]:
    """The runs continued part-way from one of their own restart files: run folder (under
    results/) -> the steps they resumed at, from each run record's launches."""
    root = workdir / "results"
    found = {}
    for record in sorted(root.rglob("run_complete.json")):
        steps = [
            s.get("start_step") for s in json.loads(record.read_text()).get("segments", []) if s.get("resume_file")
        ]
        if steps:
            found[str(record.parent.relative_to(root))] = steps
    return found
