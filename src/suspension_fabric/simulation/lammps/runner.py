"""Run the project's LAMMPS scripts (simulation/lammps/inputs/*.lmp) from Python: pack, and any segment of a
flow history (segment.lmp; the startup and a shear rotation are two kinds of segment).

Units (project convention): strain rate 1, small-particle diameter d = 1, mass rho d^3
(rho = 1), so time = strain; a run of strain S at time step dt takes S / dt steps.
Simulation frame: z is the gradient direction; a shear with flow direction
(cos t, sin t, 0) is ``fix deform ... xz erate cos(t) yz erate sin(t)``.

A run counts as failed on a non-zero exit, a LAMMPS ERROR (e.g. "Lost atoms"), a NaN/inf
in thermo, a missing completion line, or an output check (overlap, stress jitter); then
[`LammpsRunError`][suspension_fabric.simulation.lammps.runner.LammpsRunError] says why and where the partial files are.
Shear runs are resumable: an interrupted run (killed, walltime, Ctrl-C) keeps its work in
``.<name>.partial`` and the next call with the same settings continues it from its latest
readable restart file ([`rundir`][suspension_fabric.simulation.lammps.rundir]). A finished run is published whole, with
its completion marker `COMPLETION_MARKER` written last.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from suspension_fabric.io.dumpio import scan_dump
from suspension_fabric.io.protocols import Segment
from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR
from suspension_fabric.io.runinfo import RUN_RECORD_FORMAT, read_run_info
from suspension_fabric.io.schema import load_schema, schema_default
from suspension_fabric.io.stressio import UNRECORDED_COLUMNS, read_stress_table
from suspension_fabric.simulation.scales import background_viscosity, critical_load_force, output_stride

from .checks import max_overlap_in_dump, stress_jitter
from .process import ProgressCallback, failure_reason, lammps_command, launch, print_progress
from .rundir import COMPLETION_MARKER, PartialRun, ResumePoint, is_complete, publish

__all__ = [
    "COMPLETION_MARKER",
    "ForceModel",
    "ShearSettings",
    "LammpsRunError",
    "PackResult",
    "ShearRunResult",
    "pack",
    "run_segment",
    "run_startup",
    "run_rotation",
    "is_complete",
    "RUN_FILES",
]

# Output file names inside a run directory (LAMMPS writes them in its working directory).
PACK_DATA = "packing.data"
PACK_REPORT = "packing.json"
DUMP_FILE = "trajectory.dump"
TABLE_FILE = "stress.txt"
CHECKPOINT_FILE = "checkpoint.rst"
RESTART_FILES = ("restart.a.rst", "restart.b.rst")
LOG_FILE = "log.lammps"
#: run.initial_guess's values (config/schema.yaml), the fix's keyword guess
INITIAL_GUESSES = tuple(load_schema()["properties"]["run"]["properties"]["initial_guess"]["enum"])
#: The files of a finished shear run, by role (the workflow's rule outputs).
RUN_FILES = {
    "trajectory": DUMP_FILE,
    "stress": TABLE_FILE,
    "checkpoint": CHECKPOINT_FILE,
    "run_complete": COMPLETION_MARKER,
}
PACK_FILES = {"data": PACK_DATA, "report": PACK_REPORT}


class LammpsRunError(RuntimeError):
    """A LAMMPS run failed; the message says why and where the partial files are."""


@dataclass(frozen=True)
class ForceModel:
    """Force-model parameters, passed to the scripts as LAMMPS variables.

    Defaults are the study defaults of config/schema.yaml. ``eta_f`` fluid viscosity
    (Stokes number 1/eta_f), ``kn`` normal stiffness, ``mu`` friction (paper), frictional only above
    the normal force ``critical_load`` F_CL if it is > 0 (config/schema.yaml
    ``forces.critical_load_rate``), or, with ``critical_load_stress`` S > 0 (``forces.critical_load_stress``),
    at the shear stress held at S sigma_0, sigma_0 = F_CL / a^2 with a = ``critical_load_radius``, F_CL
    following the stress, ``background_viscosity`` the stress per unit rate no force carries
    (``suspension_fabric.simulation.scales.background_viscosity``); ``kt``
    tangential stiffness (None: 2/7 kn), ``delta`` lubrication gap regularisation,
    ``h_out`` outer lubrication gap cutoff (in d), ``newton_pair`` the newton setting the
    plugin styles need. ``lubrication`` "sf" = project plugin, "stock" = stand-in model of
    stock LAMMPS styles (development only, explicit only). ``plugin`` = path to the plugin
    library, loaded by every run (None: build/locate it with
    ``suspension_fabric.simulation.lammps.plugin.plugin_path()``). ``integrator`` "implicit" = fix
    hydro/implicit/sf (drag and lubrication solved implicitly, CG to ``solver_tol`` in
    gammadot d), "explicit" = velocity Verlet (needs dt ~ 2e-7; ``suspension_fabric.simulation.scales``).
    ``contact_springs`` (implicit integrator) "implicit" = the fix owns the contacts and solves
    the sticking springs with the hydrodynamics, "explicit" = pair granular; ``contact_solve`` (implicit
    springs) "lagged" = contact states from the old velocities, "newton" = the contact law solved
    implicitly by Newton passes (config/schema.yaml ``run.contact_solve``); ``preconditioner``
    of the implicit solve, "jacobi" or "dilu"; ``local_solve_fraction`` the fraction of particles
    above ``solver_tol`` below which the solve finishes locally (0: off; config/schema.yaml
    ``run.local_solve_fraction``); ``initial_guess`` the solve's first iterate each step, "previous"
    (the old velocities), "linear" or "quadratic" (their extrapolation over the last steps;
    config/schema.yaml ``run.initial_guess``); ``verify_solve`` (tests) stops the run if a solve's recomputed
    residual misses ``solver_tol``.
    """

    eta_f: float = schema_default("forces", "eta_f")
    kn: float = schema_default("forces", "kn")
    mu: float = schema_default("forces", "mu")
    critical_load: float = 0.0
    critical_load_stress: float = 0.0
    critical_load_radius: float = 0.5
    background_viscosity: float = 0.0
    kt: float | None = schema_default("forces", "kt")
    delta: float = schema_default("forces", "delta")
    h_out: float = schema_default("forces", "h_out")
    newton_pair: str = "on"
    lubrication: str = "sf"
    plugin: str | os.PathLike | None = None
    integrator: str = schema_default("run", "integrator")
    contact_springs: str = schema_default("run", "contact_springs")
    contact_solve: str = schema_default("run", "contact_solve")
    preconditioner: str = schema_default("run", "preconditioner")
    solver_tol: float = schema_default("run", "solver_tol")
    local_solve_fraction: float = schema_default("run", "local_solve_fraction")
    initial_guess: str = schema_default("run", "initial_guess")
    verify_solve: bool = False

    @classmethod
    def from_config(cls, config: Mapping, plugin: str | os.PathLike | None = None) -> ForceModel:
        """The force model of a validated study config (sections ``forces``, ``run`` and the small
        diameter of ``particles``)."""
        forces = dict(config["forces"])
        rate_ratio = forces.pop("critical_load_rate", None)
        stress_ratio = forces.pop("critical_load_stress", None)
        if rate_ratio is not None:
            forces["critical_load"] = critical_load_force(
                rate_ratio, forces["eta_f"], config["particles"]["d_small"], ShearSettings.rate
            )
        if stress_ratio is not None:
            forces["critical_load_stress"] = stress_ratio
            forces["critical_load_radius"] = 0.5 * config["particles"]["d_small"]
            forces["background_viscosity"] = background_viscosity(forces["eta_f"], config["particles"]["phi"])
        return cls(
            plugin=plugin,
            integrator=config["run"]["integrator"],
            contact_springs=config["run"]["contact_springs"],
            contact_solve=config["run"]["contact_solve"],
            preconditioner=config["run"]["preconditioner"],
            solver_tol=config["run"]["solver_tol"],
            local_solve_fraction=config["run"]["local_solve_fraction"],
            initial_guess=config["run"]["initial_guess"],
            **forces,
        )

    def variables(self) -> dict[str, str]:
        if self.lubrication not in ("sf", "stock"):
            raise ValueError(f"lubrication must be 'sf' or 'stock', got {self.lubrication!r}")
        if self.integrator not in ("implicit", "explicit"):
            raise ValueError(f"integrator must be 'implicit' or 'explicit', got {self.integrator!r}")
        if self.lubrication == "stock" and self.integrator != "explicit":
            raise ValueError("the stock force model runs with integrator='explicit' only")
        if self.contact_springs not in ("implicit", "explicit"):
            raise ValueError(f"contact_springs must be 'implicit' or 'explicit', got {self.contact_springs!r}")
        if self.contact_springs == "implicit" and self.integrator != "implicit":
            raise ValueError(
                "contact_springs='implicit' needs integrator='implicit' (the springs are "
                "solved with the implicit hydrodynamics)"
            )
        if self.contact_solve not in ("lagged", "newton"):
            raise ValueError(f"contact_solve must be 'lagged' or 'newton', got {self.contact_solve!r}")
        if self.contact_solve == "newton" and self.contact_springs != "implicit":
            raise ValueError(
                "contact_solve='newton' needs contact_springs='implicit' (it solves the fix's own contacts)"
            )
        if not self.critical_load >= 0.0:
            raise ValueError(f"critical_load must be >= 0, got {self.critical_load!r}")
        if not (
            self.critical_load_stress >= 0.0 and self.critical_load_radius > 0.0 and self.background_viscosity >= 0.0
        ):
            raise ValueError(
                "critical_load_stress and background_viscosity must be >= 0 and critical_load_radius > 0, got "
                f"{self.critical_load_stress!r}, {self.background_viscosity!r}, {self.critical_load_radius!r}"
            )
        if self.critical_load_stress > 0.0 and not self.background_viscosity > 0.0:
            raise ValueError(
                "critical_load_stress needs background_viscosity > 0 (eta_f (1 + 2.5 phi): the solvent's stress, "
                "the floor of the stress it follows)"
            )
        if self.critical_load > 0.0 and self.critical_load_stress > 0.0:
            raise ValueError("critical_load and critical_load_stress exclude each other (rate or stress imposed)")
        if (self.critical_load > 0.0 or self.critical_load_stress > 0.0) and self.contact_springs != "implicit":
            raise ValueError(
                "a critical load needs contact_springs='implicit' (fix hydro/implicit/sf's own contacts; "
                "pair granular has none)"
            )
        if self.preconditioner not in ("jacobi", "dilu"):
            raise ValueError(f"preconditioner must be 'jacobi' or 'dilu', got {self.preconditioner!r}")
        if not 0.0 <= self.local_solve_fraction < 1.0:
            raise ValueError(f"local_solve_fraction must be in [0, 1), got {self.local_solve_fraction!r}")
        if self.initial_guess not in INITIAL_GUESSES:
            raise ValueError(f"initial_guess must be one of {', '.join(INITIAL_GUESSES)}, got {self.initial_guess!r}")
        kt = 2.0 / 7.0 * self.kn if self.kt is None else self.kt
        return {
            "lubrication": self.lubrication,
            "eta_f": _number(self.eta_f),
            "kn": _number(self.kn),
            "mu": _number(self.mu),
            "critical_load": _number(self.critical_load),
            "critical_load_stress": _number(self.critical_load_stress),
            "critical_load_radius": _number(self.critical_load_radius),
            "background_viscosity": _number(self.background_viscosity),
            "kt": _number(kt),
            "delta": _number(self.delta),
            "h_out": _number(self.h_out),
            "newton_pair": self.newton_pair,
            "integrator": self.integrator,
            "contact_springs": self.contact_springs,
            "contact_solve": self.contact_solve,
            "preconditioner": self.preconditioner,
            "solver_tol": _number(self.solver_tol),
            "local_solve_fraction": _number(self.local_solve_fraction),
            "initial_guess": self.initial_guess,
            "verify_solve": "yes" if self.verify_solve else "no",
            "plugin": str(_plugin_library(self.plugin)),
        }


@dataclass(frozen=True)
class ShearSettings:
    """How a shear run is integrated, sampled and checked (defaults: config/schema.yaml, ``run``).

    ``dt`` time step and ``rate`` shear rate (1: time = strain); the trajectory every
    ``dump_strain``, the stress table every ``table_strain``, thermo (progress) every
    ``thermo_strain``, alternating restart files every ``restart_strain`` (the points a
    killed run resumes from); neighbour ``skin``. Checks: a run fails if an overlap in
    any dumped frame exceeds ``max_overlap`` (in d; a blow-up detector) or, with the table
    sampled at least every 0.002 strain, the stress jitter exceeds ``max_stress_jitter``
    ([`checks.stress_jitter`][suspension_fabric.simulation.lammps.checks.stress_jitter]; None disables it). ``ranks``
    MPI ranks.
    """

    dt: float = schema_default("run", "dt")
    rate: float = 1.0
    dump_strain: float = schema_default("run", "dump_strain")
    table_strain: float = schema_default("run", "table_strain")
    thermo_strain: float = schema_default("run", "thermo_strain")
    restart_strain: float = schema_default("run", "restart_strain")
    skin: float = 0.1
    max_overlap: float = schema_default("run", "max_overlap")
    max_stress_jitter: float | None = schema_default("run", "max_stress_jitter")
    ranks: int = schema_default("run", "mpi_ranks")

    @classmethod
    def from_config(cls, config: Mapping) -> ShearSettings:
        run = config["run"]
        names = (
            "dt",
            "dump_strain",
            "table_strain",
            "thermo_strain",
            "restart_strain",
            "max_overlap",
            "max_stress_jitter",
        )
        return cls(ranks=run["mpi_ranks"], **{name: run[name] for name in names})

    def __post_init__(self):
        for name in ("dt", "rate", "dump_strain", "table_strain", "thermo_strain", "restart_strain"):
            if not getattr(self, name) > 0:
                raise ValueError(f"ShearSettings.{name} must be positive, got {getattr(self, name)}")

    def steps_between(self, strain: float) -> int:
        """Steps between outputs every ``strain``
        ([`suspension_fabric.simulation.scales.output_stride`][suspension_fabric.simulation.scales.output_stride])."""
        return output_stride(strain, self.dt, self.rate)

    def variables(self) -> dict[str, str]:
        names = ("dt", "rate", "dump_strain", "table_strain", "thermo_strain", "restart_strain", "skin")
        return {name: _number(getattr(self, name)) for name in names}


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
    over all dumped frames; ``wall_time`` the LAMMPS time of all its segments;
    ``segments`` the number of launches it took (1 unless it was resumed).
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
    segments: int = 1


def _number(value: float) -> str:
    """Full-precision text of a number for ``-var`` (repr round-trips float64)."""
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"LAMMPS variable values must be finite, got {value}")
    return repr(value)


def _plugin_library(plugin: str | os.PathLike | None) -> Path:
    from . import plugin as plugin_module

    if plugin is None:
        return plugin_module.plugin_path()
    path = Path(plugin).resolve()
    if not path.is_file():
        raise FileNotFoundError(
            f"LAMMPS plugin library not found: {path} (build it with "
            "`python -m suspension_fabric.simulation.lammps.plugin`; a workflow segment builds it itself)"
        )
    plugin_module.check_not_stale(path)
    return path


def _failure(label: str, reason: str, command: list[str], where: str, tail: str = "") -> LammpsRunError:
    return LammpsRunError(
        f"LAMMPS {label} run failed: {reason}\n  command: {' '.join(command)}\n  {where}\n  last output lines:\n{tail}"
    )


# ---------------------------------------------------------------------------- packing


def pack(
    output_dir: str | os.PathLike,
    n_particles: int = schema_default("particles", "n"),
    phi: float = schema_default("particles", "phi"),
    seed: int = 12345,
    *,
    split: str = schema_default("particles", "split"),
    fraction_large: float = schema_default("particles", "fraction_large"),
    d_small: float = schema_default("particles", "d_small"),
    d_large: float = schema_default("particles", "d_large"),
    gap_margin: float = 0.02,
    max_overlap: float = 1.0e-6,
    phi_tolerance: float = 1.0e-9,
    ranks: int = 1,
    overwrite: bool = False,
    extra_variables: Mapping[str, object] | None = None,
) -> PackResult:
    """Random non-overlapping bidisperse packing (simulation/lammps/inputs/pack.lmp).

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
    output_dir = Path(output_dir).resolve()
    if output_dir.exists() and not overwrite:
        raise FileExistsError(f"{output_dir} exists; pass overwrite=True to replace it")
    variables = {
        "lammps_dir": str(LAMMPS_SCRIPTS_DIR),
        "n_particles": str(int(n_particles)),
        "phi": _number(phi),
        "seed": str(int(seed)),
        "split": split,
        "fraction_large": _number(fraction_large),
        "d_small": _number(d_small),
        "d_large": _number(d_large),
        "gap_margin": _number(gap_margin),
        "data_file": PACK_DATA,
        "report_file": PACK_REPORT,
    }
    variables.update({k: str(v) for k, v in (extra_variables or {}).items()})
    command = lammps_command(LAMMPS_SCRIPTS_DIR / "pack.lmp", variables, ranks, LOG_FILE)
    work = Path(tempfile.mkdtemp(prefix=f".{output_dir.name}.running-", dir=_parent(output_dir)))
    try:
        result = launch(command, work, "pack")
        reason = failure_reason(result, "PACK_RESULT")
        report_path = work / PACK_REPORT
        if reason is None and not ((work / PACK_DATA).is_file() and report_path.is_file()):
            reason = "pack.lmp did not write its data file and report"
        if reason is None:
            report = json.loads(report_path.read_text())
            if abs(report["phi"] - phi) > phi_tolerance * phi:
                reason = f"reached phi = {report['phi']} instead of {phi}"
            elif report["max_overlap"] > max_overlap:
                reason = f"largest overlap {report['max_overlap']} exceeds the bound {max_overlap}"
        if reason is not None:
            raise _failure("pack", reason, command, f"its files: {work}", result.watcher.tail())

        def fill(target: Path) -> dict:
            for name in (PACK_DATA, PACK_REPORT, LOG_FILE):
                shutil.copy2(work / name, target / name)
            return {
                "label": "pack",
                "script": "pack.lmp",
                "variables": variables,
                "ranks": ranks,
                "command": command,
                "wall_time_s": result.wall_time,
                "results": report,
            }

        publish(output_dir, fill, overwrite)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return PackResult(
        output_dir=output_dir,
        data_file=output_dir / PACK_DATA,
        phi=report["phi"],
        max_overlap=report["max_overlap"],
        n_small=int(report["n_small"]),
        n_large=int(report["n_large"]),
        box_length=report["box_length"],
        wall_time=result.wall_time,
    )


