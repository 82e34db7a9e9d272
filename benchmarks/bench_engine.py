"""Engine speed in steady shear: the implicit contact springs (engine speed II) against the
implicit hydrodynamics with explicit springs (engine speed I), the explicit plugin and stock
LAMMPS (BENCHMARKS.md, "Engine speed II: speed").

    .venv/bin/python benchmarks/bench_engine.py prepare      # steady-state checkpoints (any load)
    .venv/bin/python benchmarks/bench_engine.py measure      # the timings: run on an idle machine
    .venv/bin/python benchmarks/bench_engine.py ladder       # cost and iterations against dt (idle machine)
    .venv/bin/python benchmarks/bench_engine.py alternate    # Jacobi and dilu back to back (idle machine)
    .venv/bin/python benchmarks/bench_engine.py work         # CG iterations per unit strain against dt (any load)

`prepare`: for N = 250, 500, 1000, 2000, 4000 (phi = 0.45, packing seed 1, default forces) a
startup to strain 1.5 with the implicit springs at SPRINGS_DT and SPRINGS_KN, where the
contact network is built up (Z ~ 3.4), into results/bench_engine/n<N>/. Reused when present.

`ladder [--kn K]`: at N = 500, the implicit springs with block Jacobi and with dilu at
dt = 2e-5 ... 4e-4, solved to 1e-5 (the cost and the CG iterations against the step).

`measure`: from each checkpoint, a short continuation of the same shear (segment.lmp at
flow angle 0) with (a) the default engine (the schema's defaults: the implicit springs, dilu,
kn = 1.25e8, dt = 1e-4, solver_tol = 1e-3), (b) the same with block Jacobi, (c) dilu to
solver_tol = 1e-5 (engine speed II's first accepted setting),
(d) the implicit hydrodynamics with the springs explicit (pair granular) at kn = 1.25e9, its
production dt = 2e-5 and solver_tol 1e-5 (engine speed I: the engine of the committed
reference data), (e) the explicit plugin (velocity Verlet, lubricate/sf + stokes/sf) at
dt = 2e-7 and (f) stock lubricate/poly + granular (explicit) at 2e-7; (c), (e) and (f) at
N = 500 only. The runs (d)-(f) start with unloaded granular springs (the checkpoint holds the
fix's springs) and, at their kn = 1.25e9, from the larger overlaps of the softer contacts: a
transient of ~1e-3 strain, small against the strain timed. The time is LAMMPS's own loop time
of the run (no start-up or output checks), on one core, reported as core-s per particle per
unit strain, with the steps per unit strain and the mean CG iterations per step (all solves
of a step). Prints a Markdown table and the ratios.
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

import pandas as pd
from mpi_scaling import figures

from suspension_fabric.simulation.lammps import (
    PACK_FILES,
    RUN_FILES,
    ForceModel,
    LammpsRunError,
    ShearSettings,
    is_complete,
    pack,
    run_rotation,
    run_startup,
)

ROOT = Path("results/bench_engine")
SIZES = (250, 500, 1000, 2000, 4000)
BASE_N = 500  # the size of the single runs and of the ratios
PREPARE_STRAIN = 1.5
PRODUCTION_DT = 2.0e-5  # the implicit integrator with explicit contact springs (engine speed I)
SPRINGS_DT = float(os.environ.get("SPRINGS_DT", "1e-4"))  # implicit springs: the step measured (Engine speed II)
SPRINGS_KN = float(os.environ.get("SPRINGS_KN", "1.25e8"))  # and the normal stiffness
EXPLICIT_DT = 2.0e-7
REFERENCE_KN = 1.25e9  # the stiffness of the explicit-spring engine that made the committed reference data
# continuation strain per method: long enough for >= 10 s of loop time at N = 500
LADDER_DTS = (2e-5, 5e-5, 1e-4, 2e-4, 4e-4)
# solve_work: the Newton solve's steps against the lagged default's, and where the table goes
WORK_N, WORK_STRAIN = 1000, 0.5
WORK_DUMP_STRAIN = 0.05  # the overlaps' frames: a whole number of steps at every dt, dividing the checkpoint's step
WORK_NEWTON_DTS = (2.5e-4, 5e-4, 1e-3, 2e-3)
WORK_TABLE = Path(__file__).resolve().parent / "data" / "solve_work.csv"
STRAIN = {"explicit": 0.02, "implicit": 0.2, "stock": 0.01, "default": 1.0, "jacobi": 1.0, "dilu_tol1e-5": 0.5}


def checkpoint(n: int) -> Path:
    return ROOT / f"n{n}" / "startup" / RUN_FILES["checkpoint"]


def prepare(sizes: tuple[int, ...] | None = None) -> None:
    for n in sizes or SIZES:  # SIZES read at the call: a test sets it
        packing = ROOT / f"n{n}" / "packing"
        if not is_complete(packing):
            pack(packing, n, phi=0.45, seed=1)
        startup = ROOT / f"n{n}" / "startup"
        if not is_complete(startup):
            run_startup(
                startup,
                packing / PACK_FILES["data"],
                PREPARE_STRAIN,
                force_model=ForceModel(
                    contact_springs="implicit", preconditioner="dilu", kn=SPRINGS_KN, solver_tol=1e-5
                ),
                settings=ShearSettings(dt=SPRINGS_DT, dump_strain=0.1),
                progress_interval=120,
            )


TABLE_HEAD = (
    "| method | N | dt | steps per unit strain | strain | loop s | core-s per particle per unit strain "
    "| mean CG iterations per step |\n|---|---|---|---|---|---|---|---|"
)


def print_head(what: str) -> None:
    """The machine, one core per run and ``what``, then the table's head."""
    print(f"# {platform.machine()}, {platform.python_version()}, one core per run; {what}\n\n{TABLE_HEAD}")