def _parent(output_dir: Path) -> Path:
    output_dir.parent.mkdir(parents=True, exist_ok=True)
    return output_dir.parent


# ---------------------------------------------------------------------------- shear runs


def _probe_restart(plugin: str, scratch: Path):
    """A probe reading a restart file with LAMMPS (restart_probe.lmp); returns its step."""

    def probe(restart_file: Path) -> int:
        scratch.mkdir(parents=True, exist_ok=True)
        command = lammps_command(
            LAMMPS_SCRIPTS_DIR / "restart_probe.lmp", {"plugin": plugin, "restart_file": str(restart_file)}, 1, "none"
        )
        result = launch(command, scratch, "restart probe")
        reason = failure_reason(result, "RESTART_PROBE")
        if reason is not None:
            raise ValueError(reason)
        return int(result.watcher.line_starting("RESTART_PROBE").split()[2])

    return probe


def shear_run_variables(variables: Mapping[str, str], settings: ShearSettings, strain_total: float) -> dict[str, str]:
    """Every LAMMPS variable of a shear run (shear_run.lmp, through segment.lmp): ``variables`` (where it starts,
    the segment, the forces), the settings' integration and outputs, ``strain_total`` and the output files."""
    return {
        "lammps_dir": str(LAMMPS_SCRIPTS_DIR),
        **variables,
        **settings.variables(),
        "strain_total": _number(strain_total),
        "dump_file": DUMP_FILE,
        "table_file": TABLE_FILE,
        "checkpoint_file": CHECKPOINT_FILE,
        "restart_file_a": RESTART_FILES[0],
        "restart_file_b": RESTART_FILES[1],
    }