def continuation(model: ForceModel, dt: float, n: int, strain: float, out: Path, thermo_steps: int = 50, **settings):
    """The N = n checkpoint's shear continued for `strain` at step `dt` (thermo every `thermo_steps`,
    the trajectory every 1000 steps; `settings` override ShearSettings)."""
    # strides of 1000 / 100 / thermo_steps steps: they divide the checkpoint's step (15000 at the
    # prepare step 1e-4, 75000 at 2e-5), so the outputs stay on LAMMPS's grid of multiples
    settings = ShearSettings(
        **{
            "dt": dt,
            "dump_strain": 1000 * dt,
            "table_strain": 100 * dt,
            "thermo_strain": thermo_steps * dt,
            "restart_strain": strain,
            "max_stress_jitter": None,
        }
        | settings
    )
    return run_rotation(
        out,
        checkpoint(n),
        0.0,
        strain,
        force_model=model,
        settings=settings,
        overwrite=True,
        resume=False,
        progress=None,
    )


def timed_continuation(label: str, model: ForceModel, dt: float, n: int, strain: float, out: Path) -> float | None:
    """Continues the N = n checkpoint for `strain` and prints one table row; returns the cost in
    core-s per particle per unit strain (None if the run failed)."""
    try:
        run = continuation(model, dt, n, strain, out)
    except LammpsRunError as err:
        print(f"| {label} | {n} | {dt:g} | failed: {str(err).splitlines()[0][:120]} |||||", flush=True)
        return None
    found = figures(run.log_file.read_text())  # the LAMMPS log of the run (one segment: resume=False)
    seconds, iterations = found["loop_s"], found["iterations"] if model.integrator == "implicit" else None
    cost = seconds / (n * run.strain)
    print(
        f"| {label} | {n} | {dt:g} | {round(1 / dt)} | {run.strain:g} | {seconds:.1f} | {cost:.4f} | "
        f"{'' if iterations is None else f'{iterations:.1f}'} |",
        flush=True,
    )
    return cost


def ladder(kn: float) -> None:
    """Cost and CG iterations of the implicit springs against dt at N = BASE_N, both preconditioners."""
    print_head(f"N = {BASE_N}, kn = {kn:g}; continuation of the startup shear from strain {PREPARE_STRAIN:g}")
    for dt in LADDER_DTS:
        for preconditioner in ("jacobi", "dilu"):
            model = ForceModel(contact_springs="implicit", preconditioner=preconditioner, kn=kn, solver_tol=1e-5)
            out = ROOT / f"n{BASE_N}" / f"ladder_kn{kn:g}_{preconditioner}_dt{dt:g}"
            timed_continuation(f"implicit springs, {preconditioner}", model, dt, BASE_N, max(0.1, 2000 * dt), out)


def solve_work() -> None:
    """The solve's work per unit strain against the step at N = WORK_N (default forces): CG
    iterations per step (every step's, all passes: thermo every step) times steps per unit strain,
    for the lagged solve at the default step and the Newton solve at WORK_NEWTON_DTS; with the
    largest overlap over frames every WORK_DUMP_STRAIN. Iteration counts do not depend on the machine's
    load; the loop time does, and includes a thermo line every step."""
    prepare((WORK_N,))
    rows = []
    print(f"# N = {WORK_N}, continuation of the startup shear from strain {PREPARE_STRAIN:g} by {WORK_STRAIN:g}\n")
    print("| contact solve | dt | CG iterations per step | per unit strain | largest overlap (d) | loop s |")
    print("|---|--:|--:|--:|--:|--:|")
    engines = [("lagged", ShearSettings().dt)] + [("newton", dt) for dt in WORK_NEWTON_DTS]
    for solve, dt in engines:
        out = ROOT / f"n{WORK_N}" / f"work_{solve}_dt{dt:g}"
        model = ForceModel(contact_solve=solve)
        # the overlap is recorded here, not refused (run.max_overlap is a blow-up detector)
        frames = {"dump_strain": WORK_DUMP_STRAIN, "max_overlap": 1.0}
        run = continuation(model, dt, WORK_N, WORK_STRAIN, out, thermo_steps=1, **frames)
        found = figures(run.log_file.read_text())
        row = {"contact_solve": solve, "dt": dt, "iterations_per_step": found["iterations"]}
        row |= {"iterations_per_strain": found["iterations"] / dt, "max_overlap": run.max_overlap}
        row["loop_s"] = found["loop_s"]
        rows.append(row)
        print(
            f"| {solve} | {dt:g} | {row['iterations_per_step']:.1f} | {row['iterations_per_strain']:.0f} | "
            f"{row['max_overlap']:.4f} | {row['loop_s']:.1f} |",
            flush=True,
        )
    WORK_TABLE.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows).to_csv(WORK_TABLE, index=False, float_format="%.6g")