def _shear_run(
    script: str,
    label: str,
    variables: dict[str, str],
    output_dir,
    strain_total: float,
    settings: ShearSettings,
    overwrite: bool,
    resume: bool,
    progress: ProgressCallback | None,
    progress_interval: float,
    record: Mapping | None = None,
) -> ShearRunResult:
    output_dir = Path(output_dir).resolve()
    if output_dir.exists() and not overwrite:
        raise FileExistsError(f"{output_dir} exists; pass overwrite=True to replace it")
    if strain_total <= 0:
        raise ValueError(f"strain_total must be positive, got {strain_total}")
    run_variables = shear_run_variables(variables, settings, strain_total)
    _parent(output_dir)
    partial = PartialRun(
        output_dir, {"script": script, "variables": run_variables}, restart_names=RESTART_FILES, table_name=TABLE_FILE
    )
    point: ResumePoint | None = None
    if resume:
        point = partial.resume_point(_probe_restart(run_variables["plugin"], partial.path / "probe"))
    else:
        partial.discard("resume=False")
    segment = partial.new_segment(point)
    segment_variables = dict(run_variables)
    if point is not None:
        segment_variables.update(resume="yes", resume_file=str(point.restart_file), step0=str(point.first_step))
    command = lammps_command(LAMMPS_SCRIPTS_DIR / script, segment_variables, settings.ranks, LOG_FILE)
    try:
        result = launch(command, segment, label, strain_total, progress, progress_interval)
    except BaseException:
        partial.finish_segment(segment, "interrupted", float("nan"))
        raise
    reason = failure_reason(result, "SHEAR_RUN_COMPLETE")
    partial.finish_segment(segment, "failed" if reason else "complete", result.wall_time)
    if reason is not None:
        raise _failure(
            label,
            reason,
            command,
            f"partial run kept in {partial.path}: running it again with the same settings "
            "continues from its latest restart file",
            result.watcher.tail(),
        )

    # "SHEAR_RUN_COMPLETE step <last> first_step <first> strain <strain>"
    completion = result.watcher.line_starting("SHEAR_RUN_COMPLETE").split()
    last_step, first_step = int(completion[2]), int(completion[4])
    segments = partial.segment_summary(segment)

    def fill(target: Path) -> dict:
        partial.stitch_dump(
            segment, DUMP_FILE, first_step, settings.steps_between(settings.dump_strain), target / DUMP_FILE
        )
        partial.stitch_table(
            segment, TABLE_FILE, first_step, settings.steps_between(settings.table_strain), target / TABLE_FILE
        )
        partial.concatenate_logs(segment, LOG_FILE, target / LOG_FILE)
        shutil.copy2(segment / CHECKPOINT_FILE, target / CHECKPOINT_FILE)
        results = _check_shear_outputs(target, first_step, last_step, strain_total, settings)
        wall_time = sum(s.get("wall_time_s", 0.0) for s in segments if math.isfinite(s.get("wall_time_s", 0.0)))
        return {
            "format": RUN_RECORD_FORMAT,
            **(record or {}),
            "label": label,
            "script": script,
            "variables": run_variables,
            "ranks": settings.ranks,
            "command": command,
            "wall_time_s": wall_time,
            "segments": segments,
            "results": results,
        }

    try:
        marker = publish(output_dir, fill, overwrite)
    except (LammpsRunError, ValueError, OSError) as err:
        failed = partial.move_to_failed()
        raise _failure(label, f"output check: {err}", command, f"partial files (not a result): {failed}") from None
    shutil.rmtree(partial.path)
    if progress is not None:
        progress(label, marker["results"]["strain"], strain_total, marker["wall_time_s"])
    return ShearRunResult(
        output_dir=output_dir,
        dump_file=output_dir / DUMP_FILE,
        table_file=output_dir / TABLE_FILE,
        checkpoint_file=output_dir / CHECKPOINT_FILE,
        log_file=output_dir / LOG_FILE,
        first_step=first_step,
        last_step=last_step,
        strain=marker["results"]["strain"],
        max_overlap=marker["results"]["max_overlap"],
        wall_time=marker["wall_time_s"],
        segments=len(segments),
    )


def _check_shear_outputs(
    run_dir: Path, first_step: int, last_step: int, strain_total: float, settings: ShearSettings
) -> dict:
    """Outputs complete and continuous, finite, no blow-up; the results for the marker."""
    table = read_stress_table(run_dir / TABLE_FILE)
    checked = [values for name, values in table.items() if name not in UNRECORDED_COLUMNS]
    if not np.all(np.isfinite(np.column_stack(checked))):
        raise LammpsRunError(f"non-finite values in {TABLE_FILE}")
    strain = (last_step - first_step) * settings.dt * settings.rate
    if abs(strain - strain_total) > 0.5 * settings.dt * settings.rate:
        raise LammpsRunError(f"reached strain {strain}, expected {strain_total}")
    _check_grid(
        TABLE_FILE, table["step"].astype(np.int64), first_step, last_step, settings.steps_between(settings.table_strain)
    )
    _check_grid(
        DUMP_FILE,
        scan_dump(run_dir / DUMP_FILE).steps,
        first_step,
        last_step,
        settings.steps_between(settings.dump_strain),
    )
    largest, frames = max_overlap_in_dump(run_dir / DUMP_FILE)
    if settings.max_stress_jitter is not None and settings.table_strain <= 0.002:
        jitter, lo, hi = stress_jitter(table)
        if jitter > settings.max_stress_jitter:
            raise LammpsRunError(
                f"the stress jumps between table rows (jitter {jitter:.3g} > {settings.max_stress_jitter} "
                f"at strain {lo:.4g}-{hi:.4g}): dt = {settings.dt} is too large for the lubrication "
                "squeeze resistance (explicit integration unstable); reduce dt"
            )
    if largest > settings.max_overlap:
        raise LammpsRunError(
            f"largest overlap {largest:.3g} d in {DUMP_FILE} exceeds the bound {settings.max_overlap} d"
        )
    return {
        "first_step": first_step,
        "last_step": last_step,
        "strain": strain,
        "max_overlap": largest,
        "dump_frames": frames,
    }