def measure() -> None:
    default_dt = ShearSettings().dt
    models = {
        "default": (ForceModel(), default_dt),
        "jacobi": (ForceModel(preconditioner="jacobi"), default_dt),
        "dilu_tol1e-5": (ForceModel(preconditioner="dilu", solver_tol=1e-5), default_dt),
        "implicit": (
            ForceModel(contact_springs="explicit", preconditioner="jacobi", kn=REFERENCE_KN, solver_tol=1e-5),
            PRODUCTION_DT,
        ),
        "explicit": (ForceModel(integrator="explicit", contact_springs="explicit", kn=REFERENCE_KN), EXPLICIT_DT),
        "stock": (
            ForceModel(lubrication="stock", integrator="explicit", contact_springs="explicit", kn=REFERENCE_KN),
            EXPLICIT_DT,
        ),
    }
    model = models["default"][0]
    label = {
        "default": f"default engine (springs implicit, {model.preconditioner}, kn {model.kn:g}, "
        f"tol {model.solver_tol:g})",
        "jacobi": "the same with block Jacobi",
        "dilu_tol1e-5": "dilu to solver_tol 1e-5 (first accepted setting)",
        "implicit": f"springs explicit, kn {REFERENCE_KN:g}, tol 1e-5 (engine speed I, the reference data's engine)",
        "explicit": f"explicit plugin (Verlet), kn {REFERENCE_KN:g}",
        "stock": f"stock lubricate/poly + granular, kn {REFERENCE_KN:g}",
    }
    runs = [(method, n) for method in ("default", "jacobi", "implicit") for n in SIZES]
    runs += [(method, BASE_N) for method in ("dilu_tol1e-5", "explicit", "stock")]
    print_head(f"continuation of the startup shear from strain {PREPARE_STRAIN:g} (phi = 0.45)")
    cost = {}
    for method, n in runs:
        model, dt = models[method]
        result = timed_continuation(label[method], model, dt, n, STRAIN[method], ROOT / f"n{n}" / f"measure_{method}")
        if result is not None:
            cost[method, n] = result
    ratios = [
        f"{method} / default = {cost[method, BASE_N] / cost['default', BASE_N]:.1f}x"
        for method in ("implicit", "jacobi", "dilu_tol1e-5", "explicit", "stock")
        if (method, BASE_N) in cost and ("default", BASE_N) in cost
    ]
    print(f"\nat N = {BASE_N}: {', '.join(ratios)}; target: <= 0.012 core-s per particle per unit strain")
    for n in SIZES:
        if n > BASE_N and ("default", n) in cost and ("default", BASE_N) in cost:
            print(
                f"default engine, N = {n} / N = {BASE_N}: {cost['default', n] / cost['default', BASE_N]:.2f}"
                + (" (target <= 1.3)" if n == 4000 else "")
            )


def alternate(sizes=(500, 1000), repeats: int = 3) -> None:
    """The two preconditioners of the default engine timed back to back, alternating, `repeats`
    times per N: separate runs of `measure` on this machine differ by 10-30%, more than the
    difference sought."""
    print_head("default engine, block Jacobi and dilu alternating")
    for n in sizes:
        for repeat in range(repeats):
            for preconditioner in ("jacobi", "dilu"):
                timed_continuation(
                    f"default engine, {preconditioner} (run {repeat + 1})",
                    ForceModel(preconditioner=preconditioner),
                    ShearSettings().dt,
                    n,
                    STRAIN["default"],
                    ROOT / f"n{n}" / f"alternate_{preconditioner}",
                )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("phase", choices=("prepare", "measure", "ladder", "alternate", "work"))
    parser.add_argument("--kn", type=float, default=REFERENCE_KN, help="ladder: normal contact stiffness")
    args = parser.parse_args(argv)
    phases = {"prepare": prepare, "measure": measure, "ladder": lambda: ladder(args.kn), "alternate": alternate}
    phases["work"] = solve_work
    phases[args.phase]()


if __name__ == "__main__":
    main()