def _check_grid(name: str, steps: np.ndarray, first_step: int, last_step: int, stride: int) -> None:
    """Every output step on the run's grid first_step + k stride, each once, in order, none missing."""
    expected = np.arange(first_step, last_step + 1, stride)
    if len(steps) != len(expected) or np.any(steps != expected):
        raise LammpsRunError(
            f"{name}: steps are not the continuous sequence {first_step}, {first_step + stride}, ..., "
            f"{expected[-1]} ({len(steps)} entries instead of {len(expected)})"
        )


def run_segment(
    output_dir: str | os.PathLike,
    segment: Segment,
    *,
    data_file: str | os.PathLike | None = None,
    restart_file: str | os.PathLike | None = None,
    index: int | None = None,
    history: tuple[Segment, ...] | None = None,
    force_model: ForceModel = ForceModel(),
    settings: ShearSettings = ShearSettings(),
    require_complete_source: bool = True,
    overwrite: bool = False,
    resume: bool = True,
    progress: ProgressCallback | None = print_progress,
    progress_interval: float = 10.0,
    record: Mapping | None = None,
) -> ShearRunResult:
    """One segment of a flow history (simulation/lammps/inputs/segment.lmp): ``segment.strain`` of simple
    shear at flow angle ``segment.flow_angle_deg`` about the gradient axis z, turning at
    ``segment.turning_deg_per_strain``
    ([`suspension_fabric.io.protocols.Segment`][suspension_fabric.io.protocols.Segment]).

    Starts from rest on the packing ``data_file`` or continues from the checkpoint
    ``restart_file`` of the segment before (exactly one); ``index`` is the segment's depth in its
    flow history (0 from a packing) and ``history`` the segments up to and including this one,
    recorded in the completion marker with the segment (defaults: the segment alone from a
    packing, the history recorded by the run that wrote ``restart_file`` and the segment after it). Writes into
    ``output_dir`` the trajectory ``trajectory.dump`` (id type radius x y z), the table
    ``stress.txt``
    ([`suspension_fabric.io.stressio.read_stress_table`][suspension_fabric.io.stressio.read_stress_table]) and
    ``checkpoint.rst``; strain counts from the segment's first step. ``force_model`` must be the one of the run that
    wrote ``restart_file`` (pair coefficients are re-issued, not restored); with ``require_complete_source`` that
    checkpoint must sit in a finished run directory. With ``resume``, an interrupted earlier call with the same
    arguments is continued from its latest restart file. ``progress(label, strain, total, elapsed_s)`` is called at most
    every ``progress_interval`` seconds. ``record`` adds items to the completion marker (the workflow
    records the settings it asked for).
    """
    if (data_file is None) == (restart_file is None):
        raise ValueError("give exactly one of data_file (start from rest) and restart_file (continue)")
    if data_file is not None:
        data_file = Path(data_file).resolve()
        if not data_file.is_file():
            raise FileNotFoundError(f"packing data file not found: {data_file}")
        source = {"start_from": "packing", "start_file": str(data_file)}
    else:
        restart_file = Path(restart_file).resolve()
        if not restart_file.is_file():
            raise FileNotFoundError(f"restart file not found: {restart_file}")
        if require_complete_source and not is_complete(restart_file.parent):
            raise LammpsRunError(
                f"{restart_file} is not in a finished run directory (no {COMPLETION_MARKER}); "
                "pass require_complete_source=False to use it anyway"
            )
        source = {"start_from": "checkpoint", "start_file": str(restart_file)}
    if history is None:
        # from a packing the segment is the whole history; after a finished run, its history and this
        parent = () if data_file is not None else _recorded_history(restart_file.parent)
        history = (*parent, segment) if parent is not None else None
    if history is None:
        if index is None:
            raise ValueError(f"{restart_file.parent} holds no run record: give index and history")
        history = (segment,)
    history = tuple(history)
    index = len(history) - 1 if index is None else index
    if history[-1] != segment:
        raise ValueError("history must end with the segment")
    if index < 0 or (index == 0) != (data_file is not None):
        raise ValueError(f"index must be 0 for a segment from a packing and >= 1 after another, got {index}")
    variables = {
        **source,
        "segment_index": str(index),
        "flow_angle_deg": _number(segment.flow_angle_deg),
        "turning_deg_per_strain": _number(segment.turning_deg_per_strain),
        **force_model.variables(),
    }
    turning = f", turning {segment.turning_deg_per_strain:g} deg/strain" if segment.turning_deg_per_strain else ""
    where = f"segment {index}: {segment.strain:g} strain at {segment.flow_angle_deg:g} deg{turning}"
    label = f"{Path(output_dir).name} ({where})"
    record = {
        **(record or {}),
        "flow_segment": {"index": index, **segment.as_dict()},
        "flow_history": [past.as_dict() for past in history],
    }
    return _shear_run(
        "segment.lmp",
        label,
        variables,
        output_dir,
        segment.strain,
        settings,
        overwrite,
        resume,
        progress,
        progress_interval,
        record,
    )


def run_startup(
    output_dir: str | os.PathLike,
    data_file: str | os.PathLike,
    strain_total: float = schema_default("run", "startup_strain"),
    **options,
) -> ShearRunResult:
    """Startup simple shear from rest, flow x, gradient z:
    [`run_segment`][suspension_fabric.simulation.lammps.runner.run_segment] of ``strain_total`` at angle 0 from the
    packing ``data_file`` (``options`` as there)."""
    return run_segment(output_dir, Segment(strain_total), data_file=data_file, **options)


def run_rotation(
    output_dir: str | os.PathLike,
    restart_file: str | os.PathLike,
    theta_deg: float,
    strain_total: float = schema_default("run", "rotation_strain"),
    **options,
) -> ShearRunResult:
    """Shear rotation by ``theta_deg`` degrees from the checkpoint of a startup:
    [`run_segment`][suspension_fabric.simulation.lammps.runner.run_segment] of ``strain_total`` at flow angle theta,
    (cos theta, sin theta, 0) (paper frame: e1' = cos(theta) e1 - sin(theta) e3); theta = 0 continues the startup's
    shear."""
    return run_segment(output_dir, Segment(strain_total, theta_deg), restart_file=restart_file, index=1, **options)


def _recorded_history(run_dir: Path) -> tuple[Segment, ...] | None:
    """The flow history recorded by the finished run in ``run_dir`` (None without a record)."""
    marker = run_dir / COMPLETION_MARKER
    return read_run_info(marker).history if marker.is_file() else None
